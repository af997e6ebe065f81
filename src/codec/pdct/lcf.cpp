// Decoder library (capz_decode): builds without PCL and without the transform encoders.
#include "codec/pdct/lcf.h"

#include <cmath>

namespace capz {
namespace pdct {
namespace {

double dot3(const double* a, const double* b) {
  return a[0] * b[0] + a[1] * b[1] + a[2] * b[2];
}

// Normalises v in place; returns false (v unchanged) when its length is zero or not finite.
bool normalise(double* v) {
  const double n = std::sqrt(dot3(v, v));
  if (!(n > 0) || !std::isfinite(n)) return false;
  v[0] /= n;
  v[1] /= n;
  v[2] /= n;
  return true;
}

// y := (v - (v.x) x) normalised; false if nothing is left of v.
bool orthogonal_part(const double* v, const double* x, double* y) {
  const double d = dot3(v, x);
  for (int i = 0; i < 3; ++i) y[i] = v[i] - d * x[i];
  const double n = std::sqrt(dot3(y, y));
  const double vn = std::sqrt(dot3(v, v));
  // Less than 1e-9 of v survives: p3 is numerically on the x line.
  if (!(n > 1e-9 * vn)) return false;
  for (int i = 0; i < 3; ++i) y[i] /= n;
  return true;
}

}  // namespace

Lcf make_lcf(const double* p1, const double* p2, const double* p3) {
  Lcf f;
  double x[3], y[3], z[3], v[3];
  for (int i = 0; i < 3; ++i) {
    f.o[i] = 0.5 * (p1[i] + p2[i]);
    x[i] = p2[i] - p1[i];
    v[i] = p3[i] - f.o[i];
  }
  if (!normalise(x)) {
    x[0] = 1;
    x[1] = 0;
    x[2] = 0;
  }
  if (!orthogonal_part(v, x, y)) {
    // The world axis least aligned with x always leaves a usable orthogonal part.
    int best = 0;
    for (int i = 1; i < 3; ++i)
      if (std::fabs(x[i]) < std::fabs(x[best])) best = i;
    double e[3] = {0, 0, 0};
    e[best] = 1;
    orthogonal_part(e, x, y);
  }
  z[0] = x[1] * y[2] - x[2] * y[1];
  z[1] = x[2] * y[0] - x[0] * y[2];
  z[2] = x[0] * y[1] - x[1] * y[0];
  for (int i = 0; i < 3; ++i) {
    f.t[i] = x[i];
    f.t[3 + i] = y[i];
    f.t[6 + i] = z[i];
  }
  return f;
}

}  // namespace pdct
}  // namespace capz
