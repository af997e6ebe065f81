// The ts transform's LCPS decoder (lcps.h); the encoder is lcps_encode.cpp.
#include "codec/ts/lcps.h"

#include <Eigen/Core>
#include <algorithm>
#include <cmath>

#include "capz/error.h"
#include "codec/ts/predict.h"

namespace capz {
namespace ts {

Eigen::VectorXd lcps_decode(const LcpsFrame& f, const Eigen::MatrixXd& refs, double step,
                            int weight_bits) {
  const size_t dim = static_cast<size_t>(refs.rows());
  if (f.resid.size() != dim || f.weight.size() != f.index.size())
    fail(ErrorCode::kCorrupt, "", "ts: LCPS frame sizes disagree");
  for (uint32_t i : f.index)
    if (i >= static_cast<uint64_t>(refs.cols()))
      fail(ErrorCode::kCorrupt, "", "ts: LCPS reference index out of range");
  Eigen::VectorXd out(static_cast<Eigen::Index>(dim));
  for (size_t i = 0; i < dim; ++i) {
    const double pred =
        lcps_predict(f.index.data(), f.weight.data(), static_cast<int>(f.index.size()), weight_bits,
                     refs.data(), dim, i);
    out[static_cast<Eigen::Index>(i)] = pred + dequantise(f.resid[i], step);
  }
  return out;
}

}  // namespace ts
}  // namespace capz
