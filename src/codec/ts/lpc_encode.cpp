// The ts transform's LPC encoder (lpc.h): each row's coefficients fitted, quantised and its
// values coded as lpc_decode (lpc.cpp) will rebuild them.
#include <Eigen/Cholesky>
#include <algorithm>
#include <cmath>

#include "capz/error.h"
#include "codec/ts/lpc.h"
#include "codec/ts/predict.h"

namespace capz {
namespace ts {

std::vector<double> lpc_fit(const double* x, size_t length, int order) {
  std::vector<double> a(static_cast<size_t>(order), 0.0);
  if (order <= 0 || length <= static_cast<size_t>(order)) return a;
  Eigen::MatrixXd ata = Eigen::MatrixXd::Zero(order, order);
  Eigen::VectorXd atb = Eigen::VectorXd::Zero(order);
  for (size_t t = static_cast<size_t>(order); t < length; ++t) {
    for (int i = 0; i < order; ++i) {
      atb[i] += x[t - 1 - i] * x[t];
      for (int j = 0; j < order; ++j) ata(i, j) += x[t - 1 - i] * x[t - 1 - j];
    }
  }
  // A tiny ridge keeps short or constant series solvable (it moves no well-posed fit).
  const double ridge = 1e-9 * (ata.trace() / order + 1e-300);
  ata.diagonal().array() += ridge;
  Eigen::VectorXd sol = ata.ldlt().solve(atb);
  for (int i = 0; i < order; ++i) a[static_cast<size_t>(i)] = std::isfinite(sol[i]) ? sol[i] : 0.0;
  return a;
}

LpcCode lpc_encode(const Eigen::MatrixXd& series, const std::vector<double>& steps,
                   const LpcParams& params, Eigen::MatrixXd* recon) {
  if (params.order < 0 || params.order > 8)
    fail(ErrorCode::kInvalidParameter, "", "ts: LPC order must be 0..8");
  LpcCode c;
  c.rows = static_cast<size_t>(series.rows());
  c.length = static_cast<size_t>(series.cols());
  c.order = params.order;
  c.weight_bits = params.weight_bits;
  if (steps.size() != c.rows) fail(ErrorCode::kInternal, "", "ts: LPC steps per row mismatch");
  c.values.resize(c.rows * c.length);
  if (c.has_weights()) c.weights.resize(c.rows * static_cast<size_t>(c.order));
  std::vector<double> x(c.length), rec(c.length);
  const double wscale = std::ldexp(1.0, params.weight_bits);
  Eigen::MatrixXd out(series.rows(), series.cols());
  for (size_t i = 0; i < c.rows; ++i) {
    for (size_t t = 0; t < c.length; ++t)
      x[t] = series(static_cast<Eigen::Index>(i), static_cast<Eigen::Index>(t));
    int32_t* w = c.has_weights() ? &c.weights[i * static_cast<size_t>(c.order)] : nullptr;
    if (w) {
      std::vector<double> a = lpc_fit(x.data(), c.length, c.order);
      for (int j = 0; j < c.order; ++j) {
        double v =
            std::max(-params.max_weight, std::min(params.max_weight, a[static_cast<size_t>(j)]));
        w[j] = static_cast<int32_t>(std::llround(v * wscale));
      }
    }
    const double step = steps[i];
    for (size_t t = 0; t < c.length; ++t) {
      const double pred = (w && t >= static_cast<size_t>(c.order))
                              ? lpc_predict(w, c.order, c.weight_bits, rec.data(), t)
                              : 0.0;
      const int64_t q = quantise(x[t] - pred, step);
      c.values[i * c.length + t] = q;
      rec[t] = pred + dequantise(q, step);
    }
    for (size_t t = 0; t < c.length; ++t)
      out(static_cast<Eigen::Index>(i), static_cast<Eigen::Index>(t)) = rec[t];
  }
  if (recon) *recon = std::move(out);
  return c;
}

}  // namespace ts
}  // namespace capz
