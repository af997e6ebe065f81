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

// v written at p as a little-endian value of type / size: rounded to an integer type's nearest
// value and clamped to its range (NaN as 0).
void put_field_value(double v, char type, int size, uint8_t* p) {
  uint64_t u = 0;
  if (type == 'F' && size == 4) {
    const float f = static_cast<float>(v);
    uint32_t w;
    std::memcpy(&w, &f, 4);
    u = w;
  } else if (type == 'F') {
    std::memcpy(&u, &v, 8);
  } else {
    const int bits = 8 * size;
    const double lo = type == 'U' ? 0.0 : -std::ldexp(1.0, bits - 1);
    const double hi = type == 'U' ? std::ldexp(1.0, bits) : std::ldexp(1.0, bits - 1);
    const double r = std::isnan(v) ? 0.0 : std::nearbyint(v);
    if (r >= hi)  // the largest value (2^bits - 1 does not round-trip a double for 64 bits)
      u = type == 'U' ? ~uint64_t{0} : (uint64_t{1} << (bits - 1)) - 1;
    else if (r < lo)
      u = type == 'U' ? 0 : uint64_t{1} << (bits - 1);
    else
      u = type == 'U' ? static_cast<uint64_t>(r) : static_cast<uint64_t>(static_cast<int64_t>(r));
  }
  for (int k = 0; k < size; ++k) p[k] = static_cast<uint8_t>(u >> (8 * k));
}

// The point count of a .bin frame of `record` from its size. Throws Error(kCorrupt) naming the
// file when the size is not a whole number of points.
size_t bin_points(const std::string& path, uint64_t size, const std::vector<PCDField>& record) {
  const size_t point = bin_point_bytes(record);
  if (size % point != 0)
    fail(ErrorCode::kCorrupt, path,
         ".bin frame truncated mid-point: " + std::to_string(size) +
             " bytes is not a multiple of " + std::to_string(point) + " (" +
             (bin_record_float32(record) ? "float32 " : "") + bin_record_text(record) +
             " a point; --bin-fields gives another record)");
  return static_cast<size_t>(size / point);
}

class BinSource : public FileFrameSource {
 public:
  BinSource(const std::string& path, const std::vector<PCDField>* declared)
      : FileFrameSource(list_frame_files(path, ".bin")) {
    record_ = declared ? *declared : bin_record_fields(files_.names);
    if (!declared && record_.empty())
      fail(ErrorCode::kNotOurFormat, path,
           "some .bin frames are named *.pcd.bin (nuScenes: x y z intensity ring) and some are "
           "not (KITTI: x y z intensity): one folder holds one kind, or --bin-fields gives the "
           "record");
    std::vector<size_t> counts;
    for (size_t f = 0; f < files_.names.size(); ++f) {
      std::error_code ec;
      const std::string p = files_.path(f);
      const uint64_t size = fs::file_size(p, ec);
      if (ec) fail(ErrorCode::kIo, p, "cannot read: " + ec.message());
      counts.push_back(bin_points(p, size, record_));
    }
    set_counts(counts);
    header_.source = path;
    header_.format = Format::kBinFolder;
    header_.units = "m";
    header_.units_assumed = true;
    auto extra = std::make_shared<BinExtra>();
    extra->frame_names = files_.names;
    if (declared && !same_bin_records(*declared, bin_record_fields(files_.names))) {
      extra->declared = true;  // else the names' record: the stream as without --bin-fields
      extra->record = *declared;
    }
    header_.bin = std::move(extra);
    for (const PCDField& f : record_) header_.attributes.push_back(attribute_of(f));
    if (!declared) check_names_record();
  }

 protected:
  void read_frame(size_t f, FrameData* out) override {
    const std::string p = files_.path(f);
    InputFile in(p);
    bytes_.resize(bin_points(p, in.size(), record_) * bin_point_bytes(record_));
    in.read_at(0, bytes_.data(), bytes_.size());
    read_bin_frame(bytes_.data(), bytes_.size(), p, out, record_);
  }

 private:
  // A names' record (KITTI's, nuScenes') is a guess: frames of another record whose size happens
  // to be a whole number of its points read as garbage. The first frame with points is looked
  // at, and a warning (info, convert, compress) names --bin-fields when more than 1 % of its valid
  // points have an intensity below 0 or not finite, or a coordinate beyond 10^6 m: neither
  // happens in a real sweep, and both do in another record read with the wrong stride.
  void check_names_record() {
    size_t f = 0;
    while (f < counts_.size() && counts_[f] == 0) ++f;
    if (f == counts_.size()) return;
    FrameData d;
    read_frame(f, &d);
    size_t odd = 0, valid = 0;  // of the valid points (a gap's intensity may be anything)
    for (size_t i = 0; i < d.points; ++i) {
      if (!d.valid[i]) continue;
      ++valid;
      const float v = le_float(d.attrs[0].data() + 4 * i);  // "intensity", float32
      bool far = false;
      for (int a = 0; a < 3 && !far; ++a) far = std::fabs(d.xyz[3 * i + a]) > 1e6;
      if (!(v >= 0) || !std::isfinite(v) || far) ++odd;
    }
    if (odd * 100 <= valid || odd < 4) return;
    char share[32];
    std::snprintf(share, sizeof share, "%.1f%%",
                  100.0 * static_cast<double>(odd) / static_cast<double>(valid));
    header_.warnings.push_back(
        files_.names[f] + ": " + share +
        " of its valid points have an intensity below 0 or not a " +
        "number, or a coordinate beyond 10^6 m, as in frames of another record read as " +
        bin_record_text(record_) + " (float32): if they hold another, --bin-fields gives it " +
        "(\"x y z intensity ring:U2 t:F8\")");
  }

  std::vector<uint8_t> bytes_;
  std::vector<PCDField> record_;  // the fields after x y z
};

}  // namespace

size_t bin_point_bytes(const std::vector<PCDField>& record) {
  size_t point = 12;
  for (const PCDField& f : record) point += static_cast<size_t>(f.size);
  return point;
}

void read_bin_frame(const uint8_t* bytes, size_t size, const std::string& name, FrameData* out,
                    const std::vector<PCDField>& record) {
  const size_t n = bin_points(name, size, record), point = bin_point_bytes(record);
  out->points = n;
  out->xyz.assign(n * 3, 0.0);
  out->valid.assign(n, 0);
  out->attrs.resize(record.size());
  for (size_t k = 0; k < record.size(); ++k)
    out->attrs[k].assign(n * static_cast<size_t>(record[k].size), 0);
  for (size_t i = 0; i < n; ++i) {
    const uint8_t* q = bytes + i * point;
    double v[3];
    for (int a = 0; a < 3; ++a) v[a] = le_float(q + 4 * a);
    if (std::isfinite(v[0]) && std::isfinite(v[1]) && std::isfinite(v[2])) {
      std::memcpy(out->xyz.data() + 3 * i, v, sizeof v);
      out->valid[i] = 1;
    }
    size_t at = 12;
    for (size_t k = 0; k < record.size(); ++k) {
      const size_t s = static_cast<size_t>(record[k].size);
      std::memcpy(out->attrs[k].data() + s * i, q + at, s);
      at += s;
    }
  }
}

Take read_bin_folder(const std::string& path) {
  BinSource source(path, nullptr);
  return read_all_frames(source);
}

std::unique_ptr<FrameSource> open_bin_frames(const std::string& path) {
  return std::unique_ptr<FrameSource>(new BinSource(path, nullptr));
}

std::unique_ptr<FrameSource> open_bin_frames(const std::string& path,
                                             const std::vector<PCDField>* record) {
  return std::unique_ptr<FrameSource>(new BinSource(path, record));
}

std::vector<PCDField> bin_output_record(const Take& take, const std::string& path) {
  if (take.bin) return bin_record_of(take);
  if (single_frame_output(path, ".bin"))
    return bin_record_or_kitti({fs::path(without_trailing_slashes(path)).filename().string()});
  return bin_record_or_kitti(frame_output_names(take, ".bin"));
}

std::vector<BinRecordSource> bin_record_sources(const Take& take,
                                                const std::vector<PCDField>& record) {
  std::vector<BinRecordSource> out;
  std::vector<bool> taken(take.attributes.size(), false);  // "_" fields in their order
  for (const PCDField& f : record) {
    BinRecordSource s;
    s.field = f;
    for (size_t k = 0; k < take.attributes.size() && s.k == SIZE_MAX; ++k)
      if (!taken[k] && take.attributes[k].name == f.name && take.attributes[k].count == 1) {
        s.k = k;
        taken[k] = true;
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
  size_t point = 12;
  for (const BinRecordSource& r : record) point += static_cast<size_t>(r.field.size);
  std::vector<uint8_t> out(n * point);
  const float nan = std::numeric_limits<float>::quiet_NaN();
  for (size_t i = 0; i < n; ++i) {
    uint8_t* q = out.data() + i * point;
    for (int a = 0; a < 3; ++a)
      put_le_float(valid[i] ? static_cast<float>(xyz[3 * i + a]) : nan, q + 4 * a);
    q += 12;
    for (const BinRecordSource& r : record) {
      const size_t s = static_cast<size_t>(r.field.size);
      if (r.k < attrs.size()) {
        const uint8_t* v = attrs[r.k] + i * static_cast<size_t>(r.layout.size);
        if (r.layout.type == r.field.type && r.layout.size == r.field.size)
          std::memcpy(q, v, s);  // bit for bit (NaN payloads kept)
        else
          put_field_value(field_value(v, r.layout.type, r.layout.size), r.field.type, r.field.size,
                          q);
      }  // else 0 (out is zeroed)
      q += s;
    }
  }
  return out;
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
