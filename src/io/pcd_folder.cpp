// Decoder library (capz_decode): builds without PCL and without the transform encoders.
// A folder of PCD frames <-> Take, through PCL's PCDReader / PCDWriter, which live in a module
// loaded on first use (io/pcd_backend.h: the capz binary does not link PCL's I/O library).
//
// Reading: frames are the *.pcd files of the folder in natural order of their names
// (frame_2 before frame_10); every frame must have the first frame's point count; a point with a
// NaN or infinite coordinate is a gap. PCL trusts the counts in a PCD header and allocates
// (and, for binary bodies, reads) whatever they say, so each file is read whole into memory
// first, its header is parsed here and checked against the file's size, and only then is PCL
// given the bytes (readHeader on the header text, readBodyBinary / readBodyASCII on the body).
//
// Writing: one file per frame, x y z, float32 when every coordinate of the take is exactly a
// float (e.g. the take came from PCD), float64 otherwise (so no precision is lost); gaps are NaN
// points. Files are written into a temporary sibling folder renamed into place (AtomicDir).
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
#include "io/text_number.h"

namespace fs = std::filesystem;

namespace capz {

namespace {

// What capz needs from a PCD header, parsed independently of PCL so the counts can be checked
// against the file size before PCL allocates anything.
struct PcdHeader {
  std::vector<std::string> fields;
  std::vector<int> sizes;
  std::vector<char> types;
  std::vector<uint64_t> counts;
  uint64_t width = 0, height = 1, points = 0;
  std::string data;         // "ascii", "binary", "binary_compressed"
  size_t data_idx = 0;      // offset of the body
  uint64_t point_step = 0;  // bytes per point (sum size * count)
  uint64_t values_per_point = 0;
};

std::vector<std::string> words(const std::string& line) {
  std::vector<std::string> w;
  std::istringstream is(line);
  std::string s;
  while (is >> s) w.push_back(s);
  return w;
}

bool parse_u64(const std::string& s, uint64_t* out) {
  if (s.empty() || s.size() > 18) return false;
  uint64_t v = 0;
  for (char c : s) {
    if (c < '0' || c > '9') return false;
    v = v * 10 + static_cast<uint64_t>(c - '0');
  }
  *out = v;
  return true;
}

// Checks that the body after the header (at h.data_idx) can hold what the header announces, for
// its DATA type (binary, binary_compressed or ascii); fails on an unknown type.
void check_body_size(const std::vector<uint8_t>& bytes, const PcdHeader& h,
                     const std::string& name) {
  const size_t n = bytes.size();
  const uint64_t body = n - h.data_idx;
  if (h.data == "binary") {
    if (h.point_step != 0 && h.points > body / h.point_step)
      fail(ErrorCode::kCorrupt, name,
           "PCD header announces " + std::to_string(h.points) + " points (" +
               std::to_string(h.points * h.point_step) + " bytes) but the body holds " +
               std::to_string(body) + " bytes");
  } else if (h.data == "binary_compressed") {
    if (body < 8) fail(ErrorCode::kCorrupt, name, "compressed PCD body is shorter than 8 bytes");
    const uint8_t* p = bytes.data() + h.data_idx;
    uint64_t csize = static_cast<uint64_t>(p[0]) | static_cast<uint64_t>(p[1]) << 8 |
                     static_cast<uint64_t>(p[2]) << 16 | static_cast<uint64_t>(p[3]) << 24;
    uint64_t usize = static_cast<uint64_t>(p[4]) | static_cast<uint64_t>(p[5]) << 8 |
                     static_cast<uint64_t>(p[6]) << 16 | static_cast<uint64_t>(p[7]) << 24;
    if (csize > body - 8)
      fail(ErrorCode::kCorrupt, name,
           "compressed PCD body says " + std::to_string(csize) + " bytes but the file holds " +
               std::to_string(body - 8));
    if (h.point_step != 0 && h.points > (uint64_t{1} << 32) / h.point_step)
      fail(ErrorCode::kCorrupt, name, "PCD header announces too many points for a compressed body");
    if (usize != h.points * h.point_step)
      fail(ErrorCode::kCorrupt, name,
           "compressed PCD body unpacks to " + std::to_string(usize) + " bytes, the header needs " +
               std::to_string(h.points * h.point_step));
    // LZF expands at most ~90x; anything above that cannot be a valid stream.
    if (usize > csize * 100 + 1024)
      fail(ErrorCode::kCorrupt, name, "compressed PCD body is too small for the points announced");
  } else if (h.data == "ascii") {
    // Every value takes at least one character and one separator.
    if (h.values_per_point != 0 && h.points > (body + 1) / (2 * h.values_per_point))
      fail(ErrorCode::kCorrupt, name,
           "PCD header announces " + std::to_string(h.points) +
               " points but the ASCII body is only " + std::to_string(body) + " bytes");
  } else {
    fail(ErrorCode::kCorrupt, name, "unknown PCD DATA type '" + h.data + "'");
  }
}

PcdHeader parse_header(const std::vector<uint8_t>& bytes, const std::string& name) {
  PcdHeader h;
  size_t pos = 0;
  const size_t n = bytes.size();
  bool have_points = false, have_width = false;
  const size_t kMaxHeader = size_t{1} << 20;
  for (;;) {
    if (pos >= n || pos > kMaxHeader)
      fail(ErrorCode::kCorrupt, name, "PCD header has no DATA line");
    size_t e = pos;
    while (e < n && bytes[e] != '\n') ++e;
    std::string line(reinterpret_cast<const char*>(bytes.data()) + pos, e - pos);
    pos = e < n ? e + 1 : n;
    std::vector<std::string> w = words(line);
    if (w.empty() || w[0][0] == '#') continue;
    const std::string& k = w[0];
    auto one = [&](uint64_t* v) {
      if (w.size() < 2 || !parse_u64(w[1], v))
        fail(ErrorCode::kCorrupt, name, "PCD header: bad " + k + " line");
    };
    if (k == "VERSION" || k == "VIEWPOINT") {
      continue;
    } else if (k == "FIELDS" || k == "COLUMNS") {
      h.fields.assign(w.begin() + 1, w.end());
    } else if (k == "SIZE") {
      h.sizes.clear();
      for (size_t i = 1; i < w.size(); ++i) {
        uint64_t s;
        if (!parse_u64(w[i], &s) || (s != 1 && s != 2 && s != 4 && s != 8))
          fail(ErrorCode::kCorrupt, name, "PCD header: bad SIZE '" + w[i] + "'");
        h.sizes.push_back(static_cast<int>(s));
      }
    } else if (k == "TYPE") {
      h.types.clear();
      for (size_t i = 1; i < w.size(); ++i) {
        if (w[i].size() != 1 || std::strchr("FIU", w[i][0]) == nullptr)
          fail(ErrorCode::kCorrupt, name, "PCD header: bad TYPE '" + w[i] + "'");
        h.types.push_back(w[i][0]);
      }
    } else if (k == "COUNT") {
      h.counts.clear();
      for (size_t i = 1; i < w.size(); ++i) {
        uint64_t c;
        if (!parse_u64(w[i], &c) || c > (1u << 20))
          fail(ErrorCode::kCorrupt, name, "PCD header: bad COUNT '" + w[i] + "'");
        h.counts.push_back(c);
      }
    } else if (k == "WIDTH") {
      one(&h.width);
      have_width = true;
    } else if (k == "HEIGHT") {
      one(&h.height);
    } else if (k == "POINTS") {
      one(&h.points);
      have_points = true;
    } else if (k == "DATA") {
      if (w.size() < 2) fail(ErrorCode::kCorrupt, name, "PCD header: DATA line without a type");
      h.data = w[1];
      for (auto& c : h.data) c = static_cast<char>(std::tolower(static_cast<unsigned char>(c)));
      h.data_idx = pos;
      break;
    } else {
      fail(ErrorCode::kNotOurFormat, name, "not a PCD file (unknown header line '" + k + "')");
    }
  }
  if (h.fields.empty()) fail(ErrorCode::kCorrupt, name, "PCD header has no FIELDS");
  if (h.counts.empty()) h.counts.assign(h.fields.size(), 1);
  if (h.sizes.size() != h.fields.size() || h.types.size() != h.fields.size() ||
      h.counts.size() != h.fields.size())
    fail(ErrorCode::kCorrupt, name, "PCD header: FIELDS, SIZE, TYPE and COUNT disagree in length");
  if (!have_width) fail(ErrorCode::kCorrupt, name, "PCD header has no WIDTH");
  if (h.width > (uint64_t{1} << 40) || h.height > (uint64_t{1} << 40))
    fail(ErrorCode::kCorrupt, name, "PCD header: WIDTH x HEIGHT is absurd");
  if (!have_points) h.points = h.width * h.height;
  if (h.points != h.width * h.height)
    fail(ErrorCode::kCorrupt, name,
         "PCD header: POINTS " + std::to_string(h.points) + " is not WIDTH x HEIGHT " +
             std::to_string(h.width * h.height));
  for (size_t i = 0; i < h.fields.size(); ++i) {
    h.point_step += static_cast<uint64_t>(h.sizes[i]) * h.counts[i];
    h.values_per_point += h.counts[i];
  }
  // The body must be able to hold what the header announces.
  check_body_size(bytes, h, name);
  return h;
}

// PCL's ASCII body reader turns a bad token or a short line into zeros without a word, so the
// body is checked here first: after the header, every non-blank line holds exactly
// values_per_point numbers (nan allowed), and there are exactly `points` such lines.
void check_ascii_body(const std::vector<uint8_t>& bytes, const PcdHeader& h,
                      const std::string& name) {
  const char* p = reinterpret_cast<const char*>(bytes.data()) + h.data_idx;
  const char* end = reinterpret_cast<const char*>(bytes.data()) + bytes.size();
  uint64_t line_no = 0, rows = 0;
  std::string tok;
  while (p < end) {
    const char* nl = static_cast<const char*>(std::memchr(p, '\n', static_cast<size_t>(end - p)));
    const char* le = nl ? nl : end;
    ++line_no;
    uint64_t count = 0;
    for (const char* q = p; q < le;) {
      while (q < le && (*q == ' ' || *q == '\t' || *q == '\r')) ++q;
      if (q == le) break;
      const char* b = q;
      while (q < le && *q != ' ' && *q != '\t' && *q != '\r') ++q;
      tok.assign(b, q);
      double v;
      if (!parse_double(tok, &v))
        fail(ErrorCode::kCorrupt, name,
             "ASCII body line " + std::to_string(line_no) + ": '" + tok + "' is not a number");
      ++count;
    }
    if (count != 0) {
      if (count != h.values_per_point)
        fail(ErrorCode::kCorrupt, name,
             "ASCII body line " + std::to_string(line_no) + " holds " + std::to_string(count) +
                 " values, the header needs " + std::to_string(h.values_per_point));
      ++rows;
    }
    p = nl ? nl + 1 : end;
  }
  if (rows != h.points)
    fail(ErrorCode::kCorrupt, name,
         "ASCII body holds " + std::to_string(rows) + " points, the header says " +
             std::to_string(h.points));
}

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
std::string read_one(const std::string& path, pcd::Cloud* cloud) {
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
  return h.data;
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

// Reads frame `f` (file `names[f]`) into xyz (n x 3) and valid (n), where n is the first
// frame's point count (*points; set from frame 0 when f == 0, with *encoding). A frame of
// another count is an error.
void read_frame(const std::string& dir, const std::vector<std::string>& names, size_t f,
                size_t* points, std::string* encoding, std::vector<double>* xyz,
                std::vector<uint8_t>* valid) {
  const std::string path = (fs::path(dir) / names[f]).string();
  pcd::Cloud cloud;
  std::string enc = read_one(path, &cloud);
  const size_t n = static_cast<size_t>(cloud.width) * cloud.height;
  if (f == 0) {
    *encoding = enc;
    *points = n;
  } else if (n != *points) {
    fail(ErrorCode::kCorrupt, path,
         "frame has " + std::to_string(n) + " points, the first frame (" + names[0] + ") has " +
             std::to_string(*points));
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
}

// A PCD folder read frame file by frame file: opening lists the files and reads the first one
// (the point count and encoding); a range reads its files only.
class PCDSource : public FrameSource {
 public:
  explicit PCDSource(const std::string& dir) : dir_(dir), names_(list_frames(dir)) {
    std::string enc;
    size_t points = 0;
    read_frame(dir_, names_, 0, &points, &enc, &xyz_, &valid_);
    header_.source = dir;
    header_.format = Format::kPCDFolder;
    header_.frames = names_.size();
    header_.points = points;
    header_.labels.assign(points, std::string());
    auto extra = std::make_shared<PCDExtra>();
    extra->frame_names = names_;
    extra->encoding = enc;
    header_.pcd = std::move(extra);
  }
  bool has_sample_words() const override { return false; }
  void read(size_t first, size_t count, FrameBlock* out) override {
    const size_t N = header_.points;
    clip(&first, &count);
    out->reset(first, count, N, 0, false);
    size_t points = N;
    std::string enc;
    for (size_t k = 0; k < count; ++k) {
      read_frame(dir_, names_, first + k, &points, &enc, &xyz_, &valid_);
      std::copy(xyz_.begin(), xyz_.end(), out->xyz.begin() + static_cast<long>(k * N * 3));
      std::copy(valid_.begin(), valid_.end(), out->valid.begin() + static_cast<long>(k * N));
    }
  }

 private:
  std::string dir_;
  std::vector<std::string> names_;
  std::vector<double> xyz_;
  std::vector<uint8_t> valid_;
};

}  // namespace

Take read_pcd_folder(const std::string& dir) {
  const std::vector<std::string> names = list_frames(dir);
  Take t;
  t.source = dir;
  t.format = Format::kPCDFolder;
  auto extra = std::make_shared<PCDExtra>();
  extra->frame_names = names;
  std::vector<double> xyz;
  std::vector<uint8_t> valid;
  for (size_t f = 0; f < names.size(); ++f) {
    read_frame(dir, names, f, &t.points, &extra->encoding, &xyz, &valid);
    if (f == 0) t.labels.assign(t.points, std::string());
    // The take grows frame by frame (not resized for every file up front), so memory follows
    // what has actually been read and checked, not the first frame's count times the file count.
    t.frames = f + 1;
    t.xyz.insert(t.xyz.end(), xyz.begin(), xyz.end());
    t.valid.insert(t.valid.end(), valid.begin(), valid.end());
  }
  t.pcd = std::move(extra);
  return t;
}

std::unique_ptr<FrameSource> open_pcd_frames(const std::string& dir) {
  return std::unique_ptr<FrameSource>(new PCDSource(dir));
}

void write_pcd_folder(const Take& take, const std::string& dir, const WriteOptions& opts) {
  const std::string& enc = opts.pcd_encoding;
  if (enc != "ascii" && enc != "binary" && enc != "binary_compressed")
    fail(ErrorCode::kInvalidParameter, dir,
         "unknown PCD encoding '" + enc + "' (ascii, binary or binary_compressed)");
  const size_t F = take.frames, N = take.points;
  if (take.xyz.size() != F * N * 3 || take.valid.size() != F * N)
    fail(ErrorCode::kInternal, dir, "take arrays do not match frames x points");
  if (F == 0) fail(ErrorCode::kUsage, dir, "the take has no frames: nothing to write as PCD");
  if (N > (size_t{1} << 31)) fail(ErrorCode::kUsage, dir, "too many points for a PCD file");

  // File names: the source's when it was a PCD folder with one name per frame.
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

  bool as_float = true;
  for (size_t i = 0; i < F * N && as_float; ++i) {
    if (!take.valid[i]) continue;
    for (int a = 0; a < 3; ++a) {
      double v = take.xyz[i * 3 + a];
      if (static_cast<double>(static_cast<float>(v)) != v) as_float = false;
    }
  }
  const uint32_t size = as_float ? 4 : 8;

  // Replacing an existing directory deletes it: only allow that for a folder of PCD frames.
  std::error_code ec;
  if (opts.overwrite && fs::is_directory(dir, ec)) {
    for (fs::directory_iterator it(dir, ec), end; !ec && it != end; it.increment(ec)) {
      std::error_code ec2;
      if (!has_pcd_extension(it->path()) || !fs::is_regular_file(it->symlink_status(ec2)))
        fail(ErrorCode::kUsage, dir,
             "refusing to replace this directory: it holds " + it->path().filename().string() +
                 ", which is not a PCD frame");
    }
  }
  AtomicDir out(dir, opts.overwrite);
  const pcd::Backend& backend = pcd::backend(dir);
  pcd::Cloud cloud;
  const char* axes[3] = {"x", "y", "z"};
  for (int a = 0; a < 3; ++a) {
    pcd::Field fd;
    fd.name = axes[a];
    fd.offset = static_cast<uint32_t>(a) * size;
    fd.type = as_float ? pcd::FieldType::kFloat32 : pcd::FieldType::kFloat64;
    fd.count = 1;
    cloud.fields.push_back(fd);
  }
  cloud.width = static_cast<uint32_t>(N);
  cloud.height = 1;
  cloud.point_step = 3 * size;
  cloud.data.resize(static_cast<size_t>(cloud.point_step) * cloud.width);
  const double nan = std::nan("");
  for (size_t f = 0; f < F; ++f) {
    bool dense = true;
    for (size_t p = 0; p < N; ++p) {
      const bool ok = take.is_valid(f, p);
      dense = dense && ok;
      const double* v = take.at(f, p);
      uint8_t* dst = cloud.data.data() + p * cloud.point_step;
      for (int a = 0; a < 3; ++a) {
        double x = ok ? v[a] : nan;
        if (as_float) {
          float fx = static_cast<float>(x);
          std::memcpy(dst + a * 4, &fx, 4);
        } else {
          std::memcpy(dst + a * 8, &x, 8);
        }
      }
    }
    cloud.dense = dense;
    const std::string path = (fs::path(out.temp_dir()) / names[f]).string();
    std::string msg;
    const pcd::Status st = backend.write(path, cloud, enc, as_float ? 9 : 17, &msg);
    if (st == pcd::Status::kPclException)
      fail(ErrorCode::kIo, (fs::path(dir) / names[f]).string(), "PCL: " + msg);
    if (st != pcd::Status::kOk)
      fail(ErrorCode::kIo, (fs::path(dir) / names[f]).string(), "PCL could not write the frame");
  }
  out.commit();
}

}  // namespace capz
