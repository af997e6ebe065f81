// Decoder library (capz_decode): builds without PCL and without the transform encoders.
// A folder of PCD frames <-> Take. Read through PCL's PCDReader, which lives in a module loaded
// on first use (io/pcd_backend.h: the capz binary does not link PCL's I/O library); written by
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
#include <set>
#include <sstream>
#include <string>
#include <vector>

#include "capz/error.h"
#include "capz/io.h"
#include "capz/stream.h"
#include "core/atomic_file.h"
#include "io/natural_sort.h"
#include "io/pcd_backend.h"
#include "io/pcd_frame_writer.h"
#include "io/pcd_header.h"
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

// Reads one PCD file into a cloud (through PCL) after checking its header; returns the DATA
// encoding.
PcdHeader read_one(const std::string& path, pcd::Cloud* cloud) {
  std::vector<uint8_t> bytes = read_file(path);
  if (bytes.empty()) fail(ErrorCode::kCorrupt, path, "empty PCD file (0 bytes)");
  PcdHeader h = parse_header(bytes, path);
  for (const char* axis : {"x", "y", "z"})
    if (std::find(h.fields.begin(), h.fields.end(), axis) == h.fields.end())
      fail(ErrorCode::kCorrupt, path, std::string("PCD file has no '") + axis + "' field");

  if (h.data == "ascii") check_ascii_body(bytes, h, path);

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

bool has_pcd_extension(const fs::path& p) {
  std::string ext = p.extension().string();
  for (auto& c : ext) c = static_cast<char>(std::tolower(static_cast<unsigned char>(c)));
  return ext == ".pcd";
}

}  // namespace

namespace {

// The .pcd files of a folder in natural-sort order (the frames).
std::vector<std::string> list_frames(const std::string& dir) {
  std::error_code ec;
  if (!fs::is_directory(dir, ec)) fail(ErrorCode::kUsage, dir, "not a directory");
  std::vector<std::string> names;
  for (fs::directory_iterator it(dir, ec), end; !ec && it != end; it.increment(ec)) {
    std::error_code ec2;
    if (has_pcd_extension(it->path()) && fs::is_regular_file(it->path(), ec2))
      names.push_back(it->path().filename().string());
  }
  if (ec) fail(ErrorCode::kIo, dir, "cannot list directory: " + ec.message());
  if (names.empty()) fail(ErrorCode::kNotOurFormat, dir, "no .pcd files in directory");
  std::sort(names.begin(), names.end(), natural_less);
  return names;
}

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
    l.fields.push_back(f);
    l.offsets.push_back(cloud.fields[i].offset);
  }
  if (l.fields.size() > 1024)
    fail(ErrorCode::kCorrupt, path, "PCD frames with more than 1024 fields");
  return l;
}

// Reads frame `f` (file `names[f]`) into xyz (n x 3), valid (n) and one byte array per field
// other than x y z (n x count x size, as the file holds them). The first frame sets *layout;
// every other frame must have the same points, fields and organization.
void read_frame(const std::string& dir, const std::vector<std::string>& names, size_t f,
                FrameLayout* layout, std::vector<double>* xyz, std::vector<uint8_t>* valid,
                std::vector<std::vector<uint8_t>>* attrs) {
  const std::string path = (fs::path(dir) / names[f]).string();
  pcd::Cloud cloud;
  const PcdHeader h = read_one(path, &cloud);
  FrameLayout l = layout_of(h, cloud, path);
  const size_t n = l.points;
  if (f == 0) {
    *layout = l;
  } else if (n != layout->points) {
    fail(ErrorCode::kCorrupt, path,
         "frame has " + std::to_string(n) + " points, the first frame (" + names[0] + ") has " +
             std::to_string(layout->points));
  } else if (!same_fields(l.fields, layout->fields) || l.width != layout->width) {
    fail(
        ErrorCode::kCorrupt, path,
        "frame has other fields or another WIDTH x HEIGHT than the first frame (" + names[0] + ")");
  }
  FieldRef ref[3];
  const char* axes[3] = {"x", "y", "z"};
  for (int a = 0; a < 3; ++a) {
    auto it = std::find_if(cloud.fields.begin(), cloud.fields.end(),
                           [&](const pcd::Field& fd) { return fd.name == axes[a]; });
    ref[a].offset = it->offset;
    ref[a].type = it->type;
  }
  xyz->assign(n * 3, 0.0);
  valid->assign(n, 0);
  for (size_t p = 0; p < n; ++p) {
    const uint8_t* base = cloud.data.data() + p * cloud.point_step;
    double v[3];
    for (int a = 0; a < 3; ++a) v[a] = read_value(base + ref[a].offset, ref[a].type);
    if (std::isfinite(v[0]) && std::isfinite(v[1]) && std::isfinite(v[2])) {
      std::copy(v, v + 3, xyz->data() + 3 * p);
      (*valid)[p] = 1;
    }
  }
  attrs->clear();
  for (size_t i = 0; i < l.fields.size(); ++i) {
    const PCDField& fd = l.fields[i];
    if (fd.name == "x" || fd.name == "y" || fd.name == "z") continue;
    const size_t bpp = static_cast<size_t>(fd.size) * static_cast<size_t>(fd.count);
    if (static_cast<uint64_t>(l.offsets[i]) + bpp > cloud.point_step)
      fail(ErrorCode::kCorrupt, path, "PCD field " + fd.name + " lies outside its point");
    std::vector<uint8_t> bytes(n * bpp);
    for (size_t p = 0; p < n; ++p)
      std::memcpy(bytes.data() + p * bpp, cloud.data.data() + p * cloud.point_step + l.offsets[i],
                  bpp);
    attrs->push_back(std::move(bytes));
  }
}

// The take's PCD metadata and attribute layouts (no values) from the first frame's layout.
void set_layout(const FrameLayout& l, const std::vector<std::string>& names, Take* t) {
  auto extra = std::make_shared<PCDExtra>();
  extra->frame_names = names;
  extra->encoding = l.encoding;
  extra->version = l.version;
  extra->fields = l.fields;
  extra->width = l.width;
  extra->height = l.height;
  extra->viewpoint = l.viewpoint;
  t->pcd = std::move(extra);
  t->attributes.clear();
  for (const PCDField& fd : l.fields) {
    if (fd.name == "x" || fd.name == "y" || fd.name == "z") continue;
    t->attributes.push_back(attribute_of(fd));
  }
}

// A PCD folder read frame file by frame file: opening lists the files and reads the first one
// (the point count and encoding); a range reads its files only.
class PCDSource : public FrameSource {
 public:
  explicit PCDSource(const std::string& dir) : dir_(dir), names_(list_frames(dir)) {
    read_frame(dir_, names_, 0, &layout_, &xyz_, &valid_, &attrs_);
    header_.source = dir;
    header_.format = Format::kPCDFolder;
    header_.frames = names_.size();
    header_.points = layout_.points;
    header_.labels.assign(layout_.points, std::string());
    set_layout(layout_, names_, &header_);
  }
  bool has_sample_words() const override { return false; }
  // The folder: the encoder stores each frame file's checksum and residue (FORMAT.md 7.3, 14.3).
  std::string original_file() const override { return dir_; }
  void read(size_t first, size_t count, FrameBlock* out) override {
    const size_t N = header_.points;
    clip(&first, &count);
    out->reset(first, count, N, 0, false);
    out->attributes.assign(header_.attributes.size(), std::vector<uint8_t>());
    for (size_t a = 0; a < header_.attributes.size(); ++a)
      out->attributes[a].reserve(count * N * header_.attributes[a].bytes_per_point());
    FrameLayout l = layout_;
    for (size_t k = 0; k < count; ++k) {
      read_frame(dir_, names_, first + k, &l, &xyz_, &valid_, &attrs_);
      std::copy(xyz_.begin(), xyz_.end(), out->xyz.begin() + static_cast<long>(k * N * 3));
      std::copy(valid_.begin(), valid_.end(), out->valid.begin() + static_cast<long>(k * N));
      if (attrs_.size() != out->attributes.size()) continue;  // fields left out (drop_fields)
      for (size_t a = 0; a < attrs_.size(); ++a)
        out->attributes[a].insert(out->attributes[a].end(), attrs_[a].begin(), attrs_[a].end());
    }
  }

 private:
  std::string dir_;
  std::vector<std::string> names_;
  FrameLayout layout_;
  std::vector<double> xyz_;
  std::vector<uint8_t> valid_;
  std::vector<std::vector<uint8_t>> attrs_;
};

}  // namespace

Take read_pcd_folder(const std::string& dir) {
  const std::vector<std::string> names = list_frames(dir);
  Take t;
  t.source = dir;
  t.format = Format::kPCDFolder;
  FrameLayout layout;
  std::vector<double> xyz;
  std::vector<uint8_t> valid;
  std::vector<std::vector<uint8_t>> attrs;
  for (size_t f = 0; f < names.size(); ++f) {
    read_frame(dir, names, f, &layout, &xyz, &valid, &attrs);
    if (f == 0) {
      t.points = layout.points;
      t.labels.assign(t.points, std::string());
      set_layout(layout, names, &t);
    }
    // The take grows frame by frame (not resized for every file up front), so memory follows
    // what has actually been read and checked, not the first frame's count times the file count.
    t.frames = f + 1;
    t.xyz.insert(t.xyz.end(), xyz.begin(), xyz.end());
    t.valid.insert(t.valid.end(), valid.begin(), valid.end());
    for (size_t a = 0; a < attrs.size(); ++a)
      t.attributes[a].data.insert(t.attributes[a].data.end(), attrs[a].begin(), attrs[a].end());
  }
  return t;
}

std::unique_ptr<FrameSource> open_pcd_frames(const std::string& dir) {
  return std::unique_ptr<FrameSource>(new PCDSource(dir));
}

std::vector<std::string> list_pcd_frames(const std::string& dir) {
  return list_frames(dir);
}

std::vector<std::string> pcd_output_names(const Take& take) {
  const size_t F = take.frames;
  std::vector<std::string> names;
  if (take.pcd && take.pcd->frame_names.size() == F) {
    std::set<std::string> seen;
    bool ok = true;
    for (const auto& n : take.pcd->frame_names) {
      if (n.empty() || n.find('/') != std::string::npos || n == "." || n == ".." ||
          !has_pcd_extension(n) || !seen.insert(n).second) {
        ok = false;
        break;
      }
    }
    if (ok) names = take.pcd->frame_names;
  }
  if (names.empty()) {
    for (size_t f = 0; f < F; ++f) {
      char buf[32];
      std::snprintf(buf, sizeof buf, "frame_%06zu.pcd", f + 1);
      names.push_back(buf);
    }
  }
  return names;
}

void check_replaceable_pcd_dir(const std::string& dir, bool overwrite) {
  // Replacing an existing directory deletes it: only allow that for a folder of PCD frames.
  std::error_code ec;
  if (overwrite && fs::is_directory(dir, ec)) {
    for (fs::directory_iterator it(dir, ec), end; !ec && it != end; it.increment(ec)) {
      std::error_code ec2;
      if (!has_pcd_extension(it->path()) || !fs::is_regular_file(it->symlink_status(ec2)))
        fail(ErrorCode::kUsage, dir,
             "refusing to replace this directory: it holds " + it->path().filename().string() +
                 ", which is not a PCD frame");
    }
  }
}

void write_pcd_folder(const Take& take, const std::string& dir, const WriteOptions& opts) {
  const std::string enc = !opts.pcd_encoding.empty()                ? opts.pcd_encoding
                          : take.pcd && !take.pcd->encoding.empty() ? take.pcd->encoding
                                                                    : "binary";
  if (enc != "ascii" && enc != "binary" && enc != "binary_compressed")
    fail(ErrorCode::kInvalidParameter, dir,
         "unknown PCD encoding '" + enc + "' (ascii, binary or binary_compressed)");
  const size_t F = take.frames, N = take.points;
  if (take.xyz.size() != F * N * 3 || take.valid.size() != F * N)
    fail(ErrorCode::kInternal, dir, "take arrays do not match frames x points");
  if (F == 0) fail(ErrorCode::kUsage, dir, "the take has no frames: nothing to write as PCD");
  if (N > (size_t{1} << 31)) fail(ErrorCode::kUsage, dir, "too many points for a PCD file");

  const std::vector<std::string> names = pcd_output_names(take);
  for (const PointAttribute& a : take.attributes)
    if (a.data.size() != F * N * a.bytes_per_point())
      fail(ErrorCode::kInternal, dir, "point field " + a.name + " does not match frames x points");
  const PcdFramePlan plan = pcd_frame_plan(take, enc);

  check_replaceable_pcd_dir(dir, opts.overwrite);
  AtomicDir out(dir, opts.overwrite);
  std::vector<uint8_t> points;
  std::vector<const uint8_t*> attrs(take.attributes.size());
  for (size_t f = 0; f < F; ++f) {
    for (size_t a = 0; a < attrs.size(); ++a)
      attrs[a] = take.attributes[a].data.data() + f * N * take.attributes[a].bytes_per_point();
    pcd_frame_points(plan, N, take.xyz.data() + f * N * 3, take.valid.data() + f * N, attrs,
                     &points);
    const std::string path = (fs::path(out.temp_dir()) / names[f]).string();
    write_file(path, pcd_frame_bytes(plan.layout, points.data()), true);
  }
  out.commit();
}

}  // namespace capz
