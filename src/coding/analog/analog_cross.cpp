#include "coding/analog/analog_cross.h"

#include <cmath>

namespace capz {
namespace analog {
namespace {

int bit_length(int64_t v) {
  const uint64_t u = (static_cast<uint64_t>(v) << 1) ^ static_cast<uint64_t>(v >> 63);
  return u == 0 ? 0 : 64 - __builtin_clzll(u);
}

}  // namespace

CrossParams choose_cross(const std::vector<int32_t>& r1,
                         const std::vector<const std::vector<int32_t>*>& refs,
                         double min_gain_bits) {
  CrossParams best;
  const size_t n = r1.size();
  double ecc = 0;
  for (int32_t v : r1) ecc += static_cast<double>(v) * v;
  if (n == 0 || ecc <= 0) return best;
  double best_bits = min_gain_bits;
  // Bits saved = sum bit_length(r1) - sum bit_length(r1 - prediction), the first sum shared.
  int64_t base = 0;
  for (size_t i = 0; i < n; ++i) base += bit_length(r1[i]);
  for (size_t d = 0; d < refs.size(); ++d) {
    const std::vector<int32_t>* ref = refs[d];
    if (!ref || ref->size() != n) continue;
    double ecr = 0, err = 0;
    for (size_t i = 0; i < n; ++i) {
      ecr += static_cast<double>(r1[i]) * (*ref)[i];
      err += static_cast<double>((*ref)[i]) * (*ref)[i];
    }
    if (err <= 0) continue;
    const double beta = std::round(ecr / err * (1 << kCrossShift));
    if (!(std::fabs(beta) < kMaxBeta) || beta == 0) continue;
    // Bits saved, measured as the change of the summed bit lengths of the residuals.
    const int32_t q = static_cast<int32_t>(beta);
    int64_t after = 0;
    for (size_t i = 0; i < n; ++i) after += bit_length(r1[i] - cross_predict(q, (*ref)[i]));
    const int64_t saved = base - after;
    const double bits = static_cast<double>(saved) - 20;
    if (bits > best_bits) {
      best_bits = bits;
      best.distance = static_cast<int>(d) + 1;
      best.beta = static_cast<int32_t>(beta);
    }
  }
  return best;
}

}  // namespace analog
}  // namespace capz
