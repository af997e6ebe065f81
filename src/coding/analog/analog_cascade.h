// Backward-adaptive cascade stage (docs/format-drafts/analog.md A.3.2): a sign-sign LMS filter
// on the LPC residual, as the NLMS stages of Monkey's Audio and OptimFROG. It costs no side
// information: encoder and decoder adapt the same integer weights from the same past values.
//
// With history h[0..kTaps) (h[0] the previous stage input) and weights w (units 2^-kShift):
//   p   = clamp((sum_j w[j] * h[j] + 2^(kShift-1)) >> kShift, -kMaxSample, kMaxSample)  (int64)
//   out = in - p
//   then w[j] += kStep * sgn(out) * sgn(h[j]), clamped to [-kMaxWeight, kMaxWeight], and the
//   history shifts in `in` clamped to [-kMaxSample, kMaxSample].
// All weights and history start at 0 at the start of each channel of each window.
#pragma once

#include <cstddef>
#include <cstdint>
#include <cstring>
#include <utility>
#include <vector>

#include "coding/analog/analog_lpc.h"

namespace capz {
namespace analog {

// The arithmetic runs on doubles: weights (|w| <= 2^17), history (|h| <= 2^28), their products
// (< 2^45) and every partial sum of 16 products (< 2^49) are integers below 2^53, so each step
// is exact and the sum is the same integer in any order: two-lane vectors, no int64 multiplies.
class SignLms {
 public:
  static constexpr int kTaps = 16;
  static constexpr int kShift = 14;
  static constexpr int32_t kStep = 64;
  static constexpr int32_t kMaxWeight = 1 << 17;

  int64_t predict() const {
    const double* h = h_ + pos_;
    Lanes a0 = {0, 0}, a1 = {0, 0};
    for (int j = 0; j < kTaps; j += 4) {
      a0 += w_[j / 2] * load(h + j);
      a1 += w_[j / 2 + 1] * load(h + j + 2);
    }
    const Lanes a = a0 + a1;
    int64_t s = static_cast<int64_t>(a[0] + a[1]);
    s = (s + (int64_t{1} << (kShift - 1))) >> kShift;
    return s > kMaxSample ? kMaxSample : s < -kMaxSample ? -kMaxSample : s;
  }
  // After coding: `in` was the stage input, `out` = in - predict().
  void update(int64_t in, int64_t out) {
    if (out != 0) {
      const double d = out > 0 ? kStep : -kStep;
      const double* g = g_ + pos_;
      if (bound_ + kStep <= kMaxWeight) {
        // No weight can pass the limit in this step: the clamp is the identity.
        for (int j = 0; j < kTaps / 2; ++j) w_[j] += d * load(g + 2 * j);
        bound_ += kStep;
      } else {
        const Lanes lim = {kMaxWeight, kMaxWeight}, nlim = -lim;
        Lanes m = {0, 0};
        for (int j = 0; j < kTaps / 2; ++j) {
          Lanes w = w_[j] + d * load(g + 2 * j);
          w = w > lim ? lim : w;
          w = w < nlim ? nlim : w;
          w_[j] = w;
          const Lanes a = w < 0 ? -w : w;
          m = a > m ? a : m;
        }
        bound_ = m[0] > m[1] ? m[0] : m[1];
      }
    }
    if (pos_ == 0) {
      // Slide the window back to the end of the ring (the newest kTaps - 1 survive).
      std::memmove(h_ + kRing, h_, sizeof(double) * kTaps);
      std::memmove(g_ + kRing, g_, sizeof(double) * kTaps);
      pos_ = kRing;
    }
    --pos_;
    const int64_t c = in > kMaxSample ? kMaxSample : in < -kMaxSample ? -kMaxSample : in;
    h_[pos_] = static_cast<double>(c);
    g_[pos_] = c > 0 ? 1.0 : c < 0 ? -1.0 : 0.0;
  }

 private:
  typedef double Lanes __attribute__((vector_size(16)));
  static Lanes load(const double* p) {
    Lanes v;
    std::memcpy(&v, p, sizeof v);
    return v;
  }
  static constexpr int kRing = 112;
  // Weights w[j] in lanes; history h[j] = h_[pos_ + j] and its signs g_[pos_ + j].
  Lanes w_[kTaps / 2] = {};
  double h_[kRing + kTaps] = {};
  double g_[kRing + kTaps] = {};
  int pos_ = kRing;
  double bound_ = 0;  // at least max |w[j]|
};

// The cascade over a whole known input: out[i] = in[i] - p[i] with p[i] exactly SignLms's
// prediction after in[0..i) (the encoder's pass); returns the summed bit lengths of the
// zig-zags of in and of out. The history is read from a precomputed array of clamped inputs
// and their signs in increasing addresses (weights kept reversed), so the loop stores nothing
// that a later load of the history must wait for; the signs are stored times +kStep and times
// -kStep, so a weight update adds one of the two (d sgn(h) of the filter, the same products).
// The arrays are a reused per-thread buffer.
//
// The prediction's sum S[i] = W[i] . H[i] (weights at sample i times its history window) is a
// chain through every sample: S[i] needs the weights updated by sample i - 1's residual. The
// loop shortens it by the identity, exact as every product and partial sum is an integer below
// 2^53 (and the clamp not reached),
//   S[i + 1] = (W[i] + d U[i]) . H[i + 1] = W[i] . H[i + 1] + d (U[i] . H[i + 1])
// with d = sgn(residual i) and U[i] the +kStep sign window: W[i] . H[i + 1] is computed while
// sample i's residual is (it needs only W[i]), and B[i] = U[i] . H[i + 1], a sum over the input
// alone, is precomputed as a sliding sum of up[t] c[t + 1]. A step that clamps a weight
// computes S[i + 1] directly.
template <typename T>
inline std::pair<uint64_t, uint64_t> sign_lms_run(const int32_t* in, size_t n, T* out) {
  typedef double Lanes __attribute__((vector_size(16)));
  constexpr int kTaps = SignLms::kTaps;
  constexpr double kStep = SignLms::kStep, kMaxWeight = SignLms::kMaxWeight;
  // Bit length of the zig-zag u of v (|v| < 2^62 here): the top set bit of 2 u + 1 (one bsr).
  auto bits = [](int64_t v) {
    const uint64_t u = (static_cast<uint64_t>(v) << 1) ^ static_cast<uint64_t>(v >> 63);
    return static_cast<uint64_t>(63 - __builtin_clzll((u << 1) | 1));
  };
  // c[kTaps + i] = clamp(in[i]), zeros before; up / down its sign times kStep / -kStep.
  const size_t m = n + kTaps + 2;  // two zeros after the inputs (b2 reads c[n + kTaps + 1])
  thread_local std::vector<double> buf;
  if (buf.size() < 5 * m) buf.resize(5 * m);
  double* c = buf.data();
  double* up = c + m;
  double* down = up + m;
  double* b = down + m;
  double* b2 = b + m;
  uint64_t before = 0;
  for (size_t k = 0; k < kTaps; ++k) c[k] = up[k] = down[k] = 0;
  c[n + kTaps] = c[n + kTaps + 1] = 0;
  // Two samples a step: the clamp on doubles (exact), the signs from compares, and the bit
  // lengths from the exponent of |2 in + 1/2| (= u + 1/2 for the zig-zag u; 1/2 gives 0).
  typedef int32_t Pair __attribute__((vector_size(8)));
  typedef unsigned long long Ints __attribute__((vector_size(16)));
  const Lanes hi = {kMaxSample, kMaxSample}, lo = -hi, zero = {0, 0};
  const Lanes step = {kStep, kStep}, half = {0.5, 0.5};
  const Ints mag = {~(uint64_t{1} << 63), ~(uint64_t{1} << 63)};
  Ints acc = {0, 0};
  size_t i0 = 0;
  for (; i0 + 2 <= n; i0 += 2) {
    Pair q;
    std::memcpy(&q, in + i0, sizeof q);
    const Lanes x = __builtin_convertvector(q, Lanes);
    Lanes v = x < hi ? x : hi;
    v = v > lo ? v : lo;
    const Lanes u = (v > zero ? step : zero) + (v < zero ? -step : zero);
    const Lanes nu = -u;
    std::memcpy(c + kTaps + i0, &v, sizeof v);
    std::memcpy(up + kTaps + i0, &u, sizeof u);
    std::memcpy(down + kTaps + i0, &nu, sizeof nu);
    const Lanes e = (x + x) + half;
    Ints eb;
    std::memcpy(&eb, &e, sizeof e);
    acc += (eb & mag) >> 52;
  }
  before = acc[0] + acc[1] - 1022 * i0;
  for (size_t i = i0; i < n; ++i) {
    const int64_t v = in[i] > kMaxSample ? kMaxSample : in[i] < -kMaxSample ? -kMaxSample : in[i];
    const double sg = v > 0 ? 1.0 : v < 0 ? -1.0 : 0.0;
    c[kTaps + i] = static_cast<double>(v);
    up[kTaps + i] = kStep * sg;
    down[kTaps + i] = -kStep * sg;
    before += bits(in[i]);
  }
  auto load = [](const double* p) {
    Lanes v;
    std::memcpy(&v, p, sizeof v);
    return v;
  };
  // b[i] = U[i] . H[i + 1] and b2[i] = U[i] . H[i + 2]: the sums of up[t] c[t + lag] for t in
  // [i, i + kTaps), lag 1 and 2, sliding (|terms| <= 2^34, exact sums).
  auto sliding = [&](size_t lag, double* to) {
    double sum = 0;
    for (size_t t = 0; t < kTaps; ++t) sum += up[t] * c[t + lag];
    for (size_t i = 0; i + 1 < n; ++i) {
      to[i] = sum;
      sum += up[i + kTaps] * c[i + kTaps + lag] - up[i] * c[i + lag];
    }
    if (n) to[n - 1] = sum;
  };
  sliding(1, b);
  sliding(2, b2);
  auto dot = [&](const Lanes* w, const double* h) {
    Lanes p[kTaps / 2];
    for (int j = 0; j < kTaps / 2; ++j) p[j] = w[j] * load(h + 2 * j);
    const Lanes a = ((p[0] + p[1]) + (p[2] + p[3])) + ((p[4] + p[5]) + (p[6] + p[7]));
    return a[0] + a[1];
  };
  // wr[k] = w[kTaps - 1 - k] multiplies c[kTaps + i - kTaps + k] = in[i - kTaps + k].
  Lanes wr[kTaps / 2] = {};
  // The sums are exact integers, kept as int64 from here, and the weights' dot product runs a
  // sample ahead: with d[i] = sgn(residual i) (-1, 0 or 1) and no clamp,
  //   S[i + 1] = W[i + 1] . H[i + 1] = A[i - 1] + d[i - 1] b2[i - 1] + d[i] b[i],
  // A[i - 1] = W[i - 1] . H[i + 1] (the dot product computed at sample i - 1), b2[i] =
  // U[i] . H[i + 2]. The chain from one residual to the next prediction is then integer adds,
  // shifts and selects, and the dot product has two samples' time. A weight update adds d times
  // the +kStep sign window (d = 0 adds zeros, leaving the weights' values as they were). A step
  // that clamps a weight computes S[i + 1] and A[i] = W[i + 1] . H[i + 2] directly.
  double bound = 0;
  uint64_t after = 0;
  int64_t sum = 0;    // S[i]
  int64_t ahead = 0;  // A[i - 1] (0 for i = 0: the weights start at 0)
  int64_t dprev = 0, b2prev = 0;
  for (size_t i = 0; i < n; ++i) {
    const int64_t next = ahead + dprev * b2prev;                          // W[i] . H[i + 1]
    const int64_t ahead_next = static_cast<int64_t>(dot(wr, c + i + 2));  // W[i] . H[i + 2]
    int64_t s = (sum + (int64_t{1} << (SignLms::kShift - 1))) >> SignLms::kShift;
    s = s > kMaxSample ? kMaxSample : s < -kMaxSample ? -kMaxSample : s;
    const int64_t o = in[i] - s;
    out[i] = static_cast<T>(o);
    after += bits(o);
    const int64_t d = (o > 0) - (o < 0);
    if (bound + kStep <= kMaxWeight) {
      const double dd = static_cast<double>(d);
      for (int j = 0; j < kTaps / 2; ++j) wr[j] += dd * load(up + i + 2 * j);
      bound += kStep * dd * dd;
      sum = next + d * static_cast<int64_t>(b[i]);
      ahead = ahead_next;
      dprev = d;
      b2prev = static_cast<int64_t>(b2[i]);
    } else if (d == 0) {
      sum = next;
      ahead = ahead_next;
      dprev = 0;
    } else {
      const double* g = (o > 0 ? up : down) + i;  // d sgn(h), d = +-kStep
      const Lanes lim = {kMaxWeight, kMaxWeight}, nlim = -lim;
      Lanes mx = {0, 0};
      for (int j = 0; j < kTaps / 2; ++j) {
        Lanes w = wr[j] + load(g + 2 * j);
        w = w > lim ? lim : w;
        w = w < nlim ? nlim : w;
        wr[j] = w;
        const Lanes aw = w < 0 ? -w : w;
        mx = aw > mx ? aw : mx;
      }
      bound = mx[0] > mx[1] ? mx[0] : mx[1];
      sum = static_cast<int64_t>(dot(wr, c + i + 1));
      ahead = static_cast<int64_t>(dot(wr, c + i + 2));
      dprev = 0;
    }
  }
  return {before, after};
}

inline void sign_lms_residuals(const int32_t* in, size_t n, int64_t* out) {
  sign_lms_run(in, n, out);
}

}  // namespace analog
}  // namespace capz
