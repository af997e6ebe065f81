// Decoder library (capz_decode): builds without PCL and without the transform encoders.
#include "codec/pdct/dct.h"

#include <algorithm>
#include <cmath>
#include <numeric>

#include "capz/error.h"

namespace capz {
namespace pdct {
namespace {

constexpr double kPi = 3.14159265358979323846;

// Taylor series about 0 for |x| <= pi/4; 11 terms leave a truncation error below 1e-19.
double cos_small(double x) {
  const double x2 = x * x;
  double s = 1.0;
  for (int k = 22; k >= 2; k -= 2) s = 1.0 - s * x2 / (static_cast<double>(k) * (k - 1));
  return s;
}
double sin_small(double x) {
  const double x2 = x * x;
  double s = 1.0;
  for (int k = 23; k >= 3; k -= 2) s = 1.0 - s * x2 / (static_cast<double>(k) * (k - 1));
  return x * s;
}

}  // namespace

double cos_pi_ratio(int64_t num, int64_t den) {
  // Work with the angle pi * r / d, r in [0, 2d), all steps exact in integers.
  const int64_t d2 = 2 * den;
  int64_t r = num % d2;
  if (r < 0) r += d2;
  if (r > den) r = d2 - r;  // cos(2pi - a) = cos(a); now r in [0, d]
  double sign = 1.0;
  if (2 * r > den) {  // a > pi/2: cos(a) = -cos(pi - a)
    r = den - r;
    sign = -1.0;
  }
  // a = pi r / d in [0, pi/2]. Above pi/4 use cos(a) = sin(pi/2 - a) = sin(pi (d - 2r) / 2d).
  if (4 * r > den)
    return sign * sin_small(kPi * static_cast<double>(den - 2 * r) / static_cast<double>(d2));
  return sign * cos_small(kPi * static_cast<double>(r) / static_cast<double>(den));
}

DctPlan::DctPlan(size_t n) : n_(n), c_(n * n) {
  const double a0 = std::sqrt(1.0 / static_cast<double>(n));
  const double a = std::sqrt(2.0 / static_cast<double>(n));
  const int64_t den = 2 * static_cast<int64_t>(n);
  for (size_t l = 0; l < n; ++l)
    for (size_t i = 0; i < n; ++i)
      c_[l * n + i] = (l == 0 ? a0 : a) *
                      cos_pi_ratio(static_cast<int64_t>(l) * static_cast<int64_t>(2 * i + 1), den);
}

void DctPlan::forward(const double* x, double* X) const {
  for (size_t l = 0; l < n_; ++l) {
    const double* row = &c_[l * n_];
    double s = 0;
    for (size_t i = 0; i < n_; ++i) s += row[i] * x[i];
    X[l] = s;
  }
}

void DctPlan::inverse(const double* X, double* x) const {
  for (size_t i = 0; i < n_; ++i) x[i] = 0;
  for (size_t l = 0; l < n_; ++l) {
    const double* row = &c_[l * n_];
    const double v = X[l];
    if (v == 0) continue;  // skipping exact zeros adds +0.0, so the result is unchanged
    for (size_t i = 0; i < n_; ++i) x[i] += row[i] * v;
  }
}

void zero_and_quantise(const double* X, size_t n, const CoefQuantParams& p, int64_t* q) {
  const size_t zeroed = static_cast<size_t>(
      std::floor(std::min(1.0, std::max(0.0, p.zero_share)) * static_cast<double>(n)));
  std::vector<uint8_t> keep(n, 1);
  if (zeroed > 0) {
    std::vector<size_t> idx(n);
    std::iota(idx.begin(), idx.end(), 0);
    std::stable_sort(idx.begin(), idx.end(),
                     [X](size_t a, size_t b) { return std::fabs(X[a]) < std::fabs(X[b]); });
    // Among equal magnitudes the stable sort lists lower indices first, so they go first.
    for (size_t k = 0; k < zeroed; ++k) keep[idx[k]] = 0;
  }
  for (size_t l = 0; l < n; ++l) {
    if (!keep[l]) {
      q[l] = 0;
      continue;
    }
    const double v = X[l] / p.step;
    if (!(std::fabs(v) < 4503599627370496.0))  // 2^52
      throw Error(ErrorCode::kInvalidParameter,
                  "pdct: a DCT coefficient is " + std::to_string(X[l]) +
                      ", more than 2^52 steps of " + std::to_string(p.step) +
                      " (coefficient step too small)");
    q[l] = std::llround(v);
  }
}

}  // namespace pdct
}  // namespace capz
