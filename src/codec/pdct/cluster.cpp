#include "codec/pdct/cluster.h"

#include <algorithm>
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
    for (size_t k = 0; k < clusters; ++k) {
      const Lcf* fr = &frames_lcf[k * F];
      double prev[3], cur[3];
      size_t prev_f = 0;
      bool have_prev = false;
      for (size_t f = 0; f < F; f += (f == 0 ? 1 : stride)) {
        // Pairs (f-1, f) for f = 1, 1 + stride, ...: f-1 must be transformed too.
        const bool v0 = in.valid[(f == 0 ? 0 : f - 1) * P + i] != 0, v1 = in.valid[f * P + i] != 0;
        if (f == 0) {
          if (v1) {
            to_local(fr[0], in.xyz + 3 * i, prev);
            prev_f = 0;
            have_prev = true;
          }
          continue;
        }
        if (!(v0 && v1)) continue;
        if (!have_prev || prev_f != f - 1)
          to_local(fr[f - 1], in.xyz + 3 * ((f - 1) * P + i), prev);
        to_local(fr[f], in.xyz + 3 * (f * P + i), cur);
        theta[k] += (cur[0] - prev[0]) * (cur[0] - prev[0]) +
                    (cur[1] - prev[1]) * (cur[1] - prev[1]) +
                    (cur[2] - prev[2]) * (cur[2] - prev[2]);
        if (k == 0) ++pairs;
        std::copy(cur, cur + 3, prev);
        prev_f = f;
        have_prev = true;
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
