// Decoder library (capz_decode): builds without PCL and without the transform encoders.
#include "codec/ts/pca.h"

#include <Eigen/Eigenvalues>
#include <Eigen/SVD>
#include <algorithm>
#include <cmath>
#include <limits>

#include "capz/error.h"

namespace capz {
namespace ts {

Pca pca_frames(const Eigen::MatrixXd& frames, const PcaParams& params) {
  Pca out;
  const Eigen::Index dim = frames.rows(), l = frames.cols();
  if (dim == 0 || l == 0) {
    out.basis.resize(dim, 0);
    out.coeff.resize(0, l);
    return out;
  }
  Eigen::MatrixXd u;
  Eigen::VectorXd s;
  if (dim > l) {
    // Gram route: F^T F = V S^2 V^T, U = F V S^-1.
    Eigen::MatrixXd g = frames.transpose() * frames;
    Eigen::SelfAdjointEigenSolver<Eigen::MatrixXd> eig(g);
    if (eig.info() != Eigen::Success) fail(ErrorCode::kInternal, "", "ts: PCA eigen solver failed");
    Eigen::VectorXd lam = eig.eigenvalues().reverse();
    Eigen::MatrixXd v = eig.eigenvectors().rowwise().reverse();
    const double top = std::sqrt(std::max(0.0, lam[0]));
    Eigen::Index r = 0;
    while (r < l && std::sqrt(std::max(0.0, lam[r])) > params.rel_rank_tol * top && top > 0) ++r;
    s.resize(r);
    for (Eigen::Index i = 0; i < r; ++i) s[i] = std::sqrt(lam[i]);
    u = frames * v.leftCols(r);
    for (Eigen::Index i = 0; i < r; ++i) {
      u.col(i) /= s[i];
      u.col(i).normalize();  // undo the Gram route's rounding drift
    }
  } else {
    Eigen::BDCSVD<Eigen::MatrixXd> svd(frames, Eigen::ComputeThinU);
    const Eigen::VectorXd& sv = svd.singularValues();
    Eigen::Index r = 0;
    while (r < sv.size() && sv[r] > params.rel_rank_tol * sv[0] && sv[0] > 0) ++r;
    s = sv.head(r);
    u = svd.matrixU().leftCols(r);
  }
  for (Eigen::Index i = 0; i < u.cols(); ++i) {
    Eigen::Index at;
    u.col(i).cwiseAbs().maxCoeff(&at);
    if (u(at, i) < 0) u.col(i) = -u.col(i);
  }
  out.basis = std::move(u);
  out.sigma = std::move(s);
  out.coeff = out.basis.transpose() * frames;
  return out;
}

double round_up_to_f32(double x) {
  float f = static_cast<float>(x);
  if (!std::isfinite(f)) return static_cast<double>(std::numeric_limits<float>::max());
  if (static_cast<double>(f) < x) f = std::nextafter(f, std::numeric_limits<float>::infinity());
  return static_cast<double>(f);
}

QuantisedVector quantise_vector(const double* v, size_t n, int bits, bool f32_scale) {
  if (bits < 2 || bits > 30) fail(ErrorCode::kInvalidParameter, "", "ts: basis bits out of 2..30");
  QuantisedVector qv;
  qv.bits = bits;
  qv.q.resize(n);
  double scale = 0;
  for (size_t i = 0; i < n; ++i) scale = std::max(scale, std::fabs(v[i]));
  if (f32_scale) scale = round_up_to_f32(scale);
  qv.scale = scale;
  if (scale == 0) return qv;
  const double step = quant_step(bits, scale);
  const int32_t lim = static_cast<int32_t>((int64_t{1} << (bits - 1)) - 1);
  for (size_t i = 0; i < n; ++i) {
    long long q = std::llround(v[i] / step);
    qv.q[i] = static_cast<int32_t>(std::max<long long>(-lim, std::min<long long>(lim, q)));
  }
  return qv;
}

QuantisedVector quantise_vector_step(const double* v, size_t n, double step, int max_bits,
                                     bool f32_scale) {
  if (max_bits < 2 || max_bits > 30)
    fail(ErrorCode::kInvalidParameter, "", "ts: basis bits out of 2..30");
  double top = 0;
  for (size_t i = 0; i < n; ++i) top = std::max(top, std::fabs(v[i]));
  QuantisedVector qv;
  qv.bits = 2;
  qv.q.assign(n, 0);
  if (top == 0 || !(step > 0)) return qv;
  while (qv.bits < max_bits && static_cast<double>((int64_t{1} << (qv.bits - 1)) - 1) * step < top)
    ++qv.bits;
  const double lim = static_cast<double>((int64_t{1} << (qv.bits - 1)) - 1);
  qv.scale = std::max(step * lim, top);
  if (f32_scale) qv.scale = round_up_to_f32(qv.scale);
  const double s = quant_step(qv.bits, qv.scale);
  const int32_t ilim = static_cast<int32_t>(lim);
  for (size_t i = 0; i < n; ++i) {
    const long long q = std::llround(v[i] / s);
    qv.q[i] = static_cast<int32_t>(std::max<long long>(-ilim, std::min<long long>(ilim, q)));
  }
  return qv;
}

void dequantise_vector(const QuantisedVector& qv, double* out) {
  const double step = qv.scale > 0 ? quant_step(qv.bits, qv.scale) : 0.0;
  for (size_t i = 0; i < qv.q.size(); ++i) out[i] = static_cast<double>(qv.q[i]) * step;
}

int basis_bits_for(double sigma, double scale, size_t n, double budget, int min_bits,
                   int max_bits) {
  for (int b = min_bits; b < max_bits; ++b) {
    const double step = quant_step(b, scale);
    if (sigma * sigma * static_cast<double>(n) * step * step / 12.0 <= budget) return b;
  }
  return max_bits;
}

}  // namespace ts
}  // namespace capz
