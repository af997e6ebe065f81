// Decoder library (capz_decode). PCD frames read without PCL (io/pcd_native.h).
#include "io/pcd_native.h"

#include <algorithm>
#include <cstring>
#include <string>

#include "coding/lzf.h"

namespace capz {
namespace pcd {
namespace {

// PCL's field type for a SIZE and a TYPE (pcl::getFieldType), kUnknown where PCL has none.
FieldType type_of(int size, char type) {
  switch (size) {
    case 1:
      return type == 'I' ? FieldType::kInt8 : type == 'U' ? FieldType::kUInt8 : FieldType::kUnknown;
    case 2:
      return type == 'I'   ? FieldType::kInt16
             : type == 'U' ? FieldType::kUInt16
                           : FieldType::kUnknown;
    case 4:
      return type == 'I'   ? FieldType::kInt32
             : type == 'U' ? FieldType::kUInt32
             : type == 'F' ? FieldType::kFloat32
                           : FieldType::kUnknown;
    case 8:
      return type == 'I'   ? FieldType::kInt64
             : type == 'U' ? FieldType::kUInt64
             : type == 'F' ? FieldType::kFloat64
                           : FieldType::kUnknown;
    default:
      return FieldType::kUnknown;
  }
}

// The keys of a plain header, in the order PCL needs them read (each at most once): FIELDS
// before SIZE before TYPE before COUNT before POINTS (PCL sizes the body at POINTS with the
// point step known then). VERSION, WIDTH, HEIGHT and VIEWPOINT may come anywhere.
enum Key { kFields, kSize, kType, kCount, kPoints, kData, kVersion, kWidth, kHeight, kView, kNone };

Key key_of(const char* p, size_t n) {
  static const char* const kKeys[] = {"FIELDS", "SIZE",    "TYPE",  "COUNT",  "POINTS",
                                      "DATA",   "VERSION", "WIDTH", "HEIGHT", "VIEWPOINT"};
  for (int k = 0; k < kNone; ++k)
    if (std::strlen(kKeys[k]) == n && std::memcmp(kKeys[k], p, n) == 0) return Key(k);
  return kNone;
}

bool blank(uint8_t c) {
  return c == ' ' || (c >= '\t' && c <= '\r');
}

// True when PCL's header parser and capz's read the header [0, h.data_idx) alike: every line is
// empty, a comment (its first word starts with '#'), or a key from key_of followed by words of
// printable characters, each after one blank; the keys in PCL's order; DATA's word exactly
// "binary" or "binary_compressed".
bool plain_header(const std::vector<uint8_t>& bytes, const PcdHeader& h) {
  const char* s = reinterpret_cast<const char*>(bytes.data());
  size_t pos = 0;
  int seen = 0, last_ordered = -1;
  while (pos < h.data_idx) {
    size_t e = pos;
    while (e < h.data_idx && s[e] != '\n') ++e;
    const size_t b = pos;
    pos = e + 1;
    if (e == b) continue;  // an empty line: skipped by both
    size_t w = b;
    while (w < e && blank(static_cast<uint8_t>(s[w]))) ++w;
    if (w < e && s[w] == '#') continue;  // a comment for both
    for (size_t i = b; i < e; ++i) {
      const uint8_t c = static_cast<uint8_t>(s[i]);
      if (c == ' ' ? (i == b || i + 1 == e || s[i + 1] == ' ') : (c < 0x21 || c > 0x7e))
        return false;
    }
    size_t k = b;
    while (k < e && s[k] != ' ') ++k;
    const Key key = key_of(s + b, k - b);
    if (key == kNone || (seen & (1 << key))) return false;
    seen |= 1 << key;
    if (key <= kData) {
      if (key <= last_ordered) return false;
      last_ordered = key;
    }
    if (key == kData) {
      const std::string word(s + k + (k < e), s + e);
      if (pos != h.data_idx || (word != "binary" && word != "binary_compressed")) return false;
    }
  }
  const int needed = 1 << kFields | 1 << kSize | 1 << kType | 1 << kPoints | 1 << kData |
                     1 << kWidth | 1 << kHeight;
  return (seen & needed) == needed;
}

// The fields as PCL's readHeader sets them (offsets: the sums of SIZE x COUNT before each).
bool fields_of(const PcdHeader& h, bool compressed, Cloud* cloud) {
  cloud->fields.clear();
  uint64_t offset = 0;
  for (size_t i = 0; i < h.fields.size(); ++i) {
    Field f;
    f.name = h.fields[i];
    f.offset = static_cast<uint32_t>(offset);
    f.type = type_of(h.sizes[i], h.types[i]);
    f.count = static_cast<uint32_t>(h.counts[i]);
    if (f.count < 1 || f.type == FieldType::kUnknown || (compressed && f.name == "_")) return false;
    offset += static_cast<uint64_t>(h.sizes[i]) * h.counts[i];
    cloud->fields.push_back(f);
  }
  return offset == h.point_step;
}

// The bytes of a compressed body's planes through the last of x y z's (Field::offset: a plane
// starts at points x offset).
size_t coordinate_planes(const PcdHeader& h, const Cloud& cloud) {
  size_t end = 0;
  for (size_t i = 0; i < cloud.fields.size(); ++i) {
    const std::string& name = cloud.fields[i].name;
    if (name == "x" || name == "y" || name == "z")
      end = std::max(end, static_cast<size_t>(cloud.fields[i].offset) +
                              static_cast<size_t>(h.sizes[i]) * h.counts[i]);
  }
  return static_cast<size_t>(h.points) * end;
}

// The compressed body's fields one after another (each all points' values) into points, or
// into *planar_out as they are when it is not null (cloud->data then left empty; with
// `coordinates`, only the planes through x y z's).
bool unpack_compressed(const std::vector<uint8_t>& bytes, const PcdHeader& h, Cloud* cloud,
                       std::vector<uint8_t>* planar_out, bool coordinates) {
  const uint8_t* p = bytes.data() + h.data_idx;
  const size_t csize = static_cast<size_t>(p[0]) | static_cast<size_t>(p[1]) << 8 |
                       static_cast<size_t>(p[2]) << 16 | static_cast<size_t>(p[3]) << 24;
  const size_t n = static_cast<size_t>(h.points), step = static_cast<size_t>(h.point_step);
  std::vector<uint8_t> own;
  std::vector<uint8_t>& planar = planar_out ? *planar_out : own;
  planar.resize(n * step);
  if (planar_out && coordinates)
    return lzf_decompress_prefix(p + 8, csize, planar.data(), planar.size(),
                                 coordinate_planes(h, *cloud));
  if (!lzf_decompress_into(p + 8, csize, planar.data(), planar.size())) return false;
  if (planar_out) {
    cloud->data.clear();
    return true;
  }
  cloud->data.resize(n * step);
  const uint8_t* src = planar.data();
  uint8_t* dst = cloud->data.data();
  for (size_t i = 0; i < h.fields.size(); ++i) {
    const size_t size = static_cast<size_t>(h.sizes[i]) * h.counts[i];
    uint8_t* d = dst + cloud->fields[i].offset;
    if (size == 4) {
      for (size_t q = 0; q < n; ++q, src += 4) std::memcpy(d + q * step, src, 4);
    } else if (size == 8) {
      for (size_t q = 0; q < n; ++q, src += 8) std::memcpy(d + q * step, src, 8);
    } else {
      for (size_t q = 0; q < n; ++q, src += size) std::memcpy(d + q * step, src, size);
    }
  }
  return true;
}

}  // namespace

bool read_native(const std::vector<uint8_t>& bytes, const PcdHeader& h, Cloud* cloud,
                 std::vector<uint8_t>* planar, bool coordinates) {
  // PCL keeps WIDTH and HEIGHT in 32 bits and sizes a compressed body in 32 bits.
  if (h.points == 0 || h.width > UINT32_MAX || h.height > UINT32_MAX ||
      h.points * h.point_step >= (uint64_t{1} << 32) || !plain_header(bytes, h))
    return false;
  const bool compressed = h.data == "binary_compressed";
  if (!fields_of(h, compressed, cloud)) return false;
  cloud->width = static_cast<uint32_t>(h.width);
  cloud->height = static_cast<uint32_t>(h.height);
  cloud->point_step = static_cast<uint32_t>(h.point_step);
  cloud->dense = true;  // not computed: no reader of a Cloud uses it
  if (compressed) return unpack_compressed(bytes, h, cloud, planar, coordinates);
  const uint8_t* body = bytes.data() + h.data_idx;
  cloud->data.assign(body, body + h.points * h.point_step);
  return true;
}

}  // namespace pcd
}  // namespace capz
