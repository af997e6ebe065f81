// The ts transform's LPC decoder (lpc.h); the encoder is lpc_encode.cpp.
#include "codec/ts/lpc.h"

#include <algorithm>
#include <cmath>

#include "capz/error.h"
#include "codec/ts/predict.h"

namespace capz {
namespace ts {

Eigen::MatrixXd lpc_decode(const LpcCode& c, const std::vector<double>& steps) {
  if (steps.size() != c.rows || c.values.size() != c.rows * c.length ||
      (c.has_weights() && c.weights.size() != c.rows * static_cast<size_t>(c.order)))
    fail(ErrorCode::kCorrupt, "", "ts: LPC block sizes disagree");
  Eigen::MatrixXd out(static_cast<Eigen::Index>(c.rows), static_cast<Eigen::Index>(c.length));
  std::vector<double> rec(c.length);
  for (size_t i = 0; i < c.rows; ++i) {
    const int32_t* w = c.has_weights() ? &c.weights[i * static_cast<size_t>(c.order)] : nullptr;
    for (size_t t = 0; t < c.length; ++t) {
      const double pred = (w && t >= static_cast<size_t>(c.order))
                              ? lpc_predict(w, c.order, c.weight_bits, rec.data(), t)
                              : 0.0;
      rec[t] = pred + dequantise(c.values[i * c.length + t], steps[i]);
      out(static_cast<Eigen::Index>(i), static_cast<Eigen::Index>(t)) = rec[t];
    }
  }
  return out;
}

}  // namespace ts
}  // namespace capz
