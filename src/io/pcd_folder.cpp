// Decoder library (capz_decode): builds without PCL and without the transform encoders.
// A folder of PCD frames <-> Take. Read by capz itself when the body is binary or
// binary_compressed under a plain header (io/pcd_native.h), else through PCL's PCDReader, which
// lives in a module loaded on first use (io/pcd_backend.h: the capz binary does not link PCL's
// I/O library); written by
// capz itself (io/pcd_frame_writer.h), since PCL's writer drops padding fields and retypes
// packed colour.
//
// Reading: frames are the *.pcd files of the folder in natural order of their names
// (frame_2 before frame_10); every frame must have the first frame's point count; a point with a
// NaN or infinite coordinate is a gap. PCL trusts the counts in a PCD header and allocates
// (and, for binary bodies, reads) whatever they say, so each file is read whole into memory
// first, its header is parsed (io/pcd_header.h) and checked against the file's size, then PCL is
// given the bytes (readHeader on the header text, readBodyBinary / readBodyASCII on the body).
//
// Writing: one file per frame with the source's fields in its order and types (x y z float32
// when the source's were, else float32 when every coordinate is exactly a float, else float64
// so no precision is lost), organized when the source was, with its VIEWPOINT; gaps are NaN
// points; every other field is written with the bytes the take holds. The DATA encoding is the
// source's unless WriteOptions says otherwise. Files are written into a
// temporary sibling folder renamed into place (AtomicDir).
#include "io/pcd_folder.h"

#include <algorithm>
#include <cctype>
#include <cmath>
#include <cstdio>
#include <cstring>
#include <filesystem>
#include <memory>
#include <sstream>
#include <string>
#include <vector>

#include "capz/error.h"
#include "capz/io.h"
#include "capz/stream.h"
#include "core/atomic_file.h"
#include "core/input_file.h"
#include "io/frame_files.h"
#include "io/pcd_backend.h"
#include "io/pcd_frame_writer.h"
#include "io/pcd_header.h"
#include "io/pcd_native.h"
#include "io/text_number.h"

namespace fs = std::filesystem;

namespace capz {

namespace {

struct FieldRef {
  uint32_t offset = 0;
  pcd::FieldType type = pcd::FieldType::kUnknown;
};

double read_value(const uint8_t* p, pcd::FieldType type) {
  switch (type) {
    case pcd::FieldType::kFloat32: {
      float v;
      std::memcpy(&v, p, 4);
      return v;
    }
    case pcd::FieldType::kFloat64: {
      double v;
      std::memcpy(&v, p, 8);
      return v;
    }
    case pcd::FieldType::kInt8: {
      int8_t v;
      std::memcpy(&v, p, 1);
      return v;
    }
    case pcd::FieldType::kUInt8:
      return p[0];
    case pcd::FieldType::kInt16: {
      int16_t v;
      std::memcpy(&v, p, 2);
      return v;
    }
    case pcd::FieldType::kUInt16: {
      uint16_t v;
      std::memcpy(&v, p, 2);
      return v;
    }
    case pcd::FieldType::kInt32: {
      int32_t v;
      std::memcpy(&v, p, 4);
      return v;
    }
    case pcd::FieldType::kUInt32: {
      uint32_t v;
      std::memcpy(&v, p, 4);
      return v;
    }
    case pcd::FieldType::kInt64: {
      int64_t v;
      std::memcpy(&v, p, 8);
      return static_cast<double>(v);
    }
    case pcd::FieldType::kUInt64: {
      uint64_t v;
      std::memcpy(&v, p, 8);
      return static_cast<double>(v);
    }
    case pcd::FieldType::kUnknown:
      break;
  }
  return std::nan("");
}

// What reading a frame file needs: the file's bytes, its cloud, and a binary_compressed body's
// points as the body lays them out (pcd::read_native's `planar`, not interleaved into the cloud).
// Freed after each frame: kept, they would only add to the encoder's peak (the allocator reuses
// freed blocks anyway).
struct PcdBuffers {
  std::vector<uint8_t> file, planar;
  pcd::Cloud cloud;
  bool is_planar = false;  // the points are in `planar`, not in cloud.data
};

// Reads one PCD file into b's cloud (capz's own reader, else PCL) after checking its header;
// returns the header. With `coordinates`, a binary_compressed body read by capz has only its
// planes through x y z's decompressed (pcd::read_native).
PcdHeader read_one(const std::string& path, PcdBuffers* b, bool coordinates) {
  pcd::Cloud* cloud = &b->cloud;
  b->is_planar = false;
  {
    InputFile in(path);
    b->file.resize(static_cast<size_t>(in.size()));
    if (!b->file.empty()) in.read_at(0, b->file.data(), b->file.size());
  }
  const std::vector<uint8_t>& bytes = b->file;
  if (bytes.empty()) fail(ErrorCode::kCorrupt, path, "empty PCD file (0 bytes)");
  PcdHeader h = parse_header(bytes, path);
  for (const char* axis : {"x", "y", "z"})
    if (std::find(h.fields.begin(), h.fields.end(), axis) == h.fields.end())
      fail(ErrorCode::kCorrupt, path, std::string("PCD file has no '") + axis + "' field");

  if (h.data == "ascii") check_ascii_body(bytes, h, path);
  if (h.points == 0) {  // an empty frame: nothing for PCL to read, the fields from the header
    cloud->width = 0;
    cloud->height = static_cast<uint32_t>(std::min<uint64_t>(h.height, 1));
    cloud->point_step = static_cast<uint32_t>(h.point_step);
    cloud->fields.clear();
    uint64_t offset = 0;
    for (size_t i = 0; i < h.fields.size(); ++i) {
      pcd::Field fd;
      fd.name = h.fields[i];
      fd.offset = static_cast<uint32_t>(offset);
      fd.count = static_cast<uint32_t>(h.counts[i]);
      cloud->fields.push_back(fd);
      offset += static_cast<uint64_t>(h.sizes[i]) * h.counts[i];
    }
    cloud->data.clear();
    return h;
  }

  if (pcd::read_native(bytes, h, cloud, &b->planar, coordinates)) {
    b->is_planar = h.data == "binary_compressed";
    return h;
  }
  std::string msg;
  switch (pcd::backend(path).read(bytes.data(), bytes.size(), h.data_idx, h.points, h.point_step,
                                  cloud, &msg)) {
    case pcd::Status::kOk:
      break;
    case pcd::Status::kHeaderRejected:
      fail(ErrorCode::kCorrupt, path, "PCL rejects the PCD header");
    case pcd::Status::kHeaderDiffers:
      fail(ErrorCode::kCorrupt, path, "PCD header read differently by PCL and capz");
    case pcd::Status::kPclException:
      fail(ErrorCode::kCorrupt, path, "PCL: " + msg);
    case pcd::Status::kOtherException:
      fail(ErrorCode::kCorrupt, path, "PCL cannot parse the body: " + msg);
    default:
      fail(ErrorCode::kCorrupt, path, "PCL cannot read the PCD body (" + h.data + ")");
  }
  if (cloud->data.size() < h.points * h.point_step)
    fail(ErrorCode::kCorrupt, path, "PCD body is shorter than its header says");
  return h;
}

}  // namespace

namespace {

// The layout of one frame: what every frame of a folder must share.
struct FrameLayout {
  size_t points = 0, width = 0, height = 1;
  std::string encoding, version;
  std::vector<double> viewpoint;  // empty: the default 0 0 0 1 0 0 0
  std::vector<PCDField> fields;   // x y z as float (size 4 when the file's are float32, else 8)
  std::vector<uint32_t> offsets;  // each field's offset into a point (PCL's)
};

bool same_fields(const std::vector<PCDField>& a, const std::vector<PCDField>& b) {
  if (a.size() != b.size()) return false;
  for (size_t i = 0; i < a.size(); ++i)
    if (a[i].name != b[i].name || a[i].type != b[i].type || a[i].size != b[i].size ||
        a[i].count != b[i].count)
      return false;
  return true;
}

// The fields of a header as the take keeps them: x y z as float (size 4 when the file's are
// float32, else 8), each once and with COUNT 1.
std::vector<PCDField> fields_of(const PcdHeader& h, const std::string& path) {
  std::vector<PCDField> out;
  int seen[3] = {0, 0, 0};
  for (size_t i = 0; i < h.fields.size(); ++i) {
    PCDField f;
    f.name = h.fields[i];
    f.type = h.types[i];
    f.size = h.sizes[i];
    f.count = static_cast<int>(h.counts[i]);
    const int axis = f.name == "x" ? 0 : f.name == "y" ? 1 : f.name == "z" ? 2 : -1;
    if (axis >= 0) {
      if (++seen[axis] > 1 || f.count != 1)
        fail(ErrorCode::kCorrupt, path, "PCD field " + f.name + " twice or with a COUNT above 1");
      // Coordinates are kept as float32 when the file's are, else as float64.
      f.size = f.type == 'F' && f.size == 4 ? 4 : 8;
      f.type = 'F';
    }
    out.push_back(f);
  }
  for (int a = 0; a < 3; ++a)
    if (!seen[a])
      fail(ErrorCode::kCorrupt, path, std::string("PCD file has no '") + "xyz"[a] + "' field");
  if (out.size() > 1024) fail(ErrorCode::kCorrupt, path, "PCD frames with more than 1024 fields");
  return out;
}

FrameLayout layout_of(const PcdHeader& h, const pcd::Cloud& cloud, const std::string& path) {
  FrameLayout l;
  l.points = static_cast<size_t>(cloud.width) * cloud.height;
  l.width = cloud.width;
  l.height = cloud.height;
  l.encoding = h.data;
  l.version = h.version.empty() ? "0.7" : h.version;
  static const double kDefault[7] = {0, 0, 0, 1, 0, 0, 0};
  if (h.viewpoint.size() == 7 && !std::equal(h.viewpoint.begin(), h.viewpoint.end(), kDefault))
    l.viewpoint = h.viewpoint;
  if (cloud.fields.size() != h.fields.size())
    fail(ErrorCode::kCorrupt, path, "PCD fields read differently by PCL and capz");
  l.fields = fields_of(h, path);
  for (size_t i = 0; i < h.fields.size(); ++i) l.offsets.push_back(cloud.fields[i].offset);
  return l;
}

// A frame file's header, checked against the file's size (the points it announces fit).
PcdHeader head_of(const std::string& path) {
  std::vector<uint8_t> head = read_header_bytes(path, "\nDATA");
  if (head.empty()) fail(ErrorCode::kCorrupt, path, "empty PCD file (0 bytes)");
  const PcdHeader h = parse_header_text(head, path);
  std::error_code ec;
  const uint64_t size = fs::file_size(path, ec);
  if (ec) fail(ErrorCode::kIo, path, "cannot read: " + ec.message());
  if (head.size() < h.data_idx + 8 && size > head.size())  // a compressed body's sizes
    head = read_file_head(path, h.data_idx + 8);
  check_body_fits(head, size, h, path);
  return h;
}

// The coordinates of the n points at[a] + p x stride[a] (a = 0, 1, 2) into data's xyz and valid,
// each value read by value(pointer): a point with a coordinate that is not finite is a gap
// (0 0 0).
template <class Value>
void coordinates_of(const uint8_t* const at[3], const size_t stride[3], size_t n, Value value,
                    FrameData* data) {
  double* xyz = data->xyz.data();
  uint8_t* valid = data->valid.data();
  for (size_t p = 0; p < n; ++p) {
    double v[3];
    for (int a = 0; a < 3; ++a) v[a] = value(a, at[a] + p * stride[a]);
    const bool ok = std::isfinite(v[0]) && std::isfinite(v[1]) && std::isfinite(v[2]);
    for (int a = 0; a < 3; ++a) xyz[3 * p + size_t(a)] = ok ? v[a] : 0.0;
    valid[p] = ok ? 1 : 0;
  }
}

// The same, each coordinate of its field's PCD type (ref): float32 and float64 read without a
// switch a value.
void coordinates_by_type(const uint8_t* const at[3], const size_t stride[3], size_t n,
                         const FieldRef ref[3], FrameData* data) {
  const auto all = [&](pcd::FieldType type) {
    return ref[0].type == type && ref[1].type == type && ref[2].type == type;
  };
  const auto typed = [](auto zero) {
    return [](int, const uint8_t* p) {
      decltype(zero) v;
      std::memcpy(&v, p, sizeof v);
      return static_cast<double>(v);
    };
  };
  if (all(pcd::FieldType::kFloat32))
    coordinates_of(at, stride, n, typed(0.0f), data);
  else if (all(pcd::FieldType::kFloat64))
    coordinates_of(at, stride, n, typed(0.0), data);
  else
    coordinates_of(
        at, stride, n, [&](int a, const uint8_t* p) { return read_value(p, ref[a].type); }, data);
}

// Reads frame file `path` into *data (xyz n x 3, valid n, one byte array per field other than
// x y z: n x count x size, as the file holds them; data's arrays reused) and *l, through b.
// With `coordinates`, data's field arrays are left empty (their layout still checked).
void read_pcd_frame(const std::string& path, FrameLayout* l, FrameData* data, PcdBuffers* b,
                    bool coordinates = false) {
  const PcdHeader h = read_one(path, b, coordinates);
  const pcd::Cloud& cloud = b->cloud;
  *l = layout_of(h, cloud, path);
  const size_t n = l->points;
  // Field i's value of point p: at base(i) + p x stride(i), in the points or in the planes.
  const uint8_t* points = b->is_planar ? b->planar.data() : cloud.data.data();
  const auto base = [&](uint32_t offset) {
    if (n == 0) return points;  // may be null: no offset from it
    return points + (b->is_planar ? n * size_t{offset} : size_t{offset});
  };
  FieldRef ref[3];
  const uint8_t* at[3];
  size_t stride[3];
  const char* axes[3] = {"x", "y", "z"};
  for (int a = 0; a < 3; ++a) {
    auto it = std::find_if(cloud.fields.begin(), cloud.fields.end(),
                           [&](const pcd::Field& fd) { return fd.name == axes[a]; });
    ref[a].offset = it->offset;
    ref[a].type = it->type;
    at[a] = base(it->offset);
    const auto i = static_cast<size_t>(it - cloud.fields.begin());  // h's field i too
    stride[a] = b->is_planar ? static_cast<size_t>(h.sizes[i]) * h.counts[i] : cloud.point_step;
  }
  data->points = n;
  data->xyz.resize(n * 3);
  data->valid.resize(n);
  coordinates_by_type(at, stride, n, ref, data);
  size_t k = 0;
  for (size_t i = 0; i < l->fields.size(); ++i) {
    const PCDField& fd = l->fields[i];
    if (fd.name == "x" || fd.name == "y" || fd.name == "z") continue;
    const size_t bpp = static_cast<size_t>(fd.size) * static_cast<size_t>(fd.count);
    if (static_cast<uint64_t>(l->offsets[i]) + bpp > cloud.point_step)
      fail(ErrorCode::kCorrupt, path, "PCD field " + fd.name + " lies outside its point");
    if (coordinates) continue;
    if (data->attrs.size() <= k) data->attrs.resize(k + 1);
    std::vector<uint8_t>& bytes = data->attrs[k++];
    const uint8_t* src = base(l->offsets[i]);
    if (b->is_planar) {
      bytes.assign(src, src + n * bpp);  // not zeroed first
    } else {
      bytes.resize(n * bpp);
      for (size_t p = 0; p < n; ++p)
        std::memcpy(bytes.data() + p * bpp, src + p * cloud.point_step, bpp);
    }
  }
  data->attrs.resize(k);
}

// The take's PCD metadata and attribute layouts (no values) from the first frame's layout.
void set_layout(const FrameLayout& l, const std::vector<std::string>& names, Take* t) {
  auto extra = std::make_shared<PCDExtra>();
  extra->frame_names = names;
  extra->encoding = l.encoding;
  extra->version = l.version;
  extra->fields = l.fields;
  extra->width = t->ragged() ? 0 : l.width;
  extra->height = t->ragged() ? 1 : l.height;
  extra->viewpoint = l.viewpoint;
  t->pcd = std::move(extra);
  t->attributes.clear();
  for (const PCDField& fd : l.fields) {
    if (fd.name == "x" || fd.name == "y" || fd.name == "z") continue;
    t->attributes.push_back(attribute_of(fd));
  }
}

// A PCD folder (or one .pcd file) read frame file by frame file. Opening reads every file's
// header (its first bytes): the point counts, which make the take fixed or ragged, and the
// fields, which every frame must share; then the first frame whole (the layout PCL reads). A
// range reads its files only.
class PCDSource : public FileFrameSource {
  static constexpr size_t kKeptPoints = size_t{1} << 20;

 public:
  explicit PCDSource(const std::string& path) : FileFrameSource(list_frame_files(path, ".pcd")) {
    std::vector<size_t> counts;
    std::vector<PCDField> fields0;
    for (size_t f = 0; f < files_.names.size(); ++f) {
      const std::string p = files_.path(f);
      const PcdHeader h = head_of(p);
      const std::vector<PCDField> fields = fields_of(h, p);
      if (f == 0) fields0 = fields;
      if (!same_fields(fields, fields0))
        fail(ErrorCode::kCorrupt, p,
             "frame has other fields than the first frame (" + files_.names[0] + ")");
      if (h.height > 1) organized_ = p;
      counts.push_back(static_cast<size_t>(h.points));
    }
    set_counts(counts);
    if (header_.ragged() && !organized_.empty())
      fail(ErrorCode::kCorrupt, organized_,
           "an organized frame (HEIGHT above 1) in a folder whose frames' point counts differ");
    header_.source = path;
    header_.format = Format::kPCDFolder;
    header_.units = "m";
    header_.units_assumed = true;
    // Read whole once: its layout as PCL reads it. Kept for the first read of frame 0 (of a
    // single file: for every read).
    PcdBuffers b;
    read_pcd_frame(files_.path(0), &layout_, &first_, &b);
    have_first_ = true;
    set_layout(layout_, files_.names, &header_);
  }

 protected:
  void read_frame(size_t f, FrameData* out) override { read_file(f, out, false); }
  void read_frame_coordinates(size_t f, FrameData* out) override { read_file(f, out, true); }

 private:
  // Frame f into *out (with `coordinates`, maybe without its fields: read_pcd_frame).
  void read_file(size_t f, FrameData* out, bool coordinates) {
    // A one-file source's every read (the one-frame choice reads its frame three times,
    // compress.cpp), but for a binary cloud of more than kKeptPoints points: read again from the
    // file after the first read, so the encoder's copies are not joined by this one while it
    // codes (an ascii body is kept: reading it again would cost more than coding it).
    if (have_first_ && f == 0 && files_.names.size() == 1 &&
        (first_.points <= kKeptPoints || layout_.encoding == "ascii")) {
      *out = first_;
      return;
    }
    if (have_first_ && f == 0) {  // frame 0 read when opening: not read twice (kept until then:
      have_first_ = false;        // the encoder's first pass reads it last, compress_ragged)
      *out = std::move(first_);
      first_ = FrameData();
      return;
    }
    const std::string p = files_.path(f);
    FrameLayout l;
    PcdBuffers b;
    read_pcd_frame(p, &l, out, &b, coordinates);
    if (!same_fields(l.fields, layout_.fields) ||
        (!header_.ragged() && (l.width != layout_.width || l.height != layout_.height)))
      fail(ErrorCode::kCorrupt, p,
           "frame has other fields or another WIDTH x HEIGHT than the first frame (" +
               files_.names[0] + ")");
  }

 private:
  FrameLayout layout_;
  FrameData first_;  // frame 0 as the constructor read it, until the first read_frame (one file:
                     // kept)
  bool have_first_ = false;
  std::string organized_;  // a frame file with HEIGHT above 1, if any
};

}  // namespace

Take read_pcd_folder(const std::string& dir) {
  PCDSource source(dir);
  return read_all_frames(source);
}

std::unique_ptr<FrameSource> open_pcd_frames(const std::string& dir) {
  return std::unique_ptr<FrameSource>(new PCDSource(dir));
}

std::vector<std::string> list_pcd_frames(const std::string& dir) {
  return list_frame_files(dir, ".pcd").names;
}

std::vector<std::string> pcd_output_names(const Take& take) {
  return frame_output_names(take, ".pcd");
}

void check_replaceable_pcd_dir(const std::string& dir, bool overwrite) {
  check_replaceable_frame_dir(dir, ".pcd", overwrite);
}

namespace {

// The PCD encoding written: the option's, else the source's, else binary.
std::string pcd_encoding(const Take& take, const WriteOptions& opts, const std::string& dir) {
  const std::string enc = !opts.pcd_encoding.empty()                ? opts.pcd_encoding
                          : take.pcd && !take.pcd->encoding.empty() ? take.pcd->encoding
                                                                    : "binary";
  if (enc != "ascii" && enc != "binary" && enc != "binary_compressed")
    fail(ErrorCode::kInvalidParameter, dir,
         "unknown PCD encoding '" + enc + "' (ascii, binary or binary_compressed)");
  return enc;
}

}  // namespace

FrameFileBytes pcd_file_writer(const Take& take, const std::string& enc, const std::string& dir,
                               std::optional<bool> xyz_float) {
  return [plan = pcd_frame_plan(take, enc, xyz_float), points = std::vector<uint8_t>(),
          body = std::vector<uint8_t>(), ragged = take.ragged(),
          dir](const FrameView& v) mutable {  // the buffers kept from frame to frame
    if (v.points > (size_t{1} << 31))
      fail(ErrorCode::kUsage, dir, "too many points for a PCD file");
    if (ragged) plan.layout.width = v.points, plan.layout.height = 1;
    return pcd_frame_file(plan, v.points, v.xyz, v.valid, v.attrs, &points, &body);
  };
}

void write_pcd_folder(const Take& take, const std::string& dir, const WriteOptions& opts) {
  const std::string enc = pcd_encoding(take, opts, dir);
  write_frame_files(take, dir, ".pcd", opts.overwrite,
                    pcd_file_writer(take, enc, dir, std::nullopt));
}

std::unique_ptr<FrameSink> pcd_folder_sink(const Take& header, const std::string& dir,
                                           const WriteOptions& opts) {
  const std::string enc = pcd_encoding(header, opts, dir);
  return frame_folder_sink(header, dir, ".pcd", opts.overwrite,
                           pcd_frame_plan(header, enc).xyz_from_data,
                           [header, enc, dir](std::optional<bool> xyz_float) {
                             return pcd_file_writer(header, enc, dir, xyz_float);
                           });
}

}  // namespace capz
