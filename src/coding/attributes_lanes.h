// What ATTR's encoder (attributes_encode.cpp) and decoder (attributes_decode.cpp) share
// (docs/FORMAT.md 13, 13.4, 13.7, 13.5): a field's lanes of ordered integers, the predictors and
// the walks that apply them to a window in the same order on both sides, the colour transform,
// the unit-vector completion, byte planes and the split of values by the gap mask.
#pragma once

#include <algorithm>
#include <array>
#include <cmath>
#include <cstdint>
#include <cstring>
#include <type_traits>
#include <vector>

#include "coding/attributes.h"
#include "coding/attributes_entropy.h"
#include "coding/neighbours.h"
#include "coding/quantiser.h"

namespace capz {
namespace attr {

inline constexpr int kPredictors = 9;  // ids 0..8 (5.3); 9 (6.1) is handled apart
inline constexpr int kUnitPredictor = 9;
inline constexpr int kNearPredictor = 10;  // 7.3: the nearest earlier point's value
inline constexpr int kNearChangePredictor =
    11;  // 7.3: its change since the previous frame, carried over

// One lane: frames x points ordered values of `bits` bits.
struct Lane {
  int bits = 8;
  bool float_residuals = false;  // F elements and 64-bit lanes: float residual coding
  std::vector<uint64_t> u;
};

inline uint64_t mask_of(int bits) {
  return bits >= 64 ? ~uint64_t{0} : (uint64_t{1} << bits) - 1;
}

// A lane residual (a difference modulo 2^bits) as a signed bits-bit number, and the bit length of
// an unsigned value (the encoder's cost of a residual).
inline int64_t signed_residual(uint64_t r, int bits) {
  if (bits >= 64) return static_cast<int64_t>(r);
  const uint64_t top = uint64_t{1} << (bits - 1);
  return (r & top) ? static_cast<int64_t>(r) - static_cast<int64_t>(uint64_t{1} << bits)
                   : static_cast<int64_t>(r);
}
inline uint32_t bit_length(uint64_t u) {
  return u == 0 ? 0 : 64u - static_cast<uint32_t>(__builtin_clzll(u));
}

inline uint64_t load_le(const uint8_t* p, int size) {
  uint64_t v = 0;
  for (int i = 0; i < size; ++i) v |= static_cast<uint64_t>(p[i]) << (8 * i);
  return v;
}
inline void store_le(uint8_t* p, int size, uint64_t v) {
  for (int i = 0; i < size; ++i) p[i] = static_cast<uint8_t>(v >> (8 * i));
}

// f(std::integral_constant<int, S>()) with S the element size when it is 1, 2, 4 or 8, else
// with S = 0 (the caller's loop then takes the size at run time): an element's loads and stores
// as one instruction where the compiler knows its size.
template <typename F>
inline void with_element_size(int size, F&& f) {
  switch (size) {
    case 1:
      return f(std::integral_constant<int, 1>());
    case 2:
      return f(std::integral_constant<int, 2>());
    case 4:
      return f(std::integral_constant<int, 4>());
    case 8:
      return f(std::integral_constant<int, 8>());
    default:
      return f(std::integral_constant<int, 0>());
  }
}

// Element bits <-> ordered lane value (FORMAT.md 13.2).
inline uint64_t to_ordered(uint64_t v, char type, int bits) {
  const uint64_t top = uint64_t{1} << (bits - 1);
  if (type == 'I') return v ^ top;
  if (type == 'F') return (v & top) ? (~v & mask_of(bits)) : (v | top);
  return v;
}
inline uint64_t from_ordered(uint64_t u, char type, int bits) {
  const uint64_t top = uint64_t{1} << (bits - 1);
  if (type == 'I') return u ^ top;
  if (type == 'F') return (u & top) ? (u & ~top) : (~u & mask_of(bits));
  return u;
}

// LOCO-I's median predictor, on values of a lane (a + b - c taken modulo 2^bits).
inline uint64_t med(uint64_t a, uint64_t b, uint64_t c, uint64_t mask) {
  const uint64_t lo = std::min(a, b), hi = std::max(a, b);
  if (c >= hi) return lo;
  if (c <= lo) return hi;
  return (a + b - c) & mask;
}

// S: the spatial prediction of point p of one frame (`row` its values; 0 at point 0).
inline uint64_t spatial(const uint64_t* row, size_t p, size_t W, uint64_t mask) {
  const size_t col = p % W;
  const bool has_left = col > 0, has_up = p >= W;
  if (has_left && has_up) return med(row[p - 1], row[p - W], row[p - W - 1], mask);
  if (has_left) return row[p - 1];
  if (has_up) return row[p - W];
  return 0;
}

// The prediction of u[f][p]: cur is frame f, prev frame f - 1 (nullptr in the window's first).
inline uint64_t predict(int id, const uint64_t* cur, const uint64_t* prev, size_t p, size_t W,
                        uint64_t mask) {
  switch (id) {
    case 0:
      return 0;
    case 1:
      if (p > 0) return cur[p - 1];
      return prev ? prev[0] : 0;
    case 2:
      if (prev) return prev[p];
      if (p > 0) return cur[p - 1];
      return 0;
    case 3:
      return spatial(cur, p, W, mask);
    default:
      if (!prev) return spatial(cur, p, W, mask);
      return (prev[p] + spatial(cur, p, W, mask) - spatial(prev, p, W, mask)) & mask;
  }
}

inline size_t lane_count(const AttrSpec& s, bool colour) {
  return colour ? 4 : static_cast<size_t>(s.count);
}

inline int lane_bits(const AttrSpec& s, bool colour, size_t j) {
  if (colour) return (j == 1 || j == 2) ? 9 : 8;
  return 8 * s.size;
}

// YCoCg-R of one packed colour (bytes B G R A): Y, Co + 255, Cg + 255, A.
inline void colour_forward(const uint8_t* e, uint16_t out[4]) {
  const int B = e[0], G = e[1], R = e[2], A = e[3];
  const int co = R - B;
  const int t = B + (co >> 1);
  const int cg = G - t;
  out[0] = static_cast<uint16_t>(t + (cg >> 1));
  out[1] = static_cast<uint16_t>(co + 255);
  out[2] = static_cast<uint16_t>(cg + 255);
  out[3] = static_cast<uint16_t>(A);
}
inline void colour_inverse(const uint64_t in[4], uint8_t* e) {
  const int y = static_cast<int>(in[0]);
  const int co = static_cast<int>(in[1]) - 255;
  const int cg = static_cast<int>(in[2]) - 255;
  const int t = y - (cg >> 1);
  const int G = cg + t;
  const int B = t - (co >> 1);
  const int R = B + co;
  e[0] = static_cast<uint8_t>(B);
  e[1] = static_cast<uint8_t>(G);
  e[2] = static_cast<uint8_t>(R);
  e[3] = static_cast<uint8_t>(in[3]);
}

// The prediction of a valid point under predictors 5..8 (FORMAT.md 13.3) and 10, 11 (13.5, n the
// point's nearest earlier point, kNoPoint for none): only valid points count; `last` is the
// lane's previous valid value.
inline uint64_t predict_masked(int id, const uint64_t* cur, const uint64_t* prev,
                               const uint8_t* vcur, const uint8_t* vprev, size_t p, size_t W,
                               uint64_t mask, uint64_t last, uint32_t n) {
  const bool has_prev = prev && vprev[p];
  if (id >= kNearPredictor) {
    if (n == kNoPoint || !vcur[n]) return id == kNearPredictor || !has_prev ? last : prev[p];
    if (id == kNearPredictor || !has_prev || !vprev[n]) return cur[n];
    return (cur[n] + prev[p] - prev[n]) & mask;
  }
  const bool has_left = p % W > 0 && vcur[p - 1];
  switch (id) {
    case 5:
      return last;
    case 6:
      return has_prev ? prev[p] : last;
    case 7: {
      const bool has_up = p >= W && vcur[p - W];
      if (has_left && has_up && p % W > 0 && vcur[p - W - 1])
        return med(cur[p - 1], cur[p - W], cur[p - W - 1], mask);
      if (has_left) return cur[p - 1];
      if (has_up) return cur[p - W];
      return last;
    }
    default:
      if (has_prev && has_left && vprev[p - 1]) return (prev[p] + cur[p - 1] - prev[p - 1]) & mask;
      return has_prev ? prev[p] : last;
  }
}

// Walks lane `u` (frames x N values) in coding order under predictor `id`, calling
// step(&value, prediction, gap) for each value: the encoder reads the value, the decoder sets
// it. valid: the window's gap mask (frames x N), used by predictors 5..8, 10 and 11; near: the
// nearest earlier point of each point (FORMAT.md 13.5), used by 10 and 11.
template <typename Step>
inline void walk_lane(int id, std::vector<uint64_t>* lane, const uint8_t* valid,
                      const uint32_t* near, size_t frames, size_t N, size_t W, uint64_t mask,
                      Step&& step) {
  uint64_t last = 0, last_gap = 0;
  const bool masked = id >= 5;
  for (size_t f = 0; f < frames; ++f) {
    uint64_t* cur = lane->data() + f * N;
    const uint64_t* prev = f ? cur - N : nullptr;
    const uint8_t* vcur = masked ? valid + f * N : nullptr;
    const uint8_t* vprev = masked && f ? vcur - N : nullptr;
    for (size_t p = 0; p < N; ++p) {
      if (!masked) {
        step(&cur[p], predict(id, cur, prev, p, W, mask), false);
      } else if (!vcur[p]) {
        step(&cur[p], last_gap, true);
        last_gap = cur[p];
      } else {
        step(&cur[p],
             predict_masked(id, cur, prev, vcur, vprev, p, W, mask, last,
                            id >= kNearPredictor ? near[p] : kNoPoint),
             false);
        last = cur[p];
      }
    }
  }
}

// A float32 element referenced by predictor 9 (FORMAT.md 13.4): element `element` of attribute
// `attribute`, as its bytes (frames x points x count elements).
struct UnitRef {
  size_t attribute = 0, element = 0;
};

inline float load_f32(const std::vector<uint8_t>& bytes, size_t i, size_t count, size_t k) {
  return bits_float(static_cast<uint32_t>(load_le(bytes.data() + (i * count + k) * 4, 4)));
}

// Predictor 9's prediction of one value from x and y: completable (both finite): the ordered
// float32 of sqrt(max((1 - x*x) - y*y, 0)) with sign bit `sign`; otherwise the ordered bits of
// x when x is not finite, else of y. The squares of float32 values are exact in binary64, so a
// fused multiply-add gives the same t.
inline uint64_t unit_prediction(float x, float y, bool completable, uint32_t sign) {
  if (!completable) return to_ordered(float_bits(std::isfinite(x) ? y : x), 'F', 32);
  const double dx = x, dy = y;
  const double t = (1.0 - dx * dx) - dy * dy;
  const float m = static_cast<float>(std::sqrt(t > 0 ? t : 0.0));
  return to_ordered(float_bits(m) | (sign << 31), 'F', 32);
}

// Walks a predictor-9 lane in coding order: step(&value, x, y, completable) per value, x and y
// the referenced elements (decoded before this lane).
template <typename Step>
inline void walk_unit(std::vector<uint64_t>* lane, const std::vector<AttrSpec>& specs,
                      const std::vector<std::vector<uint8_t>>& data, const UnitRef refs[2],
                      Step&& step) {
  const std::vector<uint8_t>& ba = data[refs[0].attribute];
  const std::vector<uint8_t>& bb = data[refs[1].attribute];
  const size_t ca = static_cast<size_t>(specs[refs[0].attribute].count);
  const size_t cb = static_cast<size_t>(specs[refs[1].attribute].count);
  for (size_t i = 0; i < lane->size(); ++i) {
    const float x = load_f32(ba, i, ca, refs[0].element);
    const float y = load_f32(bb, i, cb, refs[1].element);
    step(&(*lane)[i], x, y, std::isfinite(x) && std::isfinite(y));
  }
}

// Entropy state of one lane: for valid points and (predictors 5..8) for gap points.
struct LaneState {
  Magnitude mag[2];
  int prev_nb[2] = {0, 0};
};

// Byte planes of n elements of s bytes: byte 0 of every element, then byte 1, ...
inline std::vector<uint8_t> to_planes(const std::vector<uint8_t>& b, size_t s) {
  const size_t n = s ? b.size() / s : 0;
  std::vector<uint8_t> out(b.size());
  for (size_t k = 0; k < s; ++k)
    for (size_t i = 0; i < n; ++i) out[k * n + i] = b[i * s + k];
  return out;
}
inline std::vector<uint8_t> from_planes(const std::vector<uint8_t>& planes, size_t s) {
  const size_t n = s ? planes.size() / s : 0;
  std::vector<uint8_t> out(planes.size());
  for (size_t k = 0; k < s; ++k)
    for (size_t i = 0; i < n; ++i) out[i * s + k] = planes[k * n + i];
  return out;
}

// The elements (bpp bytes a point) of the valid points, then of the gap points, each in frame
// and point order (FORMAT.md 13.7), and back.
inline void split_by_mask(const std::vector<uint8_t>& b, const uint8_t* valid, size_t n, size_t bpp,
                          std::vector<uint8_t>* at_valid, std::vector<uint8_t>* at_gaps) {
  at_valid->clear();
  at_gaps->clear();
  for (size_t i = 0; i < n; ++i) {
    std::vector<uint8_t>* to = valid[i] ? at_valid : at_gaps;
    to->insert(to->end(), b.begin() + static_cast<long>(i * bpp),
               b.begin() + static_cast<long>((i + 1) * bpp));
  }
}
inline void merge_by_mask(const std::vector<uint8_t>& at_valid, const std::vector<uint8_t>& at_gaps,
                          const uint8_t* valid, size_t n, size_t bpp, std::vector<uint8_t>* b) {
  b->resize(n * bpp);
  size_t iv = 0, ig = 0;
  for (size_t i = 0; i < n; ++i) {
    const uint8_t* from = valid[i] ? at_valid.data() + (iv++) * bpp : at_gaps.data() + (ig++) * bpp;
    std::memcpy(b->data() + i * bpp, from, bpp);
  }
}

// The nearest earlier point of every point of the window (FORMAT.md 13.5): exact squared
// distances of the POSW integers q (frames x points x 3) at the point's first valid frame.
// When every coordinate of q spans less than 2^31, a squared distance fits 64 bits (three squares
// below 2^62), so nearest_earlier_narrow finds the same points with plain sums.
inline std::vector<uint32_t> nearest_points(const int32_t* q, const uint8_t* valid, size_t frames,
                                            size_t points) {
  int64_t lo[3] = {INT32_MAX, INT32_MAX, INT32_MAX}, hi[3] = {INT32_MIN, INT32_MIN, INT32_MIN};
  for (size_t i = 0; i < frames * points; ++i)
    for (int k = 0; k < 3; ++k) {
      lo[k] = std::min<int64_t>(lo[k], q[i * 3 + k]);
      hi[k] = std::max<int64_t>(hi[k], q[i * 3 + k]);
    }
  const int64_t span = int64_t{1} << 31;
  if (hi[0] - lo[0] < span && hi[1] - lo[1] < span && hi[2] - lo[2] < span)
    return nearest_earlier_narrow(q, valid, frames, points);
  return nearest_earlier(q, valid, frames, points, 1, exact_distance);
}

}  // namespace attr
}  // namespace capz
