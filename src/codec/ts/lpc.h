// ts codec — stage 4a: linear predictive coding of a series of vectors (Luo et al. 2013, 6.1):
// the first motion fragment's PC coefficients of a cluster, and the 6 rigid parameters.
// Per row i (one PC coefficient, or one rigid parameter) the `order` weights a_ij are fitted by
// least squares over the whole series; the first `order` values are coded directly and every
// later one as the quantised residual of the closed-loop prediction from reconstructed values:
//   q_t = round((x_t - sum_j a_ij x~_{t-j}) / step_i),  x~_t = prediction + q_t * step_i.
#pragma once

#include <Eigen/Core>
#include <cstdint>
#include <vector>

namespace capz {
namespace ts {

struct LpcParams {
  int order = 2;           // m, 0..8; 0 codes every value directly
  int weight_bits = 14;    // fractional bits of the fixed-point weights
  double max_weight = 16;  // weights are clamped to [-max_weight, max_weight]
};

// A coded series of `rows` x `length`.
struct LpcCode {
  size_t rows = 0, length = 0;
  int order = 0, weight_bits = 0;
  std::vector<int32_t> weights;  // rows x order, row-major; empty when length <= order
  std::vector<int64_t> values;   // rows x length, row-major: t < order direct, else residual
  bool has_weights() const { return length > static_cast<size_t>(order) && order > 0; }
};

// series: rows x length; steps: one quantisation step (> 0) per row. *recon (optional) gets the
// reconstruction lpc_decode() will produce.
LpcCode lpc_encode(const Eigen::MatrixXd& series, const std::vector<double>& steps,
                   const LpcParams& params, Eigen::MatrixXd* recon);
// rows x length reconstruction.
Eigen::MatrixXd lpc_decode(const LpcCode& code, const std::vector<double>& steps);

// Least-squares LPC weights of one row (exposed for tests): order weights, unquantised.
std::vector<double> lpc_fit(const double* x, size_t length, int order);

}  // namespace ts
}  // namespace capz
