// What the ascii PCD body's encoder (pcd_ascii_encode.cpp) and decoder (pcd_ascii.cpp) share
// (docs/FORMAT.md 14.6): the flags and limits of the coding, a point line's columns and how a
// column is printed in a number style.
#pragma once

#include <charconv>
#include <cmath>
#include <cstddef>
#include <cstdint>
#include <cstring>
#include <string>
#include <vector>

#include "io/pcd_frame_writer.h"
#include "io/residue/mode.h"
#include "io/text_number.h"

namespace capz {
namespace residue {
namespace ascii {

inline constexpr uint8_t kFixFields = 1, kWholeLine = 2, kNewEnding = 4;
// Style bit: a packed colour's 4 bytes read as float32.
inline constexpr uint8_t kColourAsFloat = 0x80;
inline constexpr size_t kMaxSep = 16, kMaxEnding = 16, kMaxNan = 64;
inline constexpr size_t kSamples = 256;  // values per column the style is chosen on

// One number of a point line: an element of a field, at `off` in the point record.
struct Column {
  size_t off = 0;
  char type = 'F';
  int size = 4;
  bool colour = false;  // a float32 rgb / rgba (the writer prints its bytes as an integer)
};

inline std::vector<Column> columns_of(const PcdFramePlan& plan, size_t* step) {
  std::vector<Column> cols;
  size_t off = 0;
  for (const PCDField& f : plan.layout.fields) {
    for (int k = 0; k < f.count; ++k) {
      if (f.name != "_")
        cols.push_back({off, f.type, f.size,
                        f.type == 'F' && f.size == 4 && f.count == 1 &&
                            (f.name == "rgb" || f.name == "rgba")});
      off += static_cast<size_t>(f.size);
    }
  }
  *step = off;
  return cols;
}

// Appends column c of the point at p in style byte `sb` (precision `prec`).
inline void append_column(const Column& c, const uint8_t* p, uint8_t sb, uint8_t prec,
                          const std::string& nan, std::string* out) {
  const uint8_t style = sb & 0x7F;
  p += c.off;
  if (c.type == 'F' && (!c.colour || (sb & kColourAsFloat))) {
    double v;
    if (c.size == 4) {
      float f;
      std::memcpy(&f, p, 4);
      v = f;
    } else {
      std::memcpy(&v, p, 8);
    }
    if (std::isnan(v))
      *out += nan;
    else if (std::isinf(v))
      *out += v < 0 ? "-inf" : "inf";
    else
      append_styled(v, c.size == 4, style, prec, out);
    return;
  }
  uint64_t u = 0;
  for (int i = 0; i < c.size; ++i) u |= static_cast<uint64_t>(p[i]) << (8 * i);
  char buf[32];
  if (c.type == 'I') {
    const int shift = 64 - 8 * c.size;
    const int64_t v = static_cast<int64_t>(u << shift) >> shift;
    if (style == kStyleShortest)
      out->append(buf, std::to_chars(buf, buf + sizeof buf, v).ptr);
    else
      append_styled(static_cast<double>(v), false, style, prec, out);
  } else if (style == kStyleShortest) {
    out->append(buf, std::to_chars(buf, buf + sizeof buf, u).ptr);
  } else {
    append_styled(static_cast<double>(u), false, style, prec, out);
  }
}

}  // namespace ascii
}  // namespace residue
}  // namespace capz
