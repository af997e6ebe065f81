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
#include <type_traits>
#include <utility>
#include <vector>

#include "coding/analog/analog_lpc.h"
#include "coding/analog/analog_simd.h"

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

// W: the lanes of the weights' vectors (2, or 4 in sign_lms_run_avx2): a dot product is a sum
// of exact integers, the same in any order. Always inlined, so that it is compiled for its
// caller's target.
template <int W>
struct LmsLanes;
template <>
struct LmsLanes<2> {
  typedef double D __attribute__((vector_size(16)));
};
template <>
struct LmsLanes<4> {
  typedef double D __attribute__((vector_size(32)));
};

// Bit length of the zig-zag u of v (|v| < 2^62 here): the top set bit of 2 u + 1 (one bsr).
__attribute__((always_inline)) inline uint64_t lms_zigzag_bits(int64_t v) {
  const uint64_t u = (static_cast<uint64_t>(v) << 1) ^ static_cast<uint64_t>(v >> 63);
  return static_cast<uint64_t>(63 - __builtin_clzll((u << 1) | 1));
}

// The kernel's arrays, views of its per-thread buffers. c[kTaps + i] = clamp(in[i]), zeros
// before; up / down its sign times kStep / -kStep. down, zeros and up lie `stride` apart in that
// order, so that the window of a residual of sign d starts at down + (d + 1) stride (no branch
// on d). ci and sg: the clamped inputs and their signs as int32, for the sliding sums b and b2.
struct LmsScratch {
  double* down;
  double* up;
  double* c;
  size_t stride;
  int64_t* b;
  int64_t* b2;
  int32_t* ci;
  int32_t* sg;
};

// The per-thread buffers of sign_lms_kernel<W, T> for m = n + kTaps + 2 slots; the zeros are
// written when the buffer grows.
template <int W, typename T>
__attribute__((always_inline)) inline LmsScratch lms_scratch(size_t m) {
  thread_local std::vector<double> buf;
  thread_local size_t stride = 0;
  thread_local std::vector<int64_t> bbuf;
  thread_local std::vector<int32_t> cbuf;
  if (stride < m) {
    stride = m + m / 4;
    buf.assign(4 * stride, 0.0);
  }
  if (bbuf.size() < 2 * m) bbuf.resize(2 * m);
  if (cbuf.size() < 2 * m) cbuf.resize(2 * m);
  LmsScratch s;
  s.down = buf.data();
  s.up = s.down + 2 * stride;
  s.c = s.down + 3 * stride;
  s.stride = stride;
  s.b = bbuf.data();
  s.b2 = s.b + m;
  s.ci = cbuf.data();
  s.sg = s.ci + m;
  return s;
}

// Fills c, up, down, ci and sg from the n inputs (m slots) and returns the summed bit lengths of
// the zig-zags of the inputs.
__attribute__((always_inline)) inline uint64_t lms_fill_history(const int32_t* in, size_t n,
                                                                size_t m, const LmsScratch& s) {
  typedef double Lanes __attribute__((vector_size(16)));
  constexpr size_t kTaps = SignLms::kTaps;
  constexpr double kStep = SignLms::kStep;
  double* const c = s.c;
  double* const up = s.up;
  double* const down = s.down;
  int32_t* const ci = s.ci;
  int32_t* const sg = s.sg;
  for (size_t k = 0; k < kTaps; ++k) c[k] = up[k] = down[k] = 0, ci[k] = sg[k] = 0;
  for (size_t k = n + kTaps; k < m; ++k) c[k] = 0, ci[k] = 0;
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
  uint64_t before = acc[0] + acc[1] - 1022 * i0;
  for (size_t i = i0; i < n; ++i) {
    const int64_t v = in[i] > kMaxSample ? kMaxSample : in[i] < -kMaxSample ? -kMaxSample : in[i];
    const double sgn = v > 0 ? 1.0 : v < 0 ? -1.0 : 0.0;
    c[kTaps + i] = static_cast<double>(v);
    up[kTaps + i] = kStep * sgn;
    down[kTaps + i] = -kStep * sgn;
    before += lms_zigzag_bits(in[i]);
  }
  for (size_t i = 0; i < n; ++i) {
    const int32_t v = in[i] > kMaxSample ? kMaxSample : in[i] < -kMaxSample ? -kMaxSample : in[i];
    ci[kTaps + i] = v;
    sg[kTaps + i] = (v > 0) - (v < 0);
  }
  return before;
}

// b[i] = U[i] . H[i + 1] and b2[i] = U[i] . H[i + 2]: kStep times the sums of the products
// p1[t] = sg[t] ci[t + 1] and p2[t] = sg[t] ci[t + 2] (|p| <= 2^28) for t in [i, i + kTaps),
// sliding (exact, on int64). The products go where ci and sg were read (p1 over sg, p2 over ci:
// each slot is read before it is written).
__attribute__((always_inline)) inline void lms_step_sums(size_t n, const LmsScratch& s) {
  constexpr size_t kTaps = SignLms::kTaps;
  const int32_t* const ci = s.ci;
  const int32_t* const sg = s.sg;
  int32_t* p1 = s.sg;
  int32_t* p2 = s.ci;
  for (size_t t = 0; t < n + kTaps; ++t) {
    const int32_t g = sg[t];
    p1[t] = g * ci[t + 1];
    p2[t] = g * ci[t + 2];
  }
  int64_t s1 = 0, s2 = 0;
  for (size_t t = 0; t < kTaps; ++t) {
    s1 += p1[t];
    s2 += p2[t];
  }
  for (size_t i = 0; i < n; ++i) {
    s.b[i] = s1 * SignLms::kStep;
    s.b2[i] = s2 * SignLms::kStep;
    s1 += p1[i + kTaps] - p1[i];
    s2 += p2[i + kTaps] - p2[i];
  }
}

// Adds (or multiplies) W doubles from p into v (an out parameter: a function returning a
// 32-byte vector would have another ABI outside the AVX2 target).
template <int W>
__attribute__((always_inline)) inline void lms_add(typename LmsLanes<W>::D* v, const double* p) {
  typename LmsLanes<W>::D x;
  std::memcpy(&x, p, sizeof x);
  *v += x;
}
template <int W>
__attribute__((always_inline)) inline void lms_mul(typename LmsLanes<W>::D* v, const double* p) {
  typename LmsLanes<W>::D x;
  std::memcpy(&x, p, sizeof x);
  *v *= x;
}

// The dot product of the kTaps weights w with the history h (an exact integer).
template <int W>
__attribute__((always_inline)) inline int64_t lms_dot(const typename LmsLanes<W>::D* w,
                                                      const double* h) {
  constexpr int kVecs = SignLms::kTaps / W;
  typename LmsLanes<W>::D p[kVecs];
  for (int j = 0; j < kVecs; ++j) {
    p[j] = w[j];
    lms_mul<W>(&p[j], h + W * j);
  }
  for (int k = kVecs / 2; k >= 1; k /= 2)
    for (int j = 0; j < k; ++j) p[j] += p[j + k];
  double a = 0;
  for (int l = 0; l < W; ++l) a += p[0][l];
  return static_cast<int64_t>(a);
}

// Adds the window g (d sgn(h), d = +-kStep) to the weights wr with the clamp to
// [-kMaxWeight, kMaxWeight]; returns the new bound, max |w[j]|.
template <int W>
__attribute__((always_inline)) inline int64_t lms_clamped_update(typename LmsLanes<W>::D* wr,
                                                                 const double* g) {
  typedef typename LmsLanes<W>::D Wide;
  constexpr int kVecs = SignLms::kTaps / W;
  Wide lim, mx;
  for (int l = 0; l < W; ++l) lim[l] = SignLms::kMaxWeight, mx[l] = 0;
  const Wide nlim = -lim;
  for (int j = 0; j < kVecs; ++j) {
    Wide w = wr[j];
    lms_add<W>(&w, g + W * j);
    w = w > lim ? lim : w;
    w = w < nlim ? nlim : w;
    wr[j] = w;
    const Wide aw = w < 0 ? -w : w;
    mx = aw > mx ? aw : mx;
  }
  double top = 0;
  for (int l = 0; l < W; ++l) top = mx[l] > top ? mx[l] : top;
  return static_cast<int64_t>(top);
}

// The cascade over a whole known input: out[i] = in[i] - p[i] with p[i] exactly SignLms's
// prediction after in[0..i) (the encoder's pass); returns the summed bit lengths of the
// zig-zags of in and of out. The history is read from a precomputed array of clamped inputs
// and their signs in increasing addresses (weights kept reversed), so the loop stores nothing
// that a later load of the history must wait for; the signs are stored times +kStep and times
// -kStep, and a weight update adds one of the two windows, or a window of zeros for a zero
// residual (d sgn(h) of the filter; the same values up to the sign of a zero weight, which no
// product, sum or comparison here sees). The arrays are a reused per-thread buffer.
//
// The prediction's sum S[i] = W[i] . H[i] (weights at sample i times its history window) is a
// chain through every sample: S[i] needs the weights updated by sample i - 1's residual. The
// loop shortens it by the identity, exact as every product and partial sum is an integer below
// 2^53 (and the clamp not reached),
//   S[i + 1] = (W[i] + d U[i]) . H[i + 1] = W[i] . H[i + 1] + d (U[i] . H[i + 1])
// with d = sgn(residual i) and U[i] the +kStep sign window: W[i] . H[i + 1] is computed while
// sample i's residual is (it needs only W[i]), and B[i] = U[i] . H[i + 1], a sum over the input
// alone, is precomputed as a sliding sum of up[t] c[t + 1] (on int64: the same integers). A
// step that clamps a weight computes S[i + 1] directly.
template <int W, typename T>
__attribute__((always_inline)) inline std::pair<uint64_t, uint64_t> sign_lms_kernel(
    const int32_t* in, size_t n, T* out) {
  typedef typename LmsLanes<W>::D Wide;
  constexpr int kVecs = SignLms::kTaps / W;
  // Two zeros after the inputs (b2 reads c[n + kTaps + 1]).
  const size_t m = n + SignLms::kTaps + 2;
  const LmsScratch s = lms_scratch<W, T>(m);
  const uint64_t before = lms_fill_history(in, n, m, s);
  lms_step_sums(n, s);
  const double* const c = s.c;
  // wr[k] = w[kTaps - 1 - k] multiplies c[kTaps + i - kTaps + k] = in[i - kTaps + k].
  Wide wr[kVecs] = {};
  // The sums are exact integers, kept as int64 from here, and the weights' dot product runs a
  // sample ahead: with d[i] = sgn(residual i) (-1, 0 or 1) and no clamp,
  //   S[i + 1] = W[i + 1] . H[i + 1] = A[i - 1] + d[i - 1] b2[i - 1] + d[i] b[i],
  // A[i - 1] = W[i - 1] . H[i + 1] (the dot product computed at sample i - 1), b2[i] =
  // U[i] . H[i + 2]. The chain from one residual to the next prediction is then integer adds,
  // shifts and selects, and the dot product has two samples' time. d = 0 moves no weight, so
  // only d != 0 near the weights' limit takes the clamping step, which computes S[i + 1] and
  // A[i] = W[i + 1] . H[i + 2] directly.
  int64_t bound = 0;  // at least max |w[j]|
  uint64_t after = 0;
  int64_t sum = 0;    // S[i]
  int64_t ahead = 0;  // A[i - 1] (0 for i = 0: the weights start at 0)
  int64_t bprev = 0;  // d[i - 1] b2[i - 1]
  for (size_t i = 0; i < n; ++i) {
    const int64_t next = ahead + bprev;                    // W[i] . H[i + 1]
    const int64_t ahead_next = lms_dot<W>(wr, c + i + 2);  // W[i] . H[i + 2]
    int64_t p = (sum + (int64_t{1} << (SignLms::kShift - 1))) >> SignLms::kShift;
    p = p > kMaxSample ? kMaxSample : p < -kMaxSample ? -kMaxSample : p;
    const int64_t o = in[i] - p;
    out[i] = static_cast<T>(o);
    after += lms_zigzag_bits(o);
    const int64_t d = (o > 0) - (o < 0);
    if (bound + SignLms::kStep <= SignLms::kMaxWeight || d == 0) {
      const double* g = s.down + static_cast<size_t>(d + 1) * s.stride + i;
      for (int j = 0; j < kVecs; ++j) lms_add<W>(&wr[j], g + W * j);
      bound += d * d * SignLms::kStep;
      sum = next + d * s.b[i];
      ahead = ahead_next;
      bprev = d * s.b2[i];
    } else {
      bound = lms_clamped_update<W>(wr, (d > 0 ? s.up : s.down) + i);  // d sgn(h), d = +-kStep
      sum = lms_dot<W>(wr, c + i + 1);
      ahead = lms_dot<W>(wr, c + i + 2);
      bprev = 0;
    }
  }
  return {before, after};
}

#if defined(__x86_64__) || defined(__i386__)
// sign_lms_kernel<4> compiled for AVX2 (analog_simd.cpp; called only when avx2_enabled()).
std::pair<uint64_t, uint64_t> sign_lms_run_avx2(const int32_t* in, size_t n, int32_t* out);
#endif

template <typename T>
inline std::pair<uint64_t, uint64_t> sign_lms_run(const int32_t* in, size_t n, T* out) {
#if defined(__x86_64__) || defined(__i386__)
  if (std::is_same<T, int32_t>::value && avx2_enabled())
    return sign_lms_run_avx2(in, n, reinterpret_cast<int32_t*>(out));
#endif
  return sign_lms_kernel<2>(in, n, out);
}

inline void sign_lms_residuals(const int32_t* in, size_t n, int64_t* out) {
  sign_lms_run(in, n, out);
}

}  // namespace analog
}  // namespace capz
