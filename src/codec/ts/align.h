// ts codec — stage 1: rigid alignment of every frame to a reference frame (Luo et al. 2013,
// section 4.1). Encoder only. The estimate is PCL's TransformationEstimationSVD (the
// Umeyama/SVD least-squares rigid fit the paper's Goryn-Hein method amounts to), computed over
// the points valid in both the frame and the reference. PCL stays inside align.cpp.
#pragma once

#include <cstddef>
#include <vector>

#include "codec/transform.h"
#include "codec/ts/rigid.h"

namespace capz {
namespace ts {

struct AlignParams {
  size_t reference = 0;   // frame the others are aligned to (the paper: the first)
  size_t min_common = 3;  // fewer common valid points than this -> identity for that frame
};

// One RigidParams per frame, mapping the frame onto the reference (p = R v + T, see rigid.h).
// The reference frame gets the identity.
std::vector<RigidParams> estimate_alignment(const PositionsView& in, const AlignParams& params);

}  // namespace ts
}  // namespace capz
