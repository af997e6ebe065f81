// The float32 split's decoder (scan_split.h; docs/FORMAT.md "Lossless ragged streams").
#include "coding/scan_split.h"

#include <cmath>
#include <cstring>

#include "capz/error.h"
#include "coding/entropy.h"

namespace capz {
namespace scan {

namespace {

float float_of_bits(uint32_t b) {
  float f;
  std::memcpy(&f, &b, 4);
  return f;
}

// One coordinate: q at exponent e, its correction read through c.
double decode_coordinate(IntDecoder::Cursor& c, int32_t q, int e, int axis, double s) {
  if (q <= -kMaxSplitInt || q >= kMaxSplitInt) c.corrupt("float32 split integer beyond 2^30");
  const int b = split_budget(q, e);
  const int h = b < 4 ? b : 4;
  uint32_t t = 0;
  if (b > 0) {
    const int sym = c.get_symbol(26 * axis + (b > 25 ? 25 : b));
    if (sym >= (1 << h)) c.corrupt("float32 split correction over its budget");
    t = static_cast<uint32_t>(sym) << (b - h);
    if (b > h) t |= c.raw_bits(b - h);
  }
  if (q == 0) {
    const double v = static_cast<double>(float_of_bits(t));
    if (!(v >= -0.5 * s && v < 0.5 * s))
      c.corrupt("float32 split correction of a zero integer outside half a step");
    return v;
  }
  const double half = b > 0 ? std::ldexp(1.0, b - 1) : 0.0;
  const double v =
      std::ldexp(static_cast<double>(q), -e) + std::ldexp(static_cast<double>(t) - half, -e - b);
  if (static_cast<double>(static_cast<float>(v)) != v)
    c.corrupt("float32 split correction gives no float32");
  return v;
}

}  // namespace

void decode_split(const uint8_t* data, size_t size, const std::string& what, int e,
                  const std::vector<int32_t>& q, const std::vector<uint8_t>& valid, double* xyz) {
  if (e < kMinSplitExponent || e > kMaxSplitExponent || q.size() != 3 * valid.size())
    fail(ErrorCode::kCorrupt, what, "float32 split exponent out of range");
  IntDecoder dec(data, size, kSplitContexts, what);
  IntDecoder::Cursor c = dec.cursor();
  const double s = std::ldexp(1.0, -e);
  for (size_t i = 0; i < valid.size(); ++i) {
    if (!valid[i]) continue;
    for (int a = 0; a < 3; ++a)
      xyz[3 * i + static_cast<size_t>(a)] =
          decode_coordinate(c, q[3 * i + static_cast<size_t>(a)], e, a, s);
  }
  dec.commit(c);
  if (!dec.at_end())
    fail(ErrorCode::kCorrupt, what, "bytes left after the float32 split corrections");
}

}  // namespace scan
}  // namespace capz
