#include "coding/analog/analog_lpc.h"

#include <algorithm>
#include <cmath>
#include <cstring>

#include "coding/analog/analog_scratch.h"
#include "coding/analog/analog_simd.h"
#include "coding/entropy.h"

namespace capz {
namespace analog {

namespace {

typedef double Lanes __attribute__((vector_size(16)));
Lanes load(const double* p) {
  Lanes v;
  std::memcpy(&v, p, sizeof v);
  return v;
}

// The Tukey(0.5) window of n samples: each end tapers over a quarter. Blocks mostly share a
// few lengths (whole blocks, a window's last block), so the last four windows computed are
// kept (per thread), the oldest replaced first.
const std::vector<double>& tukey(size_t n) {
  constexpr int kKept = 4;
  thread_local std::vector<double> g[kKept];
  thread_local size_t next = 0;
  for (const std::vector<double>& w : g)
    if (w.size() == n && n > 0) return w;
  std::vector<double>& w = g[next];
  next = (next + 1) % kKept;
  w.resize(n);
  const double taper = 0.25 * static_cast<double>(n);
  for (size_t i = 0; i < n; ++i) {
    const double d = std::min<double>(static_cast<double>(i), static_cast<double>(n - 1 - i));
    w[i] = d < taper ? 0.5 - 0.5 * std::cos(M_PI * (d + 0.5) / taper) : 1.0;
  }
  return w;
}

#if defined(__x86_64__) || defined(__i386__)
#define CAPZ_ANALOG_AVX2 1
typedef double Quad __attribute__((vector_size(32)));
__attribute__((target("avx2"))) inline Quad load4(const double* p) {
  Quad v;
  std::memcpy(&v, p, sizeof v);
  return v;
}

// autocorrelation's 33 lags (max_lag 32) in one pass of four-lane vectors, from its reversed
// window wr (n values, then at least 35 zeros). Each lag's sum adds w[i] w[i - k] for i = 0, 1,
// ... in order: the terms for i < k read zeros and add +-0 to a +0 sum, so each is the plain
// loop's, bit for bit (a product, then a sum: no fused multiply-add in this target).
__attribute__((target("avx2"))) void autocorrelation33_avx2(const double* wr, size_t n, double* r) {
  Quad a[9] = {};
  const double* base = wr + n - 1;
  for (size_t i = 0; i < n; ++i) {
    const double wi = wr[n - 1 - i];
    const double* p = base - i;
    for (int l = 0; l < 9; ++l) a[l] += wi * load4(p + 4 * l);
  }
  for (int k = 0; k <= 32; ++k) r[k] = a[k / 4][k % 4];
}

// lpc_residuals four samples a step: lane j sums c[k] x[i + j - padded + k] over k, exact
// integers below 2^53 in any order (LpcKernel), so each is predict()'s sum.
__attribute__((target("avx2"))) size_t lpc_residuals_avx2(const LpcKernel& lpc, const int32_t* x,
                                                          const double* xd, size_t n, int32_t* r) {
  const double* c = lpc.coefficients();
  const int padded = lpc.padded(), shift = lpc.shift();
  size_t i = 0;
  for (; i + 4 <= n; i += 4) {
    const double* xi = xd + i - padded;
    Quad a0 = {0, 0, 0, 0}, a1 = {0, 0, 0, 0};
    for (int k = 0; k < padded; k += 2) {
      a0 += c[k] * load4(xi + k);
      a1 += c[k + 1] * load4(xi + k + 1);
    }
    const Quad a = a0 + a1;
    for (int j = 0; j < 4; ++j) {
      int64_t s = (static_cast<int64_t>(a[j]) >> shift) + lpc.constant();
      s = s > kMaxSample ? kMaxSample : s < -kMaxSample ? -kMaxSample : s;
      r[i + j] = static_cast<int32_t>(x[i + j] - s);
    }
  }
  return i;
}
#endif

}  // namespace

void lpc_residuals(const LpcKernel& lpc, const int32_t* x, const double* xd, size_t n, int32_t* r) {
  size_t i = 0;
#ifdef CAPZ_ANALOG_AVX2
  if (avx2_enabled()) i = lpc_residuals_avx2(lpc, x, xd, n, r);
#endif
  for (; i < n; ++i) r[i] = static_cast<int32_t>(x[i] - lpc.predict(xd + i));
}

std::vector<double> autocorrelation(const int32_t* x, size_t n, int max_lag) {
  // w[i] = g[i] x[i], kept reversed (wr[j] = w[n - 1 - j]) and followed by zeros, so that one
  // two-lane load at wr + n - 1 - i + k is (w[i - k], w[i - k - 1]): lags k and k + 1 side by
  // side. Each lag's sum still adds w[i] w[i - k] for i = k, k + 1, ... in order (the zeros
  // before a lag's first term add +-0 to a +0 sum), so every r[k] is bit for bit the plain
  // loop's. Each lag's sum is one chain of dependent additions, so a pass costs about n
  // addition latencies however many lags it carries (up to the adder's throughput): sixteen
  // lags a pass, and a group's one or two leftover lags (order 32 has 33) ride along in the
  // pass before as a ninth lane pair.
  constexpr int kGroup = 16;
  const std::vector<double>& g = tukey(n);
  // A per-thread buffer, not allocated and zeroed per block: every entry read is written here.
  const size_t m = n + 2 * kGroup + 4;  // zeros after: kGroup + 2, or 35 (AVX2)
  double* wr = scratch<double, Scratch::kAutocorrelation>(m);
  for (size_t i = 0; i < n; ++i) wr[n - 1 - i] = g[i] * x[i];
  std::fill(wr + n, wr + m, 0.0);
  std::vector<double> r(static_cast<size_t>(max_lag) + 1, 0.0);
#ifdef CAPZ_ANALOG_AVX2
  if (max_lag == 32 && avx2_enabled()) {
    autocorrelation33_avx2(wr, n, r.data());
    return r;
  }
#endif
  for (int k0 = 0; k0 <= max_lag; k0 += kGroup) {
    int lanes = std::min(kGroup, max_lag + 1 - k0);
    const double* base = wr + n - 1 + k0;
    if (lanes == 1) {
      double a = 0;
      for (size_t i = static_cast<size_t>(k0); i < n; ++i) a += wr[n - 1 - i] * *(base - i);
      r[k0] = a;
      continue;
    }
    Lanes a[kGroup / 2 + 1] = {};
    if (lanes == kGroup && max_lag + 1 - k0 <= kGroup + 2 && max_lag + 1 - k0 > kGroup) {
      // The last one or two lags join this pass: their terms for i < k0 + 16 read zeros.
      lanes = max_lag + 1 - k0;
      for (size_t i = static_cast<size_t>(k0); i < n; ++i) {
        const double wi = wr[n - 1 - i];
        const double* p = base - i;
        for (int l = 0; l < kGroup / 2 + 1; ++l) a[l] += wi * load(p + 2 * l);
      }
      for (int l = 0; l < lanes; ++l) r[k0 + l] = a[l / 2][l % 2];
      break;
    }
    if (lanes > 8) {
      for (size_t i = static_cast<size_t>(k0); i < n; ++i) {
        const double wi = wr[n - 1 - i];
        const double* p = base - i;
        for (int l = 0; l < kGroup / 2; ++l) a[l] += wi * load(p + 2 * l);
      }
    } else {
      for (size_t i = static_cast<size_t>(k0); i < n; ++i) {
        const double wi = wr[n - 1 - i];
        const double* p = base - i;
        for (int l = 0; l < 4; ++l) a[l] += wi * load(p + 2 * l);
      }
    }
    for (int l = 0; l < lanes; ++l) r[k0 + l] = a[l / 2][l % 2];
  }
  return r;
}

int levinson(const std::vector<double>& r, int order, std::vector<std::vector<double>>* a_by_order,
             std::vector<double>* err) {
  err->assign(1, r[0]);
  a_by_order->assign(1, {});
  if (!(r[0] > 0)) return 0;
  std::vector<double> a, prev;
  double e = r[0];
  for (int m = 1; m <= order; ++m) {
    double acc = r[m];
    for (int j = 0; j < m - 1; ++j) acc -= a[j] * r[m - 1 - j];
    const double k = acc / e;
    prev = a;
    a.resize(m);
    a[m - 1] = k;
    for (int j = 0; j < m - 1; ++j) a[j] = prev[j] - k * prev[m - 2 - j];
    e *= 1 - k * k;
    if (!(e > 0) || !std::isfinite(k)) return m - 1;
    err->push_back(e);
    a_by_order->push_back(a);
  }
  return order;
}

LpcParams quantise_lpc(const double* a, int order, int precision) {
  LpcParams p;
  p.order = order;
  double cmax = 0;
  for (int j = 0; j < order; ++j) cmax = std::max(cmax, std::fabs(a[j]));
  if (order == 0 || cmax == 0) {
    p.order = 0;
    return p;
  }
  int log2c;
  std::frexp(cmax, &log2c);  // cmax < 2^log2c
  p.shift = std::min(kMaxLpcShift, std::max(0, precision - log2c));
  const double lim = std::ldexp(1.0, precision) - 1;
  double carry = 0;
  for (int j = 0; j < order; ++j) {
    const double v = a[j] * std::ldexp(1.0, p.shift) + carry;
    const double q = std::max(-lim, std::min(lim, std::round(v)));
    carry = v - q;
    p.q.push_back(static_cast<int32_t>(q));
  }
  return p;
}

double coefficient_bits(int64_t q) {
  return 2 + 2 * std::log2(1.0 + static_cast<double>(q < 0 ? -q : q));
}
double coefficient_bits(const LpcParams& p) {
  double bits = p.constant != 0 ? coefficient_bits(p.constant) : 0;
  for (int32_t q : p.q) bits += coefficient_bits(q);
  return bits;
}

LpcParams choose_lpc(const int32_t* x, size_t n, double* full_bits) {
  if (full_bits) *full_bits = 0;
  const int max_order = static_cast<int>(std::min<size_t>(kMaxLpcOrder, n / 8));
  if (max_order < 1) return LpcParams();
  const std::vector<double> r = autocorrelation(x, n, max_order);
  std::vector<std::vector<double>> a;
  std::vector<double> err;
  const int reached = levinson(r, max_order, &a, &err);
  // Estimated bits: n/2 log2(error per sample) for the residual, plus the coefficients.
  const double floor_err = 0.1 * static_cast<double>(n);  // below a tenth of a count: no gain
  int best = 0;
  double best_bits = 0;
  for (int m = 0; m <= reached; ++m) {
    const double e = std::max(err[m], floor_err);
    const double bits = 0.5 * static_cast<double>(n) * std::log2(e / static_cast<double>(n)) +
                        m * (kLpcPrecision + 2.0);
    if (m == 0 || bits < best_bits) {
      best = m;
      best_bits = bits;
    }
  }
  if (best == 0) return LpcParams();
  // The precision: coarser coefficients cost fewer bits and add d' R d to the error.
  const std::vector<double>& ab = a[best];
  const double e0 = std::max(err[best], floor_err);
  auto price = [&](const LpcParams& p) {
    const double unit = std::ldexp(1.0, -p.shift);
    double d[kMaxLpcOrder];
    for (int j = 0; j < best; ++j) d[j] = p.q[j] * unit - ab[j];
    double added = 0;
    for (int j = 0; j < best; ++j) {
      double row = d[j] * r[0];
      for (int k = 0; k < j; ++k) row += 2 * d[k] * r[j - k];
      added += d[j] * row;
    }
    return 0.5 * static_cast<double>(n) * std::log2((e0 + std::max(0.0, added)) / e0) +
           coefficient_bits(p);
  };
  LpcParams chosen = quantise_lpc(ab.data(), best, kLpcPrecision);
  if (full_bits) *full_bits = coefficient_bits(chosen);
  double chosen_bits = price(chosen);
  for (int precision = kLpcPrecision - 1; precision >= kMinLpcPrecision; --precision) {
    LpcParams p = quantise_lpc(ab.data(), best, precision);
    if (p.order == 0) continue;
    const double bits = price(p);
    if (bits < chosen_bits) {
      chosen_bits = bits;
      chosen = std::move(p);
    }
  }
  return chosen;
}

namespace {

// Token histogram of residual streams (token_of of the zig-zag, coding/entropy.h), kept by
// bin = token + 2 except for the value 0 (token 0), which lands in bin 0: for an integer v with
// |v| < 2^51 and u its zig-zag, |2 v + 1/2| = u + 1/2 exactly, and for u >= 1 its biased
// exponent is 1023 + floor(log2 u) with the mantissa's top bit the bit below u's top one, so
// its top 13 bits (>> 51) are 2046 + token_of(u) (u = 1 gives 1.5: 2047); u = 0 gives 1/2,
// 2044. The bin is those bits - 2044. Two copies (even and odd samples), so that equal tokens in
// a row do not wait on each other's counter.
struct TokenCounts {
  static constexpr int kBins = 66;
  uint32_t c[2][kBins] = {};
  void add(int lane, int64_t bin) { ++c[lane][bin]; }
  // Order-0 entropy of the tokens of n values plus their raw bits (TokenTally::bits).
  double bits(size_t n) const {
    TokenTally t;
    add_to(&t);
    return t.bits(n);
  }
  void add_to(TokenTally* t) const {
    for (int b = 0; b < kBins; ++b) t->bins[b] += c[0][b] + c[1][b];
  }
};

typedef long long Bins __attribute__((vector_size(16)));
// The bins of two integer-valued doubles (above), as two-lane vectors.
inline Bins token_bins(Lanes v) {
  const Lanes half = {0.5, 0.5};
  const Lanes t = (v + v) + half;
  Bins b;
  std::memcpy(&b, &t, sizeof b);
  const Bins mag = {0x7FFFFFFFFFFFFFFF, 0x7FFFFFFFFFFFFFFF}, base = {2044, 2044};
  return ((b & mag) >> 51) - base;
}
inline Bins token_bins(int64_t v) {
  const Lanes x = {static_cast<double>(v), 0.0};
  return token_bins(x);
}

// 2 x1 - x2 clamped to the sample range: the second difference's prediction.
inline int64_t second_prediction(int64_t x1, int64_t x2) {
  const int64_t p2 = 2 * x1 - x2;
  return p2 > kMaxSample ? kMaxSample : p2 < -kMaxSample ? -kMaxSample : p2;
}

// The mean of the block's n > 0 samples, rounded: a constant prediction.
int32_t block_level(const int32_t* x, size_t n) {
  int64_t sum = 0;
  for (size_t i = 0; i < n; ++i) sum += x[i];
  return static_cast<int32_t>(std::llround(static_cast<double>(sum) / static_cast<double>(n)));
}

// The token histograms of the residuals r, of the fixed predictors 0, x[i-1] and
// 2 x[i-1] - x[i-2] (LPC orders 0, 1, 2 with exact coefficients, so their residuals are these)
// and of the constant, in one pass, two samples a step on doubles (all exact integers below
// 2^31).
inline void count_candidate_tokens(const int32_t* x, const double* xd, size_t n, const int32_t* r,
                                   int32_t constant, TokenCounts* counts) {
  const Lanes hi = {kMaxSample, kMaxSample}, lo = -hi;
  const Lanes c = {static_cast<double>(constant), static_cast<double>(constant)};
  size_t i = 0;
  for (; i + 2 <= n; i += 2) {
    const Lanes x0 = load(xd + i), x1 = load(xd + i - 1), x2 = load(xd + i - 2);
    Lanes p2 = (x1 + x1) - x2;
    p2 = p2 > hi ? hi : p2;
    p2 = p2 < lo ? lo : p2;
    const Lanes ri = {static_cast<double>(r[i]), static_cast<double>(r[i + 1])};
    const Bins b[5] = {token_bins(ri), token_bins(x0), token_bins(x0 - x1), token_bins(x0 - p2),
                       token_bins(x0 - c)};
    for (int k = 0; k < 5; ++k) {
      counts[k].add(0, b[k][0]);
      counts[k].add(1, b[k][1]);
    }
  }
  for (; i < n; ++i) {
    const int64_t x0 = x[i], x1 = static_cast<int64_t>(xd[i - 1]);
    const int64_t x2 = static_cast<int64_t>(xd[i - 2]);
    counts[0].add(0, token_bins(r[i])[0]);
    counts[1].add(0, token_bins(x0)[0]);
    counts[2].add(0, token_bins(x0 - x1)[0]);
    counts[3].add(0, token_bins(x0 - second_prediction(x1, x2))[0]);
    counts[4].add(0, token_bins(x0 - constant)[0]);
  }
}

// The residuals into r of fixed predictor pick (0 to 3, as in choose_block_predictor's fixed[];
// LpcKernel of it predicts exactly these).
inline void fixed_residuals(const int32_t* x, const double* xd, size_t n, int pick,
                            int32_t constant, int32_t* r) {
  int64_t x1 = static_cast<int64_t>(xd[-1]), x2 = static_cast<int64_t>(xd[-2]);
  for (size_t i = 0; i < n; ++i) {
    const int64_t x0 = x[i];
    const int64_t p = pick == 1 ? x1 : pick == 2 ? second_prediction(x1, x2) : constant;
    r[i] = static_cast<int32_t>(x0 - p);
    x2 = x1;
    x1 = x0;
  }
}

}  // namespace

// Order-0 entropy of the tokens of n values plus their raw bits (token / 2 - 1 for tokens
// >= 4), the sum over tokens in increasing order.
double TokenTally::bits(size_t n) const {
  uint64_t raw = 0;
  uint32_t count[64];
  for (int t = 0; t < 64; ++t) {
    count[t] = bins[t == 0 ? 0 : t + 2];
    if (t >= 4) raw += static_cast<uint64_t>(count[t]) * static_cast<uint64_t>(t / 2 - 1);
  }
  double total = static_cast<double>(raw);
  const double dn = static_cast<double>(n);
  for (int t = 0; t < 64; ++t)
    if (count[t]) total -= count[t] * std::log2(count[t] / dn);
  return total;
}
void TokenTally::add(int32_t v) {
  ++bins[token_bins(v)[0]];
}
void TokenTally::remove(int32_t v) {
  --bins[token_bins(v)[0]];
}

double token_cost_bits(const int32_t* r, size_t n) {
  // Two samples a step, even and odd ones in their own copy of the histogram (bits() adds the
  // copies' counts: the same integers).
  TokenCounts h;
  typedef int32_t Pair __attribute__((vector_size(8)));
  size_t i = 0;
  for (; i + 2 <= n; i += 2) {
    Pair q;
    std::memcpy(&q, r + i, sizeof q);
    const Bins b = token_bins(__builtin_convertvector(q, Lanes));
    h.add(0, b[0]);
    h.add(1, b[1]);
  }
  if (i < n) h.add(0, token_bins(r[i])[0]);
  return h.bits(n);
}

LpcParams choose_block_predictor(const int32_t* x, const double* xd, size_t n, int32_t* r,
                                 bool allow_constant, TokenTally* tally) {
  // choose_lpc's predictor, its residuals into r. It is weighed against the fixed predictors
  // with the cost of its full-precision coefficients: the coarser ones choose_lpc may pick
  // lower its price but not its advantage over them (priced at their own cost, they took
  // the LPC where a first difference codes smaller: TYPE-2.C3D's resting force channels,
  // whose residuals of +-1 the adaptive contexts code well below their order-0 entropy).
  double full_bits = 0;
  LpcParams best = choose_lpc(x, n, &full_bits);
  lpc_residuals(LpcKernel(best), x, xd, n, r);
  // With allow_constant, the block's mean, rounded, as a constant prediction: residuals of one
  // sign no longer waste the zig-zag's sign bit on a level far from 0 (noise around an offset,
  // rank indices). The median codes 0.006% smaller on the shared takes and costs a selection.
  LpcParams level;
  if (allow_constant && n > 0) level.constant = block_level(x, n);
  TokenCounts counts[5];
  count_candidate_tokens(x, xd, n, r, level.constant, counts);
  double best_bits = counts[0].bits(n) + full_bits;
  // The fixed predictors and the constant, in the order of counts[1..4]; with a constant of 0
  // (none allowed) the last is the first with the same histogram and cost, never picked.
  LpcParams fixed[4];
  fixed[1].order = 1;  // x[i-1]
  fixed[1].shift = 13;
  fixed[1].q = {1 << 13};
  fixed[2].order = 2;  // 2 x[i-1] - x[i-2]
  fixed[2].shift = 12;
  fixed[2].q = {1 << 13, -(1 << 12)};
  fixed[3] = level;
  int pick = -1;
  for (int k = 0; k < 4; ++k) {
    const double bits = counts[1 + k].bits(n) + coefficient_bits(fixed[k]);
    if (bits < best_bits) {
      best_bits = bits;
      pick = k;
    }
  }
  if (tally) counts[1 + pick].add_to(tally);  // pick = -1: choose_lpc's
  if (pick < 0) return best;
  fixed_residuals(x, xd, n, pick, fixed[pick].constant, r);
  return fixed[pick];
}

}  // namespace analog
}  // namespace capz
