// The bound layer's number mappings (docs/FORMAT.md 4.2): between a coordinate x (double, the
// take's units) and the 32-bit integer q that is predicted and entropy-coded.
//
// Rounding rule (grid): q = round-half-away-from-zero(x / s), computed in double; x' = q * s.
// With s = 2 * max_error * (1 - 2^-30), |x - x'| <= max_error holds for every coordinate whose
// |x / s| < 2^31 (the encoder checks the range and, by default, re-decodes and checks the bound).
#pragma once

#include <cmath>
#include <cstdint>
#include <cstring>

namespace capz {

// kFloat32Grid: x = float32(q * s), float C3D files whose floats are int16-scale multiples.
enum class PosMode : uint8_t {
  kGrid = 0,
  kDecimal = 1,
  kFloat32 = 2,
  kFloat64 = 3,
  kFloat32Grid = 4
};

// Step for a per-coordinate bound; see the rounding rule above.
inline double grid_step_for_bound(double max_error) {
  return 2.0 * max_error * (1.0 - 0x1p-30);
}

// Largest |q| the grid accepts, so predictions and residuals never overflow in practice
// (arithmetic wraps anyway, see predict.h).
constexpr double kMaxGridIndex = 2147483647.0;

// round half away from zero; the caller checks |v| <= kMaxGridIndex first.
// Defined as v < 0 ? -floor(-v + 0.5) : floor(v + 0.5) (the sum rounded in double, as written
// in FORMAT.md); the sum is positive on both branches, where truncation toward zero is floor,
// so the conversion computes it exactly without a call to floor.
inline int32_t round_to_int(double v) {
  return static_cast<int32_t>(v < 0 ? -static_cast<int64_t>(-v + 0.5)
                                    : static_cast<int64_t>(v + 0.5));
}

// std::round(x) as an integer value (halves away from zero) without the libm call, for hot
// loops: for |x| < 2^52, truncation and x - trunc(x) are exact; larger or non-finite x go to
// std::round. Only the sign of a zero result may differ (-0.3 gives +0).
inline double round_half_away(double x) {
  if (!(std::fabs(x) < 0x1p52)) return std::round(x);
  const double t = static_cast<double>(static_cast<int64_t>(x));
  const double d = x - t;
  return d >= 0.5 ? t + 1 : d <= -0.5 ? t - 1 : t;
}

// A float32's bits and back (memcpy: no value passes through a float register on the way, so a
// signalling NaN keeps its bits).
inline uint32_t float_bits(float f) {
  uint32_t u;
  std::memcpy(&u, &f, 4);
  return u;
}
inline float bits_float(uint32_t u) {
  float f;
  std::memcpy(&f, &u, 4);
  return f;
}

// float32 bits <-> an int32 that orders like the float values (sign-magnitude to two's
// complement): non-negative floats keep their bits, negative ones flip the magnitude bits.
inline int32_t float_to_ordered(float f) {
  uint32_t b = float_bits(f);
  if (b & 0x80000000u) b ^= 0x7FFFFFFFu;
  return static_cast<int32_t>(b);
}
inline float ordered_to_float(int32_t q) {
  uint32_t b = static_cast<uint32_t>(q);
  if (b & 0x80000000u) b ^= 0x7FFFFFFFu;
  return bits_float(b);
}
inline int64_t double_to_ordered(double d) {
  uint64_t b;
  std::memcpy(&b, &d, 8);
  if (b >> 63) b ^= 0x7FFFFFFFFFFFFFFFull;
  return static_cast<int64_t>(b);
}
inline double ordered_to_double(int64_t q) {
  uint64_t b = static_cast<uint64_t>(q);
  if (b >> 63) b ^= 0x7FFFFFFFFFFFFFFFull;
  double d;
  std::memcpy(&d, &b, 8);
  return d;
}

// True when a and b have the same bits (lossless compares this way: NaN payloads, -0.0).
inline bool same_bits(double a, double b) {
  return std::memcmp(&a, &b, 8) == 0;
}

// True when x y z (p[0..2]) are exactly +0.0 (bit patterns): FORMAT.md "Origin points", a
// sensor's padding for no return.
inline bool origin_point(const double* p) {
  return same_bits(p[0], 0.0) && same_bits(p[1], 0.0) && same_bits(p[2], 0.0);
}

// True when x is exactly a float32 value (NaN excluded).
inline bool is_float32(double x) {
  return static_cast<double>(static_cast<float>(x)) == x;
}

}  // namespace capz
