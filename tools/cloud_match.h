// Benchmark helpers (tools/ only): pairs each point of an original cloud with its nearest decoded
// point, for peers that reorder points or change their number (Draco's kd-tree coder, PCL's
// octree coder). The distance is the per-coordinate (Chebyshev) one, max over x y z of |a - b|,
// the measure capz's --max-error bounds, so the error a pairing reports compares directly with
// the bound; being a nearest neighbour, it is a lower bound of the error under the true
// correspondence, which these peers do not give back.
#pragma once

#include <algorithm>
#include <cmath>
#include <cstdint>
#include <limits>
#include <unordered_map>
#include <vector>

namespace capz_tools {

// Decoded points (n x 3 floats) in a uniform grid of cell `h`; nearest() is exact.
class CloudGrid {
 public:
  CloudGrid(const std::vector<float>& xyz, double h) : xyz_(xyz), h_(h > 0 ? h : 1) {
    size_t n = xyz.size() / 3;
    for (size_t i = 0; i < n; ++i)
      cells_[key(cell(&xyz[i * 3]))].push_back(static_cast<uint32_t>(i));
  }

  // Index of the decoded point nearest to q (per-coordinate distance) and that distance in *d;
  // -1 when the grid holds no points. With `ties`, every decoded point at exactly that distance
  // (points a coarse grid made coincide: a pairing cannot tell them apart, so attributes are
  // compared with each of them).
  long nearest(const float* q, double* d, std::vector<uint32_t>* ties = nullptr) const {
    *d = std::numeric_limits<double>::infinity();
    long best = -1;
    if (ties) ties->clear();
    if (cells_.empty()) return best;
    Cell c = cell(q);
    // Points in cells at ring r (Chebyshev cell offset r) are at least (r - 1) h away: once the
    // best distance is below r h, no farther ring can beat or tie it.
    for (int64_t r = 0;; ++r) {
      for (int64_t dx = -r; dx <= r; ++dx)
        for (int64_t dy = -r; dy <= r; ++dy)
          for (int64_t dz = -r; dz <= r; ++dz) {
            if (std::max({std::llabs(dx), std::llabs(dy), std::llabs(dz)}) != r) continue;
            auto it = cells_.find(key({c.x + dx, c.y + dy, c.z + dz}));
            if (it == cells_.end()) continue;
            for (uint32_t i : it->second) {
              const float* p = &xyz_[static_cast<size_t>(i) * 3];
              double e = 0;
              for (int a = 0; a < 3; ++a)
                e = std::max(e, std::fabs(static_cast<double>(p[a]) - static_cast<double>(q[a])));
              if (e < *d) {
                *d = e;
                best = i;
                if (ties) ties->clear();
              }
              if (ties && e == *d) ties->push_back(i);
            }
          }
      if (best >= 0 && *d < static_cast<double>(r) * h_) return best;
      // Beyond 64 cells the search stops: the distance is then that of the best point found
      // (an upper bound of the nearest one), or infinite.
      if (r >= 64) return best;
    }
  }

 private:
  struct Cell {
    int64_t x, y, z;
  };
  Cell cell(const float* p) const {
    return {static_cast<int64_t>(std::floor(p[0] / h_)),
            static_cast<int64_t>(std::floor(p[1] / h_)),
            static_cast<int64_t>(std::floor(p[2] / h_))};
  }
  static uint64_t key(const Cell& c) {
    auto u = [](int64_t v) { return static_cast<uint64_t>(v) & 0x1fffffu; };  // 21 bits an axis
    return u(c.x) | (u(c.y) << 21) | (u(c.z) << 42);
  }
  const std::vector<float>& xyz_;
  double h_;
  std::unordered_map<uint64_t, std::vector<uint32_t>> cells_;
};

}  // namespace capz_tools
