#include "codec/pdct/kdtree.h"

#include <algorithm>

#include "codec/pcl_geom.h"

namespace capz {
namespace pdct {

std::vector<std::vector<uint32_t>> nearest_neighbours(const double* cloud, size_t points,
                                                      const uint8_t* usable,
                                                      const std::vector<uint32_t>& queries,
                                                      const KnnParams& params) {
  std::vector<std::vector<uint32_t>> out(queries.size());
  std::vector<float> pc;      // the indexed points, float32
  std::vector<uint32_t> ids;  // cloud index of each indexed point
  for (size_t i = 0; i < points; ++i) {
    if (usable && !usable[i]) continue;
    for (int a = 0; a < 3; ++a)
      pc.push_back(static_cast<float>(cloud[3 * i + static_cast<size_t>(a)]));
    ids.push_back(static_cast<uint32_t>(i));
  }
  if (ids.size() < 2 || params.k <= 0) return out;
  std::vector<float> qs;
  qs.reserve(queries.size() * 3);
  for (uint32_t q : queries)
    for (int a = 0; a < 3; ++a)
      qs.push_back(static_cast<float>(cloud[3 * size_t{q} + static_cast<size_t>(a)]));
  const int want = std::min<int>(params.k + 1, static_cast<int>(ids.size()));
  std::vector<int> idx, found;
  geom::backend("pdct").knn(pc.data(), ids.size(), qs.data(), queries.size(), want, &idx, &found);
  for (size_t q = 0; q < queries.size(); ++q) {
    for (int j = 0; j < found[q] && static_cast<int>(out[q].size()) < params.k; ++j) {
      const uint32_t id =
          ids[static_cast<size_t>(idx[q * static_cast<size_t>(want) + static_cast<size_t>(j)])];
      if (id != queries[q]) out[q].push_back(id);
    }
  }
  return out;
}

}  // namespace pdct
}  // namespace capz
