// ts codec — stage 2: k-means clustering of aligned frames by pose (Luo et al. 2013, 4.2).
// Encoder only. Distance = Euclidean distance of the 3N-vectors; initialisation = random
// partition (every frame gets a uniformly random cluster) from a fixed seed, so the result is
// deterministic; the best of `restarts` runs (lowest within-cluster sum of squares) is kept.
#pragma once

#include <Eigen/Core>
#include <cstdint>
#include <vector>

namespace capz {
namespace ts {

struct ClusterParams {
  int k = 2;               // clusters wanted, 1..frames
  uint64_t seed = 0x5eed;  // fixed: same input, same clustering
  int restarts = 4;        // random-partition runs; the lowest WCSS wins
  int max_iterations = 100;
};

struct Clustering {
  int k = 0;               // clusters actually used (empty ones are dropped and renumbered)
  std::vector<int> label;  // per frame, 0..k-1, numbered by first appearance in time
  double wcss = 0;         // within-cluster sum of squared distances
};

// frames: 3N x F (one aligned frame per column).
Clustering kmeans_frames(const Eigen::MatrixXd& frames, const ClusterParams& params);

// Renumbers k-means labels 0..k-1 by first appearance in order (out[j] = new id of lab[j]);
// labels no item carries vanish. Returns the number of labels left. Shared by the frame
// clustering and the point segmentation (segment.h).
template <typename Label>
int renumber_by_first_appearance(const std::vector<int>& lab, int k, std::vector<Label>* out) {
  std::vector<int> map(static_cast<size_t>(k), -1);
  int next = 0;
  out->resize(lab.size());
  for (size_t j = 0; j < lab.size(); ++j) {
    int& m = map[static_cast<size_t>(lab[j])];
    if (m < 0) m = next++;
    (*out)[j] = static_cast<Label>(m);
  }
  return next;
}

}  // namespace ts
}  // namespace capz
