// Linear prediction of integer analog channels (docs/format-drafts/analog.md section A.3).
//
// Analysis (encoder only, double arithmetic, never stored): autocorrelation of a Tukey-windowed
// block, Levinson-Durbin recursion up to kMaxLpcOrder, order chosen from the recursion's
// prediction errors plus the coefficients' cost, coefficients quantised to `precision` bits
// (kMinLpcPrecision..kLpcPrecision, chosen per block) with a right shift. Synthesis (both sides,
// integer arithmetic, bit exact everywhere):
//   p = clamp((sum_j q[j] * x[i-1-j]) >> shift, -kMaxSample, kMaxSample)   (int64, floor shift)
// where samples before the channel's first are 0; or, order 0 with a constant (FORMAT.md 11.8's
// order code 33), p = constant.
#pragma once

#include <cstddef>
#include <cstdint>
#include <cstring>
#include <vector>

namespace capz {
namespace analog {

constexpr int kMaxLpcOrder = 32;
constexpr int kMaxLpcShift = 20;
constexpr int kLpcPrecision = 14;        // coefficient magnitude bits, sign excluded
constexpr int kMinLpcPrecision = 6;      // the coarsest precision choose_lpc tries
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
  // With order 0: every sample predicted by this constant (|constant| <= kMaxSample; 0 is no
  // prediction). Coded as order kLpcConstantOrder (format 9.1 on).
  int32_t constant = 0;
};
// The order code of a constant predictor (FORMAT.md 11.8).
constexpr int kLpcConstantOrder = kMaxLpcOrder + 1;

// Quantises a[0..order) with error feedback so that max |q| < 2^precision.
LpcParams quantise_lpc(const double* a, int order, int precision);

// Chooses the order (0 = no prediction) for block x[0..n) by the estimated cost in bits, then
// the coefficients' precision: each of kLpcPrecision down to kMinLpcPrecision is priced as
// its coefficients' bits plus n/2 log2((E + dE) / E), E the order's prediction error and
// dE = d' R d the error the quantisation adds (d: quantised minus exact coefficients, R: the
// block's autocorrelation matrix); the cheapest is kept. When full_bits is given, it receives
// coefficient_bits of the kLpcPrecision quantisation (choose_block_predictor weighs the
// fixed predictors against that: see there).
LpcParams choose_lpc(const int32_t* x, size_t n, double* full_bits = nullptr);

// The coefficients' estimated cost: 2 + 2 log2(1 + |q|) bits each (their adaptive coding is
// close to an Elias-gamma code of each); the first, of one value. A constant predictor's
// constant counts as one more such value.
double coefficient_bits(int64_t q);
double coefficient_bits(const LpcParams& p);

// Estimated coded bits of residuals r[0..n): the order-0 entropy of their tokens
// (coding/entropy.h token_of of the zig-zag) plus the raw bits below the tokens.
double token_cost_bits(const int32_t* r, size_t n);

// The token histogram token_cost_bits counts (bins[token + 2]; the value 0 in bins[0]), kept
// across blocks: bits(n) is token_cost_bits of the n residuals counted, the same double.
struct TokenTally {
  static constexpr int kBins = 66;
  uint32_t bins[kBins] = {};
  // One residual in or out (|v| < 2^31).
  void add(int32_t v);
  void remove(int32_t v);
  double bits(size_t n) const;
};

// Chooses the block's predictor by the estimated coded cost (token_cost_bits of its residuals,
// plus coefficient_bits) among choose_lpc's, the first and second differences as LPC of order
// 1 and 2, and none, and writes the chosen one's residuals
// x[i] - p[i] to r[0..n). x: the block's n samples; xd: the same samples as doubles with
// kMaxLpcOrder samples (or zeros) readable before xd[0]. Encoder only: any LpcParams decodes.
// With allow_constant (a 9.1 stream), a constant predictor (the block's mean, rounded) is a
// candidate too. With a tally, the chosen residuals' tokens are added to it (counted already for
// the choice).
LpcParams choose_block_predictor(const int32_t* x, const double* xd, size_t n, int32_t* r,
                                 bool allow_constant = false, TokenTally* tally = nullptr);

// Prediction of x[i] from x[i - order .. i) (the caller guarantees i >= order).
inline int64_t lpc_predict(const LpcParams& p, const int32_t* xi) {
  int64_t s = 0;
  for (int j = 0; j < p.order; ++j) s += static_cast<int64_t>(p.q[j]) * xi[-1 - j];
  s = (s >> p.shift) + p.constant;
  if (s > kMaxSample) s = kMaxSample;
  if (s < -kMaxSample) s = -kMaxSample;
  return s;
}

// lpc_predict for a run of samples, on doubles: |q| < 2^14 and |x| <= 2^28 make every product
// (< 2^42) and partial sum of up to 32 (< 2^47) an integer below 2^53, so the sum is exact in
// any order and two-lane vectors compute it. The samples are read from a double copy with
// kMaxLpcOrder zeros (or earlier samples) before the first.
class LpcKernel {
 public:
  explicit LpcKernel(const LpcParams& p) : order_(p.order), shift_(p.shift), constant_(p.constant) {
    padded_ = (p.order + 3) & ~3;
    for (int k = 0; k < padded_; ++k) {
      // c_[k] multiplies x[i - padded + k]: q[j] with j = padded - 1 - k, zero beyond the order.
      const int j = padded_ - 1 - k;
      c_[k] = j < p.order ? static_cast<double>(p.q[j]) : 0.0;
    }
  }
  int order() const { return order_; }
  // c[k] multiplies x[i - padded + k] (k < padded, a multiple of 4; zeros beyond the order).
  const double* coefficients() const { return c_; }
  int padded() const { return padded_; }
  int shift() const { return shift_; }
  int64_t constant() const { return constant_; }
  // Prediction of the sample at xi (xi[-kMaxLpcOrder .. -1] readable), as lpc_predict.
  int64_t predict(const double* xi) const {
    const double* x = xi - padded_;
    Lanes a0 = {0, 0}, a1 = {0, 0};
    for (int k = 0; k < padded_; k += 4) {
      a0 += load(c_ + k) * load(x + k);
      a1 += load(c_ + k + 2) * load(x + k + 2);
    }
    const Lanes a = a0 + a1;
    int64_t s = static_cast<int64_t>(a[0] + a[1]);
    s = (s >> shift_) + constant_;
    if (s > kMaxSample) s = kMaxSample;
    if (s < -kMaxSample) s = -kMaxSample;
    return s;
  }

 private:
  typedef double Lanes __attribute__((vector_size(16)));
  static Lanes load(const double* p) {
    Lanes v;
    std::memcpy(&v, p, sizeof v);
    return v;
  }
  int order_, shift_, padded_;
  int64_t constant_;
  double c_[kMaxLpcOrder] = {};
};

// Residuals r[i] = x[i] - lpc.predict(xd + i) for i < n (xd as for choose_block_predictor);
// four samples a step with AVX2 (analog_simd.h), the same integers.
void lpc_residuals(const LpcKernel& lpc, const int32_t* x, const double* xd, size_t n, int32_t* r);

}  // namespace analog
}  // namespace capz
