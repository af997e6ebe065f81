#include "capz/metrics.h"

#include <algorithm>
#include <cmath>
#include <limits>

#include "capz/error.h"

namespace capz {

ErrorStats compare(size_t frames, size_t points, const double* a, const double* b,
                   const uint8_t* valid) {
  ErrorStats s;
  double sq = 0, centred_sq = 0;
  double lo[3] = {std::numeric_limits<double>::infinity(), std::numeric_limits<double>::infinity(),
                  std::numeric_limits<double>::infinity()};
  double hi[3] = {-lo[0], -lo[1], -lo[2]};
  for (size_t f = 0; f < frames; ++f) {
    double c[3] = {0, 0, 0};
    size_t n = 0;
    for (size_t p = 0; p < points; ++p) {
      if (!valid[f * points + p]) continue;
      const double* x = a + (f * points + p) * 3;
      for (int k = 0; k < 3; ++k) c[k] += x[k];
      ++n;
    }
    if (n == 0) continue;
    for (double& v : c) v /= static_cast<double>(n);
    for (size_t p = 0; p < points; ++p) {
      if (!valid[f * points + p]) continue;
      const double* x = a + (f * points + p) * 3;
      const double* y = b + (f * points + p) * 3;
      double d2 = 0;
      for (int k = 0; k < 3; ++k) {
        double d = x[k] - y[k];
        d2 += d * d;
        s.max_abs = std::max(s.max_abs, std::fabs(d));
        double e = x[k] - c[k];
        centred_sq += e * e;
        lo[k] = std::min(lo[k], x[k]);
        hi[k] = std::max(hi[k], x[k]);
      }
      s.max_error = std::max(s.max_error, std::sqrt(d2));
      sq += d2;
      ++s.samples;
    }
  }
  if (s.samples == 0) return s;
  s.rmse = std::sqrt(sq / static_cast<double>(s.samples));
  s.kg_error = centred_sq > 0 ? 100.0 * std::sqrt(sq / centred_sq) : (sq > 0 ? INFINITY : 0.0);
  double diag = std::sqrt((hi[0] - lo[0]) * (hi[0] - lo[0]) + (hi[1] - lo[1]) * (hi[1] - lo[1]) +
                          (hi[2] - lo[2]) * (hi[2] - lo[2]));
  s.psnr = s.rmse > 0 ? 20.0 * std::log10(diag / s.rmse) : INFINITY;
  return s;
}

ErrorStats compare(const Take& a, const Take& b) {
  if (a.frames != b.frames || a.points != b.points || b.xyz.size() != a.xyz.size())
    fail(ErrorCode::kInvalidParameter, a.source,
         "cannot compare takes of different shapes (" + std::to_string(a.frames) + "x" +
             std::to_string(a.points) + " vs " + std::to_string(b.frames) + "x" +
             std::to_string(b.points) + ")");
  ErrorStats s = compare(a.frames, a.points, a.xyz.data(), b.xyz.data(), a.valid.data());
  if (b.valid.size() == a.valid.size())
    for (size_t i = 0; i < a.valid.size(); ++i) s.mask_mismatches += (a.valid[i] != 0) != (b.valid[i] != 0);
  return s;
}

double bpvf(size_t bytes, size_t frames, size_t points) {
  if (frames == 0 || points == 0) return 0;
  return 8.0 * static_cast<double>(bytes) / (static_cast<double>(frames) * static_cast<double>(points));
}

}  // namespace capz
