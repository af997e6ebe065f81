#include "coding/analog/analog_cross.h"

#include <cmath>
#include <cstring>

#include "coding/analog/analog_scratch.h"
#include "coding/analog/analog_simd.h"

namespace capz {
namespace analog {
namespace {

typedef double Lanes __attribute__((vector_size(16)));

// Bit length of the zig-zag of v (0 for 0), without a branch: clz(u | 1) is defined for every
// u, and u == 0 gives 64 - 63 - 1 = 0.
int bit_length(int64_t v) {
  const uint64_t u = (static_cast<uint64_t>(v) << 1) ^ static_cast<uint64_t>(v >> 63);
  return 64 - __builtin_clzll(u | 1) - (u == 0);
}

typedef unsigned long long Ints __attribute__((vector_size(16)));

// Sum over i of bit_length(r1[i] - cross_predict(beta, ref[i])), two samples a step on doubles.
// With |beta| < 2^15 and |ref| <= 2^29 (an LPC residual), beta ref + 1/2 is exact, and
//   floor((beta ref + 2^11) / 2^12) = nearest((beta ref + 1/2) / 2^12)
// (never a tie), rounded by adding and subtracting 1.5 2^52. The zig-zag u of the difference
// (< 2^31) is exact too, and the bit length of u >= 1 is its biased exponent - 1022; u = 0 is
// raised to 1/2, whose exponent gives 0.
int64_t residual_bits_clamped(const int32_t* r1, const int32_t* ref, size_t n, int32_t beta) {
  const double kRound = 6755399441055744.0;  // 1.5 2^52
  const Lanes b = {static_cast<double>(beta), static_cast<double>(beta)};
  const Lanes half = {0.5, 0.5}, scale = {1.0 / 4096, 1.0 / 4096}, big = {kRound, kRound};
  const Lanes hi = {kMaxSample, kMaxSample}, lo = -hi, zero = {0, 0};
  Ints acc = {0, 0};
  size_t i = 0;
  for (; i + 2 <= n; i += 2) {
    const Lanes x = {static_cast<double>(ref[i]), static_cast<double>(ref[i + 1])};
    Lanes p = ((b * x + half) * scale + big) - big;
    p = p > hi ? hi : p;
    p = p < lo ? lo : p;
    const Lanes e = Lanes{static_cast<double>(r1[i]), static_cast<double>(r1[i + 1])} - p;
    Lanes u = e < zero ? -2 * e - 1 : 2 * e;
    u = u < half ? half : u;
    Ints bitsu;
    std::memcpy(&bitsu, &u, sizeof u);
    acc += bitsu >> 52;
  }
  int64_t after = static_cast<int64_t>(acc[0] + acc[1]) - 1022 * static_cast<int64_t>(i);
  for (; i < n; ++i) after += bit_length(r1[i] - cross_predict(beta, ref[i]));
  return after;
}

// Vectors of W lanes for residual_bits (a template's vector_size cannot depend on its
// parameter): doubles, their bit patterns, and the int32 references.
template <int W>
struct CrossLanes;
template <>
struct CrossLanes<2> {
  typedef double D __attribute__((vector_size(16)));
  typedef unsigned long long U __attribute__((vector_size(16)));
  typedef int32_t I __attribute__((vector_size(8)));
};
template <>
struct CrossLanes<4> {
  typedef double D __attribute__((vector_size(32)));
  typedef unsigned long long U __attribute__((vector_size(32)));
  typedef int32_t I __attribute__((vector_size(16)));
};

// residual_bits's loop, W samples a step over the first samples: returns how many it took,
// their summed bit lengths in *bits (a sum of integers: the width changes nothing). Always
// inlined, so that it is compiled for its caller's target.
template <int W>
__attribute__((always_inline)) inline size_t residual_bits_lanes(const double* t,
                                                                 const int32_t* ref, size_t n,
                                                                 int32_t beta, int64_t* bits) {
  typedef typename CrossLanes<W>::D D;
  typedef typename CrossLanes<W>::U U;
  typedef typename CrossLanes<W>::I I;
  const double kRound = 6755399441055744.0;  // 1.5 2^52
  D b = {}, h = {}, big = {};  // every lane set below (initialised for -Wmaybe-uninitialized)
  U mag = {}, acc = {};
  for (int l = 0; l < W; ++l) {
    b[l] = static_cast<double>(beta) / 4096;
    h[l] = 1.0 / 8192;
    big[l] = kRound;
    mag[l] = ~(uint64_t{1} << 63);
    acc[l] = 0;
  }
  size_t i = 0;
  for (; i + W <= n; i += W) {
    I q;
    std::memcpy(&q, ref + i, sizeof q);
    const D x = __builtin_convertvector(q, D);
    const D p = ((b * x + h) + big) - big;
    D tt;
    std::memcpy(&tt, t + i, sizeof tt);
    const D d = (p + p) - tt;
    U db;
    std::memcpy(&db, &d, sizeof d);
    acc += (db & mag) >> 52;
  }
  uint64_t sum = 0;
  for (int l = 0; l < W; ++l) sum += acc[l];
  *bits = static_cast<int64_t>(sum) - 1022 * static_cast<int64_t>(i);
  return i;
}

#if defined(__x86_64__) || defined(__i386__)
__attribute__((target("avx2"))) size_t residual_bits_avx2(const double* t, const int32_t* ref,
                                                          size_t n, int32_t beta, int64_t* bits) {
  return residual_bits_lanes<4>(t, ref, n, beta, bits);
}
#endif

// The same sum when no prediction can reach the clamp (|p| <= kMaxSample for every ref[i]),
// from t[i] = 2 r1[i] + 1/2. With p as above (beta ref / 2^12 + 2^-13 is exact, as beta ref +
// 1/2 is) and e = r1[i] - p: 2 p - t[i] = -(2 e + 1/2), whose magnitude is u + 1/2 for the
// zig-zag u of e (2 e + 1/2 for e >= 0, (-2 e - 1) + 1/2 for e < 0), an exact double. u + 1/2
// stays below the next power of two above u, so its biased exponent - 1022 is the bit length
// of u, and 0 for u = 0 (1/2): one subtraction, a mask and a shift a sample.
int64_t residual_bits(const double* t, const int32_t* r1, const int32_t* ref, size_t n,
                      int32_t beta) {
  size_t i = 0;
  int64_t wide = 0, narrow = 0;
#if defined(__x86_64__) || defined(__i386__)
  if (avx2_enabled()) i = residual_bits_avx2(t, ref, n, beta, &wide);  // analog_simd.h
#endif
  i += residual_bits_lanes<2>(t + i, ref + i, n - i, beta, &narrow);
  int64_t after = wide + narrow;
  for (; i < n; ++i) after += bit_length(r1[i] - cross_predict(beta, ref[i]));
  return after;
}

// e[k] = sum over i of r1[i] p[k][i] for k < K, each in increasing i, two sums a vector.
template <size_t K>
void cross_sums(const int32_t* r1, const int32_t* const* p, size_t n, double* e) {
  Lanes acc[K / 2] = {};
  for (size_t i = 0; i < n; ++i) {
    const double a = r1[i];
    for (size_t k = 0; k < K / 2; ++k)
      acc[k] += a * Lanes{static_cast<double>(p[2 * k][i]), static_cast<double>(p[2 * k + 1][i])};
  }
  for (size_t k = 0; k < K; ++k) e[k] = acc[k / 2][k % 2];
}

// Writes t = 2 r1 + 1/2 for residual_bits and returns sum bit_length(r1): residual_bits's with
// p = 0, |t| = u + 1/2 (two samples a step); *nonzero tells whether any r1 is not 0.
inline int64_t residual_terms(const int32_t* r1, size_t n, double* t, bool* nonzero) {
  typedef int32_t Pair __attribute__((vector_size(8)));
  const Lanes two = {2.0, 2.0}, half = {0.5, 0.5};
  const Ints mag = {~(uint64_t{1} << 63), ~(uint64_t{1} << 63)};
  Ints acc = {0, 0};
  Pair any = {0, 0};
  size_t i0 = 0;
  for (; i0 + 2 <= n; i0 += 2) {
    Pair q;
    std::memcpy(&q, r1 + i0, sizeof q);
    any |= q;
    const Lanes ti = two * __builtin_convertvector(q, Lanes) + half;
    std::memcpy(t + i0, &ti, sizeof ti);
    Ints tb;
    std::memcpy(&tb, &ti, sizeof ti);
    acc += (tb & mag) >> 52;
  }
  int64_t base = static_cast<int64_t>(acc[0] + acc[1]) - 1022 * static_cast<int64_t>(i0);
  bool nz = any[0] != 0 || any[1] != 0;
  for (size_t i = i0; i < n; ++i) {
    t[i] = 2.0 * r1[i] + 0.5;
    nz |= r1[i] != 0;
    base += bit_length(r1[i]);
  }
  *nonzero = nz;
  return base;
}

// Whether reference d exists and has n samples.
inline bool usable_ref(const std::vector<const std::vector<int32_t>*>& refs, size_t d, size_t n) {
  return refs[d] && refs[d]->size() == n;
}

// Cross energies ecrs[d] = sum r1[i] refs[d][i], up to eight references a pass in two-lane vectors
// (each lane the same sum, in the same order, as one reference alone; a missing reference reads
// zeros): each sum is a chain of dependent additions, so four chains a pass cost little more
// than two. ecrs has kPass - 1 more entries than refs.
constexpr size_t kPass = 8;
inline void cross_energies(const int32_t* r1, const std::vector<const std::vector<int32_t>*>& refs,
                           size_t n, std::vector<double>* ecrs) {
  const size_t nr = refs.size();
  std::vector<int32_t> zeros;
  for (size_t d0 = 0; d0 < nr; d0 += kPass) {
    const int32_t* p[kPass];
    for (size_t k = 0; k < kPass; ++k) {
      if (d0 + k < nr && usable_ref(refs, d0 + k, n)) {
        p[k] = refs[d0 + k]->data();
      } else {
        zeros.resize(n, 0);
        p[k] = zeros.data();
      }
    }
    if (nr - d0 > kPass / 2)
      cross_sums<kPass>(r1, p, n, &(*ecrs)[d0]);
    else
      cross_sums<kPass / 2>(r1, p, n, &(*ecrs)[d0]);
  }
}

}  // namespace

double reference_energy(const std::vector<int32_t>& r) {
  double e = 0;
  for (int32_t v : r) e += static_cast<double>(v) * static_cast<double>(v);
  return e;
}

CrossParams choose_cross(const std::vector<int32_t>& r1,
                         const std::vector<const std::vector<int32_t>*>& refs,
                         const std::vector<double>& ref_energy, double min_gain_bits) {
  CrossParams best;
  const size_t n = r1.size();
  // t = 2 r1 + 1/2 for residual_bits; r1 all zero (no energy) takes no reference.
  // Bits saved = sum bit_length(r1) - sum bit_length(r1 - prediction), the first sum shared.
  // t in a per-thread buffer (every entry is written below), not a vector zeroed per channel.
  double* t = scratch<double, Scratch::kCrossTerms>(n);
  bool nonzero = false;
  const int64_t base = residual_terms(r1.data(), n, t, &nonzero);
  if (!nonzero) return best;
  double best_bits = min_gain_bits;
  // The references' own energies were computed once, in the same order as the cross energies.
  const size_t nr = refs.size();
  std::vector<double> ecrs(nr + kPass - 1, 0.0);
  cross_energies(r1.data(), refs, n, &ecrs);
  for (size_t d = 0; d < nr; ++d) {
    if (!usable_ref(refs, d, n)) continue;
    const std::vector<int32_t>* ref = refs[d];
    const double ecr = ecrs[d], err = ref_energy[d];
    if (err <= 0) continue;
    const double beta = std::round(ecr / err * (1 << kCrossShift));
    if (!(std::fabs(beta) < kMaxBeta) || beta == 0) continue;
    // Bits saved, measured as the change of the summed bit lengths of the residuals.
    const int32_t q = static_cast<int32_t>(beta);
    // No prediction reaches the clamp when |beta| max|ref| + 2^11 <= 2^40; max|ref| <=
    // sqrt(err) (err the sum of ref^2, computed within a relative 2^-30 of it here).
    const bool unclamped =
        std::fabs(beta) * (std::sqrt(err) * 1.001 + 1) + 4096 <= 1099511627776.0;  // 2^40
    const int64_t after = unclamped ? residual_bits(t, r1.data(), ref->data(), n, q)
                                    : residual_bits_clamped(r1.data(), ref->data(), n, q);
    const int64_t saved = base - after;
    const double bits = static_cast<double>(saved) - 20;
    if (bits > best_bits) {
      best_bits = bits;
      best.distance = static_cast<int>(d) + 1;
      best.beta = static_cast<int32_t>(beta);
    }
  }
  return best;
}

}  // namespace analog
}  // namespace capz
