// The ts transform's LCPS encoder (lcps.h): the references chosen and a frame coded as
// lcps_decode (lcps.cpp) will rebuild it.
#include <Eigen/QR>
#include <algorithm>
#include <cmath>

#include "capz/error.h"
#include "codec/ts/lcps.h"
#include "codec/ts/predict.h"

namespace capz {
namespace ts {

void lcps_select(const Eigen::VectorXd& w, const Eigen::MatrixXd& refs, int k,
                 std::vector<uint32_t>* index, std::vector<double>* weight) {
  index->clear();
  weight->clear();
  const Eigen::Index count = refs.cols();
  const int kk = static_cast<int>(std::min<Eigen::Index>(std::max(0, k), count));
  Eigen::VectorXd norms = refs.colwise().norm().transpose();
  Eigen::VectorXd d = w;
  Eigen::VectorXd b;
  for (int s = 0; s < kk; ++s) {
    const double dn = d.norm();
    if (dn == 0) break;
    Eigen::Index best = -1;
    double best_cos = -1;
    for (Eigen::Index c = 0; c < count; ++c) {
      if (norms[c] == 0) continue;
      if (std::find(index->begin(), index->end(), static_cast<uint32_t>(c)) != index->end())
        continue;
      const double cs = std::fabs(d.dot(refs.col(c))) / (dn * norms[c]);
      if (cs > best_cos) {
        best_cos = cs;
        best = c;
      }
    }
    if (best < 0) break;
    index->push_back(static_cast<uint32_t>(best));
    Eigen::MatrixXd sel(refs.rows(), static_cast<Eigen::Index>(index->size()));
    for (size_t j = 0; j < index->size(); ++j)
      sel.col(static_cast<Eigen::Index>(j)) = refs.col((*index)[j]);
    b = sel.colPivHouseholderQr().solve(w);
    d = w - sel * b;
  }
  for (Eigen::Index j = 0; j < b.size(); ++j) weight->push_back(std::isfinite(b[j]) ? b[j] : 0.0);
}

LcpsFrame lcps_encode(const Eigen::VectorXd& w, const Eigen::MatrixXd& refs, double step,
                      const LcpsParams& params, Eigen::VectorXd* recon) {
  LcpsFrame f;
  std::vector<double> wt;
  lcps_select(w, refs, params.k, &f.index, &wt);
  const double scale = std::ldexp(1.0, params.weight_bits);
  for (double v : wt) {
    v = std::max(-params.max_weight, std::min(params.max_weight, v));
    f.weight.push_back(static_cast<int32_t>(std::llround(v * scale)));
  }
  const size_t dim = static_cast<size_t>(w.size());
  f.resid.resize(dim);
  Eigen::VectorXd out(w.size());
  for (size_t i = 0; i < dim; ++i) {
    const double pred =
        lcps_predict(f.index.data(), f.weight.data(), static_cast<int>(f.index.size()),
                     params.weight_bits, refs.data(), dim, i);
    const int64_t q = quantise(w[static_cast<Eigen::Index>(i)] - pred, step);
    f.resid[i] = q;
    out[static_cast<Eigen::Index>(i)] = pred + dequantise(q, step);
  }
  if (recon) *recon = std::move(out);
  return f;
}

}  // namespace ts
}  // namespace capz
