// What ROTW's encoder (rotations_encode.cpp) and decoder (rotations.cpp) share (docs/FORMAT.md
// 12): the roles and their contexts, the predictions and the one traversal (code_sample) that
// drives the encoder's estimate, the encoder and the decoder. Both files are compiled without
// fused multiply-add contraction (CMakeLists.txt), so they predict alike on every build.
#pragma once

#include <algorithm>
#include <cfloat>
#include <cmath>
#include <cstddef>
#include <cstdint>
#include <cstring>
#include <limits>

#include "coding/entropy.h"
#include "coding/quantiser.h"

namespace capz {
namespace rotw {

inline constexpr int kElements = 17;  // 16 matrix elements + reliability
inline constexpr int kPredictors = 4;
inline constexpr int kContextsPerRole = 16;  // by the series' previous token
// What predicts a value (its role picks the contexts).
enum Role : int {
  kTime = 0,    // temporal prediction of a rotation element
  kNorm = 1,    // column 0's unit norm
  kCircle = 2,  // column 1's orthogonality and unit norm
  kCross = 3,   // column 2 = column 0 x column 1
  kTranslation = 4,
  kBottom = 5,
  kReliability = 6,
  kRoles = 7
};
inline constexpr int kContexts = kRoles * kContextsPerRole;
inline constexpr uint32_t kOne = 0x3F800000u;  // 1.0f

// float_to_ordered / ordered_to_float (quantiser.h) on the bits themselves, so no value is
// passed as a float on its way (a signalling NaN keeps its bits). Its own inverse.
inline uint32_t ordered(uint32_t bits) {
  return bits & 0x80000000u ? bits ^ 0x7FFFFFFFu : bits;
}
inline bool finite(uint32_t bits) {
  return (bits & 0x7F800000u) != 0x7F800000u;
}
inline double value(uint32_t bits) {
  return static_cast<double>(bits_float(bits));
}
// float() of the spec: round to binary32, overflow to infinity (never called with a NaN).
inline uint32_t to_bits(double d) {
  if (d > FLT_MAX) return float_bits(std::numeric_limits<float>::infinity());
  if (d < -FLT_MAX) return float_bits(-std::numeric_limits<float>::infinity());
  return float_bits(static_cast<float>(d));
}

inline int escape_set(int role) {
  return role <= kCross ? 0 : role == kTranslation ? 1 : 2;
}

// Where element k of segment g at sample s lives, as float32 bits.
struct WindowBits {
  const float* matrices;
  const float* reliability;
  size_t segments;
  uint32_t get(size_t s, size_t g, int k) const {
    const size_t i = s * segments + g;
    uint32_t u;
    std::memcpy(&u, k < 16 ? &matrices[i * 16 + static_cast<size_t>(k)] : &reliability[i], 4);
    return u;
  }
};

// Temporal prediction of element k of segment g at sample s with predictor p.
inline uint32_t temporal(int p, const WindowBits& w, size_t s, size_t g, int k) {
  if (p == 0 || s == 0) return 0;
  const uint32_t a = w.get(s - 1, g, k);
  if (p == 1 || s < static_cast<size_t>(p)) return a;
  const uint32_t b = w.get(s - 2, g, k);
  if (!finite(a) || !finite(b)) return a;
  if (p == 2) return to_bits(2.0 * value(a) - value(b));
  const uint32_t c = w.get(s - 3, g, k);
  if (!finite(c)) return a;
  return to_bits((3.0 * value(a) - 3.0 * value(b)) + value(c));
}

// Column 1's circle for row i with the value t: rows p < q solve A p + B q = C on the circle of
// squared radius r2 (docs/FORMAT.md 12).
struct Circle {
  int p, q;
  double A, B, C, n2, r2, h2;
  Circle(const double u[3], int i, double t) {
    p = i == 0 ? 1 : 0;
    q = i == 2 ? 1 : 2;
    A = u[p];
    B = u[q];
    C = -(u[i] * t);
    n2 = A * A + B * B;
    r2 = 1 - t * t;
    h2 = r2 - (C * C) / n2;
  }
  bool usable() const {
    return std::isfinite(n2) && std::isfinite(r2) && std::isfinite(h2) && n2 > 0x1p-40 &&
           r2 > 0x1p-40 && h2 > 0;
  }
};

// The rotation part of one structured sample (previous sample's rotation all finite). code(pred,
// role, k) codes element k and returns its bits.
template <typename Code>
void code_structured(const uint32_t T[16], Code& code) {
  double x[16] = {};
  auto put = [&](uint32_t pred, int role, int k) { x[k] = value(code(pred, role, k)); };
  // Column 0: the two smaller in time, the largest from the unit norm.
  int j = 0;
  for (int k = 1; k < 3; ++k)
    if (std::fabs(bits_float(T[k])) > std::fabs(bits_float(T[j]))) j = k;
  const int m = j == 0 ? 1 : 0, n = j == 2 ? 1 : 2;
  put(T[m], kTime, m);
  put(T[n], kTime, n);
  if (std::isfinite(x[m]) && std::isfinite(x[n])) {
    double r = 1 - (x[m] * x[m] + x[n] * x[n]);
    if (!(r > 0)) r = 0;
    put(to_bits(std::copysign(std::sqrt(r), static_cast<double>(bits_float(T[j])))), kNorm, j);
  } else {
    put(T[j], kTime, j);
  }
  // Column 1: the best conditioned row in time, the other two on the circle.
  const double u[3] = {x[0], x[1], x[2]};
  int best = -1;
  double score = 0;
  if (std::isfinite(u[0]) && std::isfinite(u[1]) && std::isfinite(u[2]))
    for (int i = 0; i < 3; ++i) {
      const Circle c(u, i, value(T[4 + i]));
      if (c.usable() && (best < 0 || c.h2 / c.r2 > score)) {
        best = i;
        score = c.h2 / c.r2;
      }
    }
  if (best < 0) {
    for (int k = 4; k < 7; ++k) put(T[k], kTime, k);
  } else {
    put(T[4 + best], kTime, 4 + best);
    const Circle c(u, best, x[4 + best]);
    if (!std::isfinite(x[4 + best]) || !c.usable()) {
      put(T[4 + c.p], kTime, 4 + c.p);
      put(T[4 + c.q], kTime, 4 + c.q);
    } else {
      const double h = std::sqrt(c.h2), w = std::sqrt(c.n2);
      const double p0 = (c.C * c.A) / c.n2, q0 = (c.C * c.B) / c.n2;
      const double hb = (h * c.B) / w, ha = (h * c.A) / w;
      const double tp = value(T[4 + c.p]), tq = value(T[4 + c.q]);
      const double d1p = (p0 - hb) - tp, d1q = (q0 + ha) - tq;
      const double d2p = (p0 + hb) - tp, d2q = (q0 - ha) - tq;
      const bool plus = !(d2p * d2p + d2q * d2q < d1p * d1p + d1q * d1q);
      put(to_bits(plus ? p0 - hb : p0 + hb), kCircle, 4 + c.p);
      put(to_bits(plus ? q0 + ha : q0 - ha), kCircle, 4 + c.q);
    }
  }
  // Column 2: the cross product.
  bool all = true;
  for (int k : {0, 1, 2, 4, 5, 6}) all = all && std::isfinite(x[k]);
  if (all) {
    put(to_bits(x[1] * x[6] - x[2] * x[5]), kCross, 8);
    put(to_bits(x[2] * x[4] - x[0] * x[6]), kCross, 9);
    put(to_bits(x[0] * x[5] - x[1] * x[4]), kCross, 10);
  } else {
    for (int k = 8; k < 11; ++k) put(T[k], kTime, k);
  }
}

// Codes the 17 values of segment g at sample s in the order of docs/FORMAT.md 12:
// code(pred, role, k) codes element k with that prediction and returns its bits (written to the
// window before it returns, so later predictions see it).
template <typename Code>
void code_sample(const WindowBits& w, size_t s, size_t g, int pr, int pt, Code& code) {
  static const int kBottomK[4] = {3, 7, 11, 15};
  static const uint32_t kStart[4] = {0, 0, 0, kOne};
  for (int i = 0; i < 4; ++i)
    code(s ? w.get(s - 1, g, kBottomK[i]) : kStart[i], kBottom, kBottomK[i]);
  code(s ? w.get(s - 1, g, 16) : kOne, kReliability, 16);
  for (int k = 12; k < 15; ++k) code(temporal(pt, w, s, g, k), kTranslation, k);
  static const int kRot[9] = {0, 1, 2, 4, 5, 6, 8, 9, 10};
  uint32_t T[16] = {};
  bool structured = s >= 1;
  for (int k : kRot) {
    T[k] = temporal(pr, w, s, g, k);
    structured = structured && finite(w.get(s - 1, g, k));
  }
  if (structured) {
    code_structured(T, code);
  } else {
    for (int k : kRot) code(T[k], kTime, k);
  }
}

// Every value of the window in coding order; code(pred, role, s, g, k) as above.
template <typename Code>
void code_window(const WindowBits& w, size_t samples, int pr, int pt, Code code) {
  for (size_t s = 0; s < samples; ++s)
    for (size_t g = 0; g < w.segments; ++g) {
      auto at = [&](uint32_t pred, int role, int k) { return code(pred, role, s, g, k); };
      code_sample(w, s, g, pr, pt, at);
    }
}

// The context of a residual of `role` after the series' previous token.
inline int context(int role, int prev_tok) {
  return role * kContextsPerRole + std::min(prev_tok, kContextsPerRole - 1);
}

inline uint32_t residual(uint32_t v, uint32_t pred) {
  return ordered(v) - ordered(pred);
}

}  // namespace rotw
}  // namespace capz
