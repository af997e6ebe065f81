#include "codec/pdct/cluster.h"

#include <limits>

namespace capz {
namespace pdct {

std::vector<int32_t> assign_clusters(const PositionsView& in, const std::vector<Lcf>& frames_lcf,
                                     size_t clusters, const std::vector<uint8_t>& frame_point,
                                     const ClusterParams& params) {
  const size_t F = in.frames, P = in.points;
  std::vector<int32_t> out(P, 0);
  const size_t stride = params.frame_stride == 0 ? 1 : params.frame_stride;
  std::vector<double> theta(clusters);
  for (size_t i = 0; i < P; ++i) {
    if (frame_point[i]) {
      out[i] = -1;
      continue;
    }
    if (clusters <= 1) continue;
    std::fill(theta.begin(), theta.end(), 0.0);
    size_t pairs = 0;
    for (size_t f = 1; f < F; f += stride) {
      if (!in.valid[f * P + i] || !in.valid[(f - 1) * P + i]) continue;
      ++pairs;
      const double* a = in.xyz + 3 * ((f - 1) * P + i);
      const double* b = in.xyz + 3 * (f * P + i);
      for (size_t k = 0; k < clusters; ++k) {
        double qa[3], qb[3];
        to_local(frames_lcf[k * F + f - 1], a, qa);
        to_local(frames_lcf[k * F + f], b, qb);
        theta[k] += (qb[0] - qa[0]) * (qb[0] - qa[0]) + (qb[1] - qa[1]) * (qb[1] - qa[1]) +
                    (qb[2] - qa[2]) * (qb[2] - qa[2]);
      }
    }
    if (pairs == 0) {
      // Nearest first-frame origin.
      const double* p = in.xyz + 3 * i;
      for (size_t k = 0; k < clusters; ++k) {
        const double* o = frames_lcf[k * F].o;
        theta[k] = (p[0] - o[0]) * (p[0] - o[0]) + (p[1] - o[1]) * (p[1] - o[1]) +
                   (p[2] - o[2]) * (p[2] - o[2]);
      }
    }
    size_t best = 0;
    for (size_t k = 1; k < clusters; ++k)
      if (theta[k] < theta[best]) best = k;
    out[i] = static_cast<int32_t>(best);
  }
  return out;
}

}  // namespace pdct
}  // namespace capz
