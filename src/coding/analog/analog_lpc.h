// Linear prediction of integer analog channels (docs/format-drafts/analog.md section A.3).
//
// Analysis (encoder only, double arithmetic, never stored): autocorrelation of a Tukey-windowed
// block, Levinson-Durbin recursion up to kMaxLpcOrder, order chosen from the recursion's
// prediction errors plus the coefficients' cost, coefficients quantised to `precision` bits
// with a right shift. Synthesis (both sides, integer arithmetic, bit exact everywhere):
//   p = clamp((sum_j q[j] * x[i-1-j]) >> shift, -kMaxSample, kMaxSample)   (int64, floor shift)
// where samples before the channel's first are 0.
#pragma once

#include <cstddef>
#include <cstdint>
#include <vector>

namespace capz {
namespace analog {

constexpr int kMaxLpcOrder = 32;
constexpr int kMaxLpcShift = 20;
constexpr int kLpcPrecision = 14;        // coefficient magnitude bits, sign excluded
constexpr int32_t kMaxSample = 1 << 28;  // integer samples satisfy |x| <= kMaxSample

// r[0..max_lag] of x[0..n) after a Tukey(0.5) window.
std::vector<double> autocorrelation(const int32_t* x, size_t n, int max_lag);

// Levinson-Durbin on r[0..order]: fills a[0..order) (x[i] ~ sum_j a[j] x[i-1-j]) for the
// highest order reached and err[0..order] with the prediction error power at each order.
// Returns the order reached (it stops early when the error stops being positive).
int levinson(const std::vector<double>& r, int order, std::vector<std::vector<double>>* a_by_order,
             std::vector<double>* err);

struct LpcParams {
  int order = 0;
  int shift = 0;
  std::vector<int32_t> q;  // order coefficients, |q| < 2^kLpcPrecision
};

// Quantises a[0..order) with error feedback so that max |q| < 2^precision.
LpcParams quantise_lpc(const double* a, int order, int precision);

// Chooses the order (0 = no prediction) for block x[0..n) by the estimated cost in bits.
LpcParams choose_lpc(const int32_t* x, size_t n);

// Prediction of x[i] from x[i - order .. i) (the caller guarantees i >= order).
inline int64_t lpc_predict(const LpcParams& p, const int32_t* xi) {
  int64_t s = 0;
  for (int j = 0; j < p.order; ++j) s += static_cast<int64_t>(p.q[j]) * xi[-1 - j];
  s >>= p.shift;
  if (s > kMaxSample) s = kMaxSample;
  if (s < -kMaxSample) s = -kMaxSample;
  return s;
}

}  // namespace analog
}  // namespace capz
