// ts codec — stage 3: PCA of the frames of one cluster (Luo et al. 2013, 5.1) and the uniform
// quantisation of its basis. The paper's PCA is on the raw frame vectors (no mean removed):
// the first component carries the cluster's mean shape.
#pragma once

#include <Eigen/Core>
#include <cstdint>
#include <vector>

namespace capz {
namespace ts {

struct PcaParams {
  // Components whose singular value is below rel_rank_tol * largest are dropped (numerical rank;
  // the Gram route resolves singular values only down to about sqrt(machine epsilon)).
  double rel_rank_tol = 1e-7;
};

struct Pca {
  Eigen::MatrixXd basis;  // 3N x r, orthonormal columns, by decreasing singular value
  Eigen::VectorXd sigma;  // r singular values
  Eigen::MatrixXd coeff;  // r x l coefficients = basis^T * frames
};

// frames: 3N x l. Uses the l x l Gram matrix (eigenvectors of F^T F) when 3N > l, else an SVD of
// F itself. Sign convention: each basis column's largest-magnitude entry is positive.
Pca pca_frames(const Eigen::MatrixXd& frames, const PcaParams& params);

// Uniform symmetric quantiser of one basis vector with `bits` bits (2..30):
//   step = scale / (2^(bits-1) - 1), q_i = round_half_away(b_i / step), b~_i = q_i * step,
// where scale = max_i |b_i| (stored as float64). |q_i| <= 2^(bits-1) - 1.
struct QuantisedVector {
  int bits = 0;
  double scale = 0;
  std::vector<int32_t> q;
};
inline double quant_step(int bits, double scale) {
  return scale / static_cast<double>((int64_t{1} << (bits - 1)) - 1);
}
// With f32_scale the scale is rounded up to the nearest float32 (a version-2 payload with flags
// bit 3 stores it as f32), and the values are quantised with that scale.
QuantisedVector quantise_vector(const double* v, size_t n, int bits, bool f32_scale = false);
// The same quantiser with a free step (no power-of-two grid of steps): bits = the fewest in
// 2..max_bits with (2^(bits-1) - 1) step >= max_i |v_i|, scale = step (2^(bits-1) - 1), so the
// decoder's quant_step(bits, scale) is `step` up to rounding. When max_bits cannot hold the
// range, the step grows to max_i |v_i| / (2^(max_bits-1) - 1).
QuantisedVector quantise_vector_step(const double* v, size_t n, double step, int max_bits,
                                     bool f32_scale = false);
// x rounded up to a float32 value (FLT_MAX when beyond it).
double round_up_to_f32(double x);
void dequantise_vector(const QuantisedVector& qv, double* out);  // writes qv.q.size() values

// Fewest bits in [min_bits, max_bits] whose step keeps the basis error of a component with
// singular value `sigma` within `budget` (squared error over the cluster's frames, estimated as
// sigma^2 * n * step^2 / 12 for n entries). Returns max_bits when none is enough.
int basis_bits_for(double sigma, double scale, size_t n, double budget, int min_bits, int max_bits);

}  // namespace ts
}  // namespace capz
