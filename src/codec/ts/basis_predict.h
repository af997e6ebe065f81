// ts codec — prediction of the quantised PCA basis across points (an addition to the paper,
// whose bases are stored as plain quantised values). Eigen-shapes are smooth over the object, so
// a point's basis entries are close to those of a spatial neighbour. Connectivity-free: the
// neighbour ("parent") of point i is the nearest point j < i in the geometry given by the
// cluster's first quantised basis vector (the cluster's mean shape up to scale: the PCA is not
// centred), found with exact integer arithmetic so encoder and decoder agree. The first basis
// vector itself is predicted from the previous point (i - 1).
#pragma once

#include <cstddef>
#include <cstdint>
#include <vector>

namespace capz {
namespace ts {

// parent[i] for i >= 1 (parent[0] = 0, unused): the j < i minimising the squared distance
// between the integer 3-vectors q1[3i..3i+2] and q1[3j..3j+2]; among equal distances the
// largest j. Found with a uniform grid (expected linear time).
std::vector<uint32_t> spatial_parents(const std::vector<int32_t>& q1, size_t points);

// Prediction of entry (point i, axis a) of a basis vector q: the parent's entry; 0 for point 0;
// `parents` empty = point i - 1.
inline int64_t basis_prediction(const int32_t* q, const std::vector<uint32_t>& parents, size_t i,
                                int a) {
  if (i == 0) return 0;
  const size_t p = parents.empty() ? i - 1 : parents[i];
  return q[3 * p + static_cast<size_t>(a)];
}

}  // namespace ts
}  // namespace capz
