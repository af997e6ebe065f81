// Decoder library (capz_decode): builds without PCL and without the transform encoders.
#include "codec/ts/basis_predict.h"

#include <algorithm>
#include <cmath>
#include <unordered_map>

namespace capz {
namespace ts {

std::vector<uint32_t> spatial_parents(const std::vector<int32_t>& q1, size_t points) {
  std::vector<uint32_t> parent(points, 0);
  if (points < 2 || q1.size() < 3 * points) return parent;
  int64_t lo[3], hi[3];
  for (int a = 0; a < 3; ++a) lo[a] = hi[a] = q1[static_cast<size_t>(a)];
  for (size_t i = 0; i < points; ++i)
    for (int a = 0; a < 3; ++a) {
      lo[a] = std::min<int64_t>(lo[a], q1[3 * i + a]);
      hi[a] = std::max<int64_t>(hi[a], q1[3 * i + a]);
    }
  const int64_t ext = std::max({hi[0] - lo[0], hi[1] - lo[1], hi[2] - lo[2], int64_t{1}});
  // About one point per cell for a surface sampled by `points` points.
  const int64_t h = std::max<int64_t>(
      1, static_cast<int64_t>(static_cast<double>(ext) / std::sqrt(static_cast<double>(points))));
  const int64_t dims = ext / h + 1;
  auto key = [&](int64_t cx, int64_t cy, int64_t cz) { return (cx * dims + cy) * dims + cz; };
  std::unordered_map<int64_t, std::vector<uint32_t>> grid;
  auto cell = [&](size_t i, int a) { return (q1[3 * i + a] - lo[a]) / h; };
  grid[key(cell(0, 0), cell(0, 1), cell(0, 2))].push_back(0);
  for (size_t i = 1; i < points; ++i) {
    const int64_t c[3] = {cell(i, 0), cell(i, 1), cell(i, 2)};
    int64_t best = INT64_MAX;
    uint32_t bj = static_cast<uint32_t>(i - 1);
    for (int64_t r = 0; r <= dims; ++r) {
      for (int64_t dx = -r; dx <= r; ++dx)
        for (int64_t dy = -r; dy <= r; ++dy)
          for (int64_t dz = -r; dz <= r; ++dz) {
            if (std::max({std::llabs(dx), std::llabs(dy), std::llabs(dz)}) != r) continue;
            const int64_t x = c[0] + dx, y = c[1] + dy, z = c[2] + dz;
            if (x < 0 || y < 0 || z < 0 || x >= dims || y >= dims || z >= dims) continue;
            auto it = grid.find(key(x, y, z));
            if (it == grid.end()) continue;
            for (uint32_t j : it->second) {
              int64_t d = 0;
              for (int a = 0; a < 3; ++a) {
                const int64_t e =
                    static_cast<int64_t>(q1[3 * i + a]) - q1[3 * static_cast<size_t>(j) + a];
                d += e * e;
              }
              if (d < best || (d == best && j > bj)) {
                best = d;
                bj = j;
              }
            }
          }
      // Every point in ring r + 1 or beyond is at least r * h away.
      if (best != INT64_MAX && best <= (r * h) * (r * h)) break;
    }
    parent[i] = bj;
    grid[key(c[0], c[1], c[2])].push_back(static_cast<uint32_t>(i));
  }
  return parent;
}

}  // namespace ts
}  // namespace capz
