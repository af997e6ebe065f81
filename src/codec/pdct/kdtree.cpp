#include "codec/pdct/kdtree.h"

#include <pcl/kdtree/kdtree_flann.h>
#include <pcl/point_cloud.h>
#include <pcl/point_types.h>

namespace capz {
namespace pdct {

std::vector<std::vector<uint32_t>> nearest_neighbours(const double* cloud, size_t points,
                                                      const uint8_t* usable,
                                                      const std::vector<uint32_t>& queries,
                                                      const KnnParams& params) {
  std::vector<std::vector<uint32_t>> out(queries.size());
  pcl::PointCloud<pcl::PointXYZ>::Ptr pc(new pcl::PointCloud<pcl::PointXYZ>);
  std::vector<uint32_t> ids;  // cloud index of each indexed point
  for (size_t i = 0; i < points; ++i) {
    if (usable && !usable[i]) continue;
    pc->push_back(pcl::PointXYZ(static_cast<float>(cloud[3 * i]),
                                static_cast<float>(cloud[3 * i + 1]),
                                static_cast<float>(cloud[3 * i + 2])));
    ids.push_back(static_cast<uint32_t>(i));
  }
  if (pc->size() < 2 || params.k <= 0) return out;
  pcl::KdTreeFLANN<pcl::PointXYZ> tree;
  tree.setSortedResults(true);
  tree.setInputCloud(pc);
  const int want = std::min<int>(params.k + 1, static_cast<int>(pc->size()));
  std::vector<int> idx(want);
  std::vector<float> d2(want);
  for (size_t q = 0; q < queries.size(); ++q) {
    const double* p = cloud + 3 * static_cast<size_t>(queries[q]);
    pcl::PointXYZ qp(static_cast<float>(p[0]), static_cast<float>(p[1]), static_cast<float>(p[2]));
    const int found = tree.nearestKSearch(qp, want, idx, d2);
    for (int j = 0; j < found && static_cast<int>(out[q].size()) < params.k; ++j) {
      const uint32_t id = ids[static_cast<size_t>(idx[j])];
      if (id != queries[q]) out[q].push_back(id);
    }
  }
  return out;
}

}  // namespace pdct
}  // namespace capz
