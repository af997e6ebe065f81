// ts codec — stage 4b: linear coding based on pose similarity (Luo et al. 2013, 6.2). A frame of
// a later motion fragment (its PC-coefficient vector w) is predicted as a weighted sum of k
// reference frames (the reconstructed first fragment of its cluster), chosen greedily: each
// step adds the reference most parallel to the current residual d (max |cos(d, ref)|), then
// refits all weights by least squares and updates d. Weights are fixed-point with
// `weight_bits` fractional bits; the residual w - prediction is quantised with `step`.
#pragma once

#include <Eigen/Core>
#include <cstdint>
#include <vector>

namespace capz {
namespace ts {

struct LcpsParams {
  int k = 2;                 // references per frame (the paper: 2)
  int weight_bits = 14;      // fractional bits of the fixed-point weights
  double max_weight = 1024;  // weights are clamped to [-max_weight, max_weight]
};

struct LcpsFrame {
  std::vector<uint32_t> index;  // k' = min(k, references) reference columns, in selection order
  std::vector<int32_t> weight;  // k' fixed-point weights
  std::vector<int64_t> resid;   // dim quantised residuals
};

// Greedy choice and least-squares weights (unquantised), exposed for tests.
void lcps_select(const Eigen::VectorXd& w, const Eigen::MatrixXd& refs, int k,
                 std::vector<uint32_t>* index, std::vector<double>* weight);

// refs: dim x count reconstructed reference frames (count >= 1). *recon gets what
// lcps_decode() returns for the result.
LcpsFrame lcps_encode(const Eigen::VectorXd& w, const Eigen::MatrixXd& refs, double step,
                      const LcpsParams& params, Eigen::VectorXd* recon);
Eigen::VectorXd lcps_decode(const LcpsFrame& code, const Eigen::MatrixXd& refs, double step,
                            int weight_bits);

}  // namespace ts
}  // namespace capz
