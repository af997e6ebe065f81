// Encoder stage: the error of a window as written (window_error.h).
#include "codec/window_error.h"

#include <cmath>

namespace capz {
namespace {

// x as the C3D writer stores it at int16 scale `scale`.
inline double as_written(double x, double scale) {
  const double q = x / scale;
  return std::fabs(q) < 4.5e15 ? std::round(q) * scale : x;  // beyond: not int16, written as is
}

}  // namespace

double window_sq_error(size_t fn, size_t n, const double* a, const double* b, const uint8_t* valid,
                       double written_scale) {
  double s = 0;
  for (size_t i = 0; i < fn * n; ++i)
    if (valid[i])
      for (size_t k = i * 3; k < i * 3 + 3; ++k) {
        const double d = a[k] - (written_scale > 0 ? as_written(b[k], written_scale) : b[k]);
        s += d * d;
      }
  return s;
}
double centred_sq_window(size_t fn, size_t n, const double* x, const uint8_t* valid) {
  double cs = 0;
  for (size_t f = 0; f < fn; ++f) {
    double c[3] = {0, 0, 0};
    size_t m = 0;
    for (size_t p = 0; p < n; ++p)
      if (valid[f * n + p]) {
        for (int a = 0; a < 3; ++a) c[a] += x[(f * n + p) * 3 + a];
        ++m;
      }
    if (!m) continue;
    for (double& v : c) v /= static_cast<double>(m);
    for (size_t p = 0; p < n; ++p)
      if (valid[f * n + p])
        for (int a = 0; a < 3; ++a) {
          const double d = x[(f * n + p) * 3 + a] - c[a];
          cs += d * d;
        }
  }
  return cs;
}

}  // namespace capz
