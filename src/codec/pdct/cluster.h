// pdct stage: vertex clustering by motion in the local frames (Amjoun & Strasser 2007, Sec. 4.2).
//
// Each point that is not a triangle vertex joins the cluster k minimising
//   theta(k, i) = sum over f >= 1 of || q(k, i, f) - q(k, i, f-1) ||^2,
// q(k, i, f) = the point's coordinates in cluster k's local frame of frame f, summed over the
// frames where the point is measured in both f and f-1 (gaps do not count). A point never
// measured in two consecutive frames joins the cluster whose first-frame origin is nearest to it
// (first frame position, filled or not). Ties go to the lower cluster index. Encoder only: the
// assignment is stored in the bitstream.
#pragma once

#include <cstddef>
#include <cstdint>
#include <vector>

#include "codec/pdct/lcf.h"
#include "codec/transform.h"

namespace capz {
namespace pdct {

struct ClusterParams {
  // Use every `frame_stride`-th frame pair only (1 = all, the paper); larger values trade a little
  // clustering quality for speed on long takes.
  size_t frame_stride = 1;
};

// frames_lcf: clusters x frames local frames, frames_lcf[k * in.frames + f].
// frame_point[i] != 0 marks triangle vertices: they get -1. Others get a cluster in [0, clusters).
std::vector<int32_t> assign_clusters(const PositionsView& in, const std::vector<Lcf>& frames_lcf,
                                     size_t clusters, const std::vector<uint8_t>& frame_point,
                                     const ClusterParams& params);

}  // namespace pdct
}  // namespace capz
