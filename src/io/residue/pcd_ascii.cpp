// Ascii PCD bodies rebuilt by number style (see pcd_ascii.h; layout in docs/FORMAT.md 14.6); the
// encoder, which finds the styles, is pcd_ascii_encode.cpp.
#include "io/residue/pcd_ascii.h"

#include <algorithm>
#include <charconv>
#include <cmath>
#include <cstring>
#include <map>
#include <string>

#include "capz/error.h"
#include "io/residue/mode.h"
#include "io/residue/pack.h"
#include "io/residue/pcd_ascii_shared.h"
#include "io/text_number.h"

namespace capz {
namespace residue {

using namespace ascii;

void decode_ascii_body(const PcdFramePlan& plan, const uint8_t* points, size_t n, ByteReader& in,
                       uint64_t limit, const std::string& what, std::vector<uint8_t>* out) {
  size_t step = 0;
  const std::vector<Column> cols = columns_of(plan, &step);
  const size_t C = cols.size();
  if (in.varint() != C) fail(ErrorCode::kCorrupt, what, "ascii body: column count differs");
  std::vector<std::pair<uint8_t, uint8_t>> styles(C);
  for (size_t c = 0; c < C; ++c) {
    styles[c].first = in.u8();
    styles[c].second = in.u8();
    if ((styles[c].first & 0x7F) >= kNumberStyles || styles[c].second > kMaxStylePrecision ||
        ((styles[c].first & kColourAsFloat) && !cols[c].colour))
      fail(ErrorCode::kCorrupt, what, "ascii body: bad number style");
  }
  const std::string sep = in.str(), eol = in.str(), nan = in.str();
  if (sep.size() > kMaxSep || eol.size() > kMaxEnding || nan.size() > kMaxNan)
    fail(ErrorCode::kCorrupt, what, "ascii body: bad separator, line end or NaN text");
  const std::vector<uint8_t> packed = unpack(in, {}, 2 * limit + 65536);
  ByteReader ex(packed.data(), packed.size(), what + ": ascii body exceptions");
  uint64_t left = ex.count(2, "exceptions");
  uint64_t next = left ? ex.varint() : n;
  std::string line, text, ending;
  std::vector<std::string> fields(C);
  for (size_t i = 0; i < n; ++i) {
    const uint8_t* pt = points + i * step;
    for (size_t c = 0; c < C; ++c) {
      fields[c].clear();
      append_column(cols[c], pt, styles[c].first, styles[c].second, nan, &fields[c]);
    }
    line.clear();
    ending = eol;
    bool whole = false;
    if (i == next) {
      const uint8_t flags = ex.u8();
      if (flags == 0 || flags > 7 || ((flags & kWholeLine) && (flags & kFixFields)))
        fail(ErrorCode::kCorrupt, what, "ascii body: bad exception flags");
      if (flags & kWholeLine) line = ex.str(), whole = true;
      if (flags & kFixFields) {
        const uint64_t nfix = ex.count(2, "field fixes");
        for (uint64_t j = 0, c = 0; j < nfix; ++j) {
          c += ex.varint();
          if (c >= C) fail(ErrorCode::kCorrupt, what, "ascii body: field fix past the line");
          fields[static_cast<size_t>(c)] = ex.str();
        }
      }
      if (flags & kNewEnding) ending = ex.str();
      const uint64_t d = --left ? ex.varint() : n;
      if (left && d == 0) fail(ErrorCode::kCorrupt, what, "ascii body: exceptions out of order");
      next = left ? next + d : n;
    }
    if (!whole)
      for (size_t c = 0; c < C; ++c) {
        if (c) line += sep;
        line += fields[c];
      }
    out->insert(out->end(), line.begin(), line.end());
    out->insert(out->end(), ending.begin(), ending.end());
    if (out->size() > limit) fail(ErrorCode::kCorrupt, what, "ascii body longer than the file");
  }
  if (left) fail(ErrorCode::kCorrupt, what, "ascii body: exceptions past the last line");
  const std::string tail = ex.str();
  out->insert(out->end(), tail.begin(), tail.end());
  if (!ex.at_end()) fail(ErrorCode::kCorrupt, what, "ascii body: bytes left over");
}

}  // namespace residue
}  // namespace capz
