// Decoder library (capz_decode): builds without PCL and without the transform encoders.
// .bin folders, KITTI's or nuScenes' (io/bin_folder.h): read frame file by frame file, written by
// capz.
#include "io/bin_folder.h"

#include <cmath>
#include <cstdio>
#include <cstring>
#include <filesystem>
#include <limits>
#include <memory>

#include "capz/error.h"
#include "capz/stream.h"
#include "core/atomic_file.h"
#include "core/input_file.h"
#include "io/frame_files.h"

namespace fs = std::filesystem;

namespace capz {

namespace {

float le_float(const uint8_t* p) {
  const uint32_t u = static_cast<uint32_t>(p[0]) | static_cast<uint32_t>(p[1]) << 8 |
                     static_cast<uint32_t>(p[2]) << 16 | static_cast<uint32_t>(p[3]) << 24;
  float f;
  std::memcpy(&f, &u, 4);
  return f;
}

void put_le_float(float f, uint8_t* p) {
  uint32_t u;
  std::memcpy(&u, &f, 4);
  for (int k = 0; k < 4; ++k) p[k] = static_cast<uint8_t>(u >> (8 * k));
}

// The record of `fields` values after x y z: nuScenes' (2, a NAME.pcd.bin's), else KITTI's.
std::vector<std::string> record_of(size_t fields) {
  return bin_record_fields(fields == 2 ? std::vector<std::string>{"x.pcd.bin"}
                                       : std::vector<std::string>());
}

// The point count of a .bin frame of `fields` values after x y z a point from its size. Throws
// Error(kCorrupt) naming the file when the size is not a whole number of points.
size_t bin_points(const std::string& path, uint64_t size, size_t fields) {
  const size_t point = 4 * (3 + fields);
  if (size % point != 0)
    fail(ErrorCode::kCorrupt, path,
         ".bin frame truncated mid-point: " + std::to_string(size) +
             " bytes is not a multiple of " + std::to_string(point) + " (float32 " +
             bin_record_text(record_of(fields)) + " a point" +
             (fields == 1 ? "; nuScenes' x y z intensity ring frames are read as such when "
                            "named *.pcd.bin)"
                          : ")"));
  return static_cast<size_t>(size / point);
}

class BinSource : public FileFrameSource {
 public:
  explicit BinSource(const std::string& path) : FileFrameSource(list_frame_files(path, ".bin")) {
    const std::vector<std::string> record = bin_record_fields(files_.names);
    if (record.empty())
      fail(ErrorCode::kNotOurFormat, path,
           "some .bin frames are named *.pcd.bin (nuScenes: x y z intensity ring) and some are "
           "not (KITTI: x y z intensity): one folder holds one kind");
    fields_ = record.size();
    std::vector<size_t> counts;
    for (size_t f = 0; f < files_.names.size(); ++f) {
      std::error_code ec;
      const std::string p = files_.path(f);
      const uint64_t size = fs::file_size(p, ec);
      if (ec) fail(ErrorCode::kIo, p, "cannot read: " + ec.message());
      counts.push_back(bin_points(p, size, fields_));
    }
    set_counts(counts);
    header_.source = path;
    header_.format = Format::kBinFolder;
    header_.units = "m";
    header_.units_assumed = true;
    auto extra = std::make_shared<BinExtra>();
    extra->frame_names = files_.names;
    header_.bin = std::move(extra);
    for (const std::string& name : record) {
      PointAttribute a;
      a.name = name;
      a.type = 'F';
      a.size = 4;
      header_.attributes.push_back(a);
    }
  }

 protected:
  void read_frame(size_t f, FrameData* out) override {
    const std::string p = files_.path(f);
    InputFile in(p);
    bytes_.resize(bin_points(p, in.size(), fields_) * 4 * (3 + fields_));
    in.read_at(0, bytes_.data(), bytes_.size());
    read_bin_frame(bytes_.data(), bytes_.size(), p, out, fields_);
  }

 private:
  std::vector<uint8_t> bytes_;
  size_t fields_ = 1;  // float32 values a point after x y z
};

// A field's value as a double (little-endian bytes of type / size).
double field_value(const uint8_t* p, char type, int size) {
  uint64_t u = 0;
  for (int k = 0; k < size; ++k) u |= static_cast<uint64_t>(p[k]) << (8 * k);
  if (type == 'F') {
    if (size == 4) {
      float f;
      const uint32_t w = static_cast<uint32_t>(u);
      std::memcpy(&f, &w, 4);
      return f;
    }
    double d;
    std::memcpy(&d, &u, 8);
    return d;
  }
  if (type == 'U') return static_cast<double>(u);
  const int shift = 64 - 8 * size;  // sign-extend
  return static_cast<double>(static_cast<int64_t>(u << shift) >> shift);
}

}  // namespace

void read_bin_frame(const uint8_t* bytes, size_t size, const std::string& name, FrameData* out,
                    size_t fields) {
  const size_t n = bin_points(name, size, fields), point = 4 * (3 + fields);
  out->points = n;
  out->xyz.assign(n * 3, 0.0);
  out->valid.assign(n, 0);
  out->attrs.assign(fields, std::vector<uint8_t>(n * 4));
  for (size_t i = 0; i < n; ++i) {
    const uint8_t* q = bytes + i * point;
    double v[3];
    for (int a = 0; a < 3; ++a) v[a] = le_float(q + 4 * a);
    if (std::isfinite(v[0]) && std::isfinite(v[1]) && std::isfinite(v[2])) {
      std::memcpy(out->xyz.data() + 3 * i, v, sizeof v);
      out->valid[i] = 1;
    }
    for (size_t k = 0; k < fields; ++k)
      std::memcpy(out->attrs[k].data() + 4 * i, q + 12 + 4 * k, 4);
  }
}

std::vector<uint8_t> bin_frame_bytes(size_t n, const double* xyz, const uint8_t* valid,
                                     const std::vector<const float*>& fields) {
  const size_t point = 4 * (3 + fields.size());
  std::vector<uint8_t> out(n * point);
  const float nan = std::numeric_limits<float>::quiet_NaN();
  for (size_t i = 0; i < n; ++i) {
    uint8_t* q = out.data() + i * point;
    for (int a = 0; a < 3; ++a)
      put_le_float(valid[i] ? static_cast<float>(xyz[3 * i + a]) : nan, q + 4 * a);
    for (size_t k = 0; k < fields.size(); ++k)
      put_le_float(fields[k] ? fields[k][i] : 0.0f, q + 12 + 4 * k);
  }
  return out;
}

std::vector<float> bin_values(const PointAttribute& a, const uint8_t* bytes, size_t n) {
  std::vector<float> v(n);
  const size_t s = static_cast<size_t>(a.size);
  for (size_t i = 0; i < n; ++i) {
    const uint8_t* p = bytes + i * s;
    if (a.type == 'F' && a.size == 4)
      std::memcpy(&v[i], p, 4);  // bit for bit (NaN payloads kept)
    else
      v[i] = static_cast<float>(field_value(p, a.type, a.size));
  }
  return v;
}

Take read_bin_folder(const std::string& path) {
  BinSource source(path);
  return read_all_frames(source);
}

std::unique_ptr<FrameSource> open_bin_frames(const std::string& path) {
  return std::unique_ptr<FrameSource>(new BinSource(path));
}

std::vector<std::string> bin_output_record(const Take& take, const std::string& path) {
  if (take.bin) return bin_record_of(take);
  if (single_frame_output(path, ".bin"))
    return bin_record_or_kitti({fs::path(without_trailing_slashes(path)).filename().string()});
  return bin_record_or_kitti(frame_output_names(take, ".bin"));
}

std::vector<BinRecordSource> bin_record_sources(const Take& take,
                                                const std::vector<std::string>& record) {
  std::vector<BinRecordSource> out;
  for (const std::string& name : record) {
    BinRecordSource s;
    for (size_t k = 0; k < take.attributes.size() && s.k == SIZE_MAX; ++k)
      if (take.attributes[k].name == name && take.attributes[k].count == 1) {
        s.k = k;
        s.layout.type = take.attributes[k].type;
        s.layout.size = take.attributes[k].size;
      }
    out.push_back(s);
  }
  return out;
}

std::vector<uint8_t> bin_record_frame(const std::vector<BinRecordSource>& record, size_t n,
                                      const double* xyz, const uint8_t* valid,
                                      const std::vector<const uint8_t*>& attrs) {
  std::vector<std::vector<float>> values(record.size());
  std::vector<const float*> fields(record.size(), nullptr);
  for (size_t r = 0; r < record.size(); ++r)
    if (record[r].k < attrs.size()) {
      values[r] = bin_values(record[r].layout, attrs[record[r].k], n);
      fields[r] = values[r].data();
    }
  return bin_frame_bytes(n, xyz, valid, fields);
}

namespace {

// The frame's record (bin_output_record) from the take's fields (bin_record_sources).
FrameFileBytes bin_file_writer(const Take& take, const std::string& path) {
  std::vector<BinRecordSource> record = bin_record_sources(take, bin_output_record(take, path));
  return [record](const FrameView& v) {
    return bin_record_frame(record, v.points, v.xyz, v.valid, v.attrs);
  };
}

}  // namespace

void write_bin_folder(const Take& take, const std::string& path, const WriteOptions& opts) {
  write_frame_files(take, path, ".bin", opts.overwrite, bin_file_writer(take, path));
}

std::unique_ptr<FrameSink> bin_folder_sink(const Take& header, const std::string& path,
                                           const WriteOptions& opts) {
  return frame_folder_sink(
      header, path, ".bin", opts.overwrite, false,
      [header, path](std::optional<bool>) { return bin_file_writer(header, path); });
}

}  // namespace capz
