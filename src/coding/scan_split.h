// The float32 split of a lossless scan window (docs/FORMAT.md "Scans (format 1.1)", "Lossless
// ragged streams"): float32 coordinates v as integers q on a power-of-two grid s = 2^-E, which
// the scan geometry coder predicts as at a lossy bound, plus per coordinate an exact correction
// t within a budget of b bits that the decoder derives from q and E alone:
//   q = floor(v / s + 1/2); for q != 0, v = q s + (t - 2^(b-1)) u with u = s 2^-b;
//   for q = 0 (budget 32), t is v's float32 bits.
#pragma once

#include <cstddef>
#include <cstdint>
#include <string>
#include <vector>

namespace capz {
namespace scan {

// SCNW's E field: -128 means no split (the integers are mode 2's ordered float32 bits).
constexpr int kNoSplit = -128;
constexpr int kMinSplitExponent = -64, kMaxSplitExponent = 64;
// |q| of a split coordinate stays below this.
constexpr int64_t kMaxSplitInt = int64_t{1} << 30;
// The budget of q = 0: the coordinate's float32 bits.
constexpr int kZeroBudget = 32;
// Contexts of the corrections block: 26 per axis (budgets 0..24, and 25 for the budget 32).
constexpr int kSplitContexts = 78;

// The correction budget b (bits) of grid integer q at exponent E: 0..24 for q != 0 (|q| <
// 2^30, E in [-64, 64]), kZeroBudget for q = 0.
inline int split_budget(int32_t q, int e) {
  if (q == 0) return kZeroBudget;
  const uint64_t a = q < 0 ? uint64_t{0} - static_cast<uint64_t>(static_cast<int64_t>(q))
                           : static_cast<uint64_t>(q);
  // m = |q| s - s/2 = (2|q| - 1) 2^(-E-1); x = floor(log2 m).
  const int x = (63 - __builtin_clzll(2 * a - 1)) - e - 1;
  const int gx = (x < -126 ? -126 : x) - 23;  // log2 of the float32 spacing at m
  const int ux = gx < -e ? gx : -e;           // log2 u = min(-E, gx)
  return -e - ux;
}

// Decodes a corrections block: the window's valid points (valid, total entries) with their
// grid integers q (3 per point, gaps ignored) at exponent e into xyz (3 per point, gaps left
// as they are). Throws Error(kCorrupt) naming `what`.
void decode_split(const uint8_t* data, size_t size, const std::string& what, int e,
                  const std::vector<int32_t>& q, const std::vector<uint8_t>& valid, double* xyz);

// Encoder side (scan_split_encode.cpp). Splits float32 coordinates xyz (3 per point, every
// valid one a float32) at exponent e: *q gets the grid integers (gaps 0), *t the corrections
// (gaps 0). False when some valid coordinate is not finite or its |q| reaches `max_int`.
bool split_coordinates(const double* xyz, const uint8_t* valid, size_t n, int e, int64_t max_int,
                       std::vector<int32_t>* q, std::vector<uint32_t>* t);
// The corrections block of a split (t from split_coordinates).
std::vector<uint8_t> encode_split(int e, const std::vector<int32_t>& q,
                                  const std::vector<uint32_t>& t,
                                  const std::vector<uint8_t>& valid);

}  // namespace scan
}  // namespace capz
