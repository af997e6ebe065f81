// pdct stage: nearest neighbours in one frame, through pcl::KdTreeFLANN. This header is
// PCL-free; kdtree.cpp is the only pdct file that includes PCL.
#pragma once

#include <cstddef>
#include <cstdint>
#include <vector>

namespace capz {
namespace pdct {

struct KnnParams {
  int k = 12;  // neighbours wanted per query (fewer when the cloud is smaller)
};

// For each query point index, up to k other point indices of `cloud` (points x 3 doubles),
// nearest first (Euclidean; ties in FLANN's order), never the query itself. Only points with
// usable[i] != 0 are indexed (usable may be null = all). Coordinates are searched as float32,
// which is enough to pick neighbours; the choice is stored in the bitstream, so the decoder never
// searches.
std::vector<std::vector<uint32_t>> nearest_neighbours(const double* cloud, size_t points,
                                                      const uint8_t* usable,
                                                      const std::vector<uint32_t>& queries,
                                                      const KnnParams& params);

}  // namespace pdct
}  // namespace capz
