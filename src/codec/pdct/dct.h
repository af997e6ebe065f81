// pdct stage: the orthonormal DCT along a cluster's points (Amjoun & Strasser 2007, Sec. 4.5)
// and the coefficient quantiser (Sec. 4.6).
//
//   forward (DCT-II):  X[l] = a(l) sum_i x[i] cos(pi l (2i+1) / 2n),  a(0) = sqrt(1/n), else
//   sqrt(2/n) inverse (DCT-III): x[i] = sum_l a(l) X[l] cos(pi l (2i+1) / 2n)
//
// The cosine table is computed with cos_pi_ratio(), which uses only +, -, *, / on doubles (no
// libm), and sums run in a fixed order, so the decoder's inverse is bit-identical to the
// encoder's on any IEEE-754 platform that does not contract a*b+c into fma (C++17 ISO mode on
// GCC/Clang does not).
#pragma once

#include <cstddef>
#include <cstdint>
#include <vector>

namespace capz {
namespace pdct {

// cos(pi * num / den) for den > 0, to about 1 ulp, deterministic (argument reduced exactly in
// integers to [0, pi/4], then a fixed Taylor polynomial).
double cos_pi_ratio(int64_t num, int64_t den);

class DctPlan {
 public:
  explicit DctPlan(size_t n);  // n >= 1; the table holds n*n doubles
  size_t size() const { return n_; }
  void forward(const double* x, double* X) const;  // n values in, n out (may not alias)
  void inverse(const double* X, double* x) const;

 private:
  size_t n_;
  std::vector<double> c_;  // c_[l * n + i] = a(l) cos(pi l (2i+1) / 2n)
};

struct CoefQuantParams {
  double step = 1;        // quantiser step (units of the coefficients), > 0
  double zero_share = 0;  // in [0, 1]: this share of the signal's coefficients, smallest |X| first
                          // (ties: lower index first), is set to zero before quantising
};

// q[l] = round(X[l] / step), half away from zero, after zeroing floor(zero_share * n) of the
// smallest coefficients. Throws Error(kInvalidParameter) if a value does not fit in 2^52 steps.
void zero_and_quantise(const double* X, size_t n, const CoefQuantParams& p, int64_t* q);

// X[l] = q[l] * step: the decoder's dequantiser (shared).
inline void dequantise(const int64_t* q, size_t n, double step, double* X) {
  for (size_t l = 0; l < n; ++l) X[l] = static_cast<double>(q[l]) * step;
}

}  // namespace pdct
}  // namespace capz
