// Decoder library (capz_decode): builds without PCL and without the transform encoders.
#include "codec/ts/rigid.h"

#include <Eigen/Geometry>
#include <cmath>

namespace capz {
namespace ts {

Eigen::Matrix3d rotation_matrix(const RigidParams& p) {
  const double x = p.rot[0], y = p.rot[1], z = p.rot[2];
  const double theta2 = x * x + y * y + z * z;
  Eigen::Matrix3d k;
  k << 0, -z, y, z, 0, -x, -y, x, 0;
  // R = I + a K + b K^2 with a = sin(t)/t, b = (1 - cos(t))/t^2 (Taylor series near 0).
  double a, b;
  if (theta2 < 1e-12) {
    a = 1.0 - theta2 / 6.0;
    b = 0.5 - theta2 / 24.0;
  } else {
    const double t = std::sqrt(theta2);
    a = std::sin(t) / t;
    b = (1.0 - std::cos(t)) / theta2;
  }
  return Eigen::Matrix3d::Identity() + a * k + b * (k * k);
}

RigidParams params_from_transform(const Eigen::Matrix3d& rot, const Eigen::Vector3d& trans) {
  RigidParams p;
  Eigen::AngleAxisd aa(rot);
  Eigen::Vector3d v = aa.axis() * aa.angle();
  if (!std::isfinite(v[0]) || !std::isfinite(v[1]) || !std::isfinite(v[2])) v.setZero();
  for (int i = 0; i < 3; ++i) {
    p.rot[i] = v[i];
    p.trans[i] = trans[i];
  }
  return p;
}

void apply_rigid(const RigidParams& p, double* xyz, size_t points) {
  const Eigen::Matrix3d r = rotation_matrix(p);
  for (size_t i = 0; i < points; ++i) {
    double* v = xyz + 3 * i;
    double o[3];
    for (int a = 0; a < 3; ++a)
      o[a] = r(a, 0) * v[0] + r(a, 1) * v[1] + r(a, 2) * v[2] + p.trans[a];
    for (int a = 0; a < 3; ++a) v[a] = o[a];
  }
}

void apply_rigid_inverse(const RigidParams& p, double* xyz, size_t points) {
  const Eigen::Matrix3d r = rotation_matrix(p);
  for (size_t i = 0; i < points; ++i) {
    double* v = xyz + 3 * i;
    const double d[3] = {v[0] - p.trans[0], v[1] - p.trans[1], v[2] - p.trans[2]};
    for (int a = 0; a < 3; ++a) v[a] = r(0, a) * d[0] + r(1, a) * d[1] + r(2, a) * d[2];
  }
}

}  // namespace ts
}  // namespace capz
