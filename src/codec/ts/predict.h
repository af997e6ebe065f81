// ts codec — the predictors and dequantisers shared by the encoder and the decoder. The encoder
// runs exactly these functions on the quantised data, so its reconstruction is bit for bit what
// the decoder computes (same code, same doubles, same order of operations).
#pragma once

#include <cmath>
#include <cstdint>

namespace capz {
namespace ts {

// Fixed-point weight: w = q / 2^frac_bits.
inline double fixed_to_double(int32_t q, int frac_bits) {
  return std::ldexp(static_cast<double>(q), -frac_bits);
}

// Rounding rule of every uniform quantiser in ts: round half away from zero (std::llround).
inline int64_t quantise(double x, double step) {
  return std::llround(x / step);
}
inline double dequantise(int64_t q, double step) {
  return static_cast<double>(q) * step;
}

// LPC prediction of x_t from the reconstructed history: sum_j a_j x~_{t-j}, j = 1..order.
// `row` points at the reconstructed series, `t` >= order.
inline double lpc_predict(const int32_t* weights, int order, int frac_bits, const double* row,
                          size_t t) {
  double p = 0;
  for (int j = 0; j < order; ++j) p += fixed_to_double(weights[j], frac_bits) * row[t - 1 - j];
  return p;
}

// LCPS prediction of coefficient `i` of a frame: sum_s b_s * ref_{index_s}[i], where `refs` is
// column-major (dim x count, column c at refs + c * dim).
inline double lcps_predict(const uint32_t* index, const int32_t* weights, int k, int frac_bits,
                           const double* refs, size_t dim, size_t i) {
  double p = 0;
  for (int s = 0; s < k; ++s)
    p += fixed_to_double(weights[s], frac_bits) * refs[index[s] * dim + i];
  return p;
}

}  // namespace ts
}  // namespace capz
