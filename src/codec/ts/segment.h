// ts codec — point segmentation (an addition to Luo et al. 2013, after Sattler et al. 2005's
// clustered PCA): the points are split into groups that move alike, and each group gets its own
// PCA, so a kept component costs 3 N_s basis entries instead of 3 N. Encoder only: the labels
// are stored in the payload (docs/CODEC-TS.md, "Point segments").
#pragma once

#include <Eigen/Core>
#include <cstdint>
#include <vector>

#include "codec/ts/ts_model.h"  // kMaxSegments, segment_members

namespace capz {
namespace ts {

struct SegmentParams {
  int segments = 8;        // wanted, 1..kMaxSegments; clamped to the number of points
  uint64_t seed = 0x5eed;  // fixed: same input, same segmentation
  int max_iterations = 60;
};

struct Segmentation {
  int segments = 0;            // non-empty segments (0 only for zero points)
  std::vector<uint8_t> label;  // per point, 0..segments-1, numbered by first appearance
  double wcss = 0;             // within-segment sum of squared distances of the features
};

// frames: 3N x F (column = one aligned frame, entry 3 i + axis = point i). Point i's feature is
// its trajectory minus its temporal mean (a 3F-vector); k-means++ seeding (draws from the seed
// with integer arithmetic only), then Lloyd iterations until no label changes. Deterministic.
Segmentation segment_points(const Eigen::MatrixXd& frames, const SegmentParams& params);

}  // namespace ts
}  // namespace capz
