#include "codec/ts/align.h"

#include <Eigen/Core>
#include <cmath>

#include "capz/error.h"
#include "codec/pcl_geom.h"

namespace capz {
namespace ts {

std::vector<RigidParams> estimate_alignment(const PositionsView& in, const AlignParams& params) {
  if (in.frames > 0 && params.reference >= in.frames)
    fail(ErrorCode::kInvalidParameter, "", "ts: alignment reference frame out of range");
  std::vector<RigidParams> out(in.frames);
  if (in.frames == 0) return out;
  const size_t ref = params.reference;
  std::vector<float> src, tgt;  // x y z of the common points, less the reference's mean
  for (size_t f = 0; f < in.frames; ++f) {
    if (f == ref) continue;
    // PCL points are float: subtract the reference frame's mean first so the float rounding is
    // relative to the object's size, not to its distance from the origin.
    double c[3] = {0, 0, 0};
    size_t n = 0;
    for (size_t p = 0; p < in.points; ++p) {
      if (!in.valid[f * in.points + p] || !in.valid[ref * in.points + p]) continue;
      const double* b = in.xyz + (ref * in.points + p) * 3;
      for (int a = 0; a < 3; ++a) c[a] += b[a];
      ++n;
    }
    if (n < params.min_common) continue;  // identity
    for (double& v : c) v /= static_cast<double>(n);
    src.clear();
    tgt.clear();
    src.reserve(3 * n);
    tgt.reserve(3 * n);
    for (size_t p = 0; p < in.points; ++p) {
      if (!in.valid[f * in.points + p] || !in.valid[ref * in.points + p]) continue;
      const double* s = in.xyz + (f * in.points + p) * 3;
      const double* t = in.xyz + (ref * in.points + p) * 3;
      for (int a = 0; a < 3; ++a) {
        src.push_back(static_cast<float>(s[a] - c[a]));
        tgt.push_back(static_cast<float>(t[a] - c[a]));
      }
    }
    double mm[16];
    geom::backend("ts alignment").rigid(src.data(), tgt.data(), n, mm);
    Eigen::Matrix4d m;
    for (int r = 0; r < 4; ++r)
      for (int k = 0; k < 4; ++k) m(r, k) = mm[4 * r + k];
    if (!m.allFinite()) continue;
    // p - c = R (v - c) + t'  =>  p = R v + (t' + c - R c)
    const Eigen::Matrix3d r = m.block<3, 3>(0, 0);
    const Eigen::Vector3d cc(c[0], c[1], c[2]);
    const Eigen::Vector3d t = m.block<3, 1>(0, 3) + cc - r * cc;
    out[f] = params_from_transform(r, t);
  }
  return out;
}

}  // namespace ts
}  // namespace capz
