// Float channels' encoder (docs/FORMAT.md 9.1): each predictor's coded size estimated, predictor
// 5's coefficients fitted, the smallest kept, and the channel coded; the decoder is
// analog_float.cpp.
#include <algorithm>
#include <cmath>
#include <cstring>
#include <limits>

#include "coding/analog/analog_entropy.h"
#include "coding/analog/analog_float.h"
#include "coding/analog/analog_lpc.h"
#include "coding/analog/analog_repr.h"

namespace capz {
namespace analog {

using namespace float9;

namespace {

// Predictor 5's coefficients for x: Levinson-Durbin on the autocorrelation, the order by
// n/2 log2(error) plus 16 bits a coefficient, quantised to |q| < 2^15. False when x gives no
// usable fit.
bool fit_float_lpc(const std::vector<double>& x, FloatPlan* plan) {
  const size_t n = x.size();
  const int maxo = static_cast<int>(std::min<size_t>(kMaxFloatLpcOrder, n / 8));
  if (maxo < 1) return false;
  double r[kMaxFloatLpcOrder + 1];
  for (int k = 0; k <= maxo; ++k) {
    double acc = 0;
    for (size_t i = static_cast<size_t>(k); i < n; ++i) acc += x[i] * x[i - k];
    r[k] = acc;
  }
  if (!(r[0] > 0) || !std::isfinite(r[0])) return false;
  r[0] *= 1.0 + 1e-9;  // a little white noise: a well-conditioned recursion
  std::vector<std::vector<double>> a_by_order;
  std::vector<double> err;
  const int reached = levinson(std::vector<double>(r, r + maxo + 1), maxo, &a_by_order, &err);
  double best_cost = 0.5 * static_cast<double>(n) * std::log2(err[0]);
  int best = 0;
  for (int m = 1; m <= reached; ++m) {
    const double cost = 0.5 * static_cast<double>(n) * std::log2(err[m]) + 16.0 * m;
    if (cost < best_cost) {
      best_cost = cost;
      best = m;
    }
  }
  if (best == 0) return false;
  const std::vector<double>& best_a = a_by_order[best];  // best_a[j] weighs x[i - 1 - j]
  double maxabs = 0;
  for (int j = 0; j < best; ++j) maxabs = std::max(maxabs, std::fabs(best_a[j]));
  if (!(maxabs > 0) || !std::isfinite(maxabs)) return false;
  const int shift =
      std::min(kMaxFloatLpcShift,
               static_cast<int>(std::floor(std::log2(((1 << kFloatLpcPrecision) - 1) / maxabs))));
  if (shift < 0) return false;
  plan->predictor = 5;
  plan->order = best;
  plan->shift = shift;
  for (int j = 0; j < best; ++j) {
    const double q = std::nearbyint(std::ldexp(best_a[j], shift));
    if (!(std::fabs(q) < (1 << kFloatLpcPrecision))) return false;  // NaN too
    plan->q[j] = static_cast<int32_t>(q);
  }
  return true;
}

// From this many samples on, the predictors' sizes are estimated on every other run of 32
// samples (runs, not every other sample: a channel holding each value for two samples would
// look like one that never holds).
constexpr size_t kCostSubsample = 1024;
inline size_t next_sample(size_t i, size_t stride) {
  return stride == 1 || (i + 1) % 32 ? i + 1 : i + 33;
}

// An estimate of 9.1's coding of residuals, in bits: the raw bits, plus the order-0 entropies of
// the bit lengths and of the top bits under each bit length (what the models learn).
class Cost9 {
 public:
  void add(int64_t d) {
    const uint64_t u = zigzag64(d);
    const int nb = u == 0 ? 0 : 64 - __builtin_clzll(u);
    ++nb_[nb];
    lengths_ += static_cast<uint64_t>(nb);
    if (nb < 2) return;
    const int below = nb - 1, k = below < 4 ? below : 4;
    raw_ += static_cast<uint64_t>(below - k);
    ++top_[nb][(u >> (below - k)) & 15];
  }
  double bits() const {
    double b = static_cast<double>(raw_) + entropy(nb_, 65);
    for (int nb = 2; nb < 65; ++nb)
      if (nb_[nb]) b += entropy(top_[nb], 16, nb_[nb]);
    return b;
  }
  // The summed bit lengths (the estimate 4.2.7 compares between kinds).
  uint64_t lengths() const { return lengths_; }

 private:
  // sum c log2(total / c) = total log2 total - sum c log2 c.
  static double entropy(const uint32_t* c, int m, uint32_t total = 0) {
    if (!total)
      for (int i = 0; i < m; ++i) total += c[i];
    if (total == 0) return 0;
    double s = 0;
    for (int i = 0; i < m; ++i)
      if (c[i] > 1) s += c[i] * std::log2(static_cast<double>(c[i]));
    return total * std::log2(static_cast<double>(total)) - s;
  }
  uint32_t nb_[65] = {};
  uint32_t top_[65][16] = {};
  uint64_t raw_ = 0, lengths_ = 0;
};

// A predictor's estimated size in bits, and its residuals' summed bit lengths, both over the
// samples next_sample visits (each predicted from the samples before it) times stride.
struct Estimate {
  double bits;
  uint64_t lengths;
};
Estimate scaled(const Cost9& c, size_t stride, double side) {
  return {c.bits() * static_cast<double>(stride) + side, c.lengths() * stride};
}

// The estimate for predictors 2-4, one loop each (predict9 without its switch).
// The ordered pattern of v (ord32 widened, or ord64): residual(v, p) is ord(v) - ord(p), as a
// signed difference for float32, wrapping for float64.
inline uint64_t ord_of(double v, bool f32) {
  return f32 ? ordered_f32(v) : ordered_bits(bits_of(v));
}
inline int64_t ord_diff(uint64_t ov, uint64_t op, bool f32) {
  return f32 ? static_cast<int64_t>(ov) - static_cast<int64_t>(op) : static_cast<int64_t>(ov - op);
}

// The estimates of predictors 2, 3 and 4 in one pass (each sample's pattern computed once).
void simple_costs(const std::vector<double>& x, bool f32, size_t stride, Estimate out[3]) {
  Cost9 c[3];
  const size_t n = x.size();
  const uint64_t zero = ord_of(0.0, f32);
  for (size_t i = 0; i < n; i = next_sample(i, stride)) {
    const double a = i > 0 ? x[i - 1] : 0;
    double p = a + (a - (i > 1 ? x[i - 2] : 0));
    if (f32) p = round_to_float32(p);
    const uint64_t ov = ord_of(x[i], f32);
    c[0].add(ord_diff(ov, ord_of(a, f32), f32));
    c[1].add(ord_diff(ov, ord_of(p, f32), f32));
    c[2].add(ord_diff(ov, zero, f32));
  }
  for (int k = 0; k < 3; ++k) out[k] = scaled(c[k], stride, 0);
}

// Predictor 5's estimate.
Estimate lpc_cost(const std::vector<double>& x, const FloatPlan& plan, bool f32, size_t stride) {
  Cost9 c;
  const double scale = lpc_scale(plan);
  for (size_t i = 0; i < x.size(); i = next_sample(i, stride))
    c.add(residual(x[i], predict9(plan, scale, x.data(), i, f32), f32));
  return scaled(c, stride, 16.0 * (plan.order + 1));
}

}  // namespace

FloatPlan choose_float_plan9(const std::vector<double>& x, bool f32, uint64_t* bits) {
  FloatPlan plans[4];
  Estimate est[4];
  int m = 3;
  for (int p = 2; p <= 4; ++p) plans[p - 2].predictor = p;
  const size_t stride = x.size() >= kCostSubsample ? 2 : 1;
  simple_costs(x, f32, stride, est);
  if (fit_float_lpc(x, &plans[m])) {
    est[m] = lpc_cost(x, plans[m], f32, stride);
    ++m;
  }
  int best = 0;
  for (int k = 1; k < m; ++k)
    if (est[k].bits < est[best].bits) best = k;
  if (bits) *bits = est[best].lengths;
  return plans[best];
}

__attribute__((flatten)) bool encode_float_channel(const std::vector<double>& x, bool f32,
                                                   const FloatPlan& plan, IntEncoder::Cursor* out,
                                                   size_t limit) {
  IntEncoder::Cursor c = *out;
  IntEncoder::Cursor* enc = &c;
  const size_t n = x.size();
  enc->put(static_cast<uint32_t>(plan.predictor), kParamContext);
  if (plan.predictor == 5) {
    enc->put(static_cast<uint32_t>(plan.order), kParamContext);
    enc->put(static_cast<uint32_t>(plan.shift), kParamContext);
    for (int j = 0; j < plan.order; ++j) enc->put_signed(plan.q[j], kCoefContext);
  }
  const double scale = lpc_scale(plan);
  int prev_nb = 0;
  for (size_t i0 = 0; i0 < n; i0 += kTrialCheck) {
    if (enc->bytes_out() >= limit) return false;
    const size_t i1 = std::min(n, i0 + kTrialCheck);
    for (size_t i = i0; i < i1; ++i)
      put_float_residual9(enc, &prev_nb,
                          residual(x[i], predict9(plan, scale, x.data(), i, f32), f32));
  }
  *out = c;
  return true;
}

}  // namespace analog
}  // namespace capz
