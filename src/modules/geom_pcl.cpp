// libcapz_pcl_geom.so: the encoders' PCL geometry (codec/pcl_geom.h says why it is a module),
// loaded by capz with dlopen the first time pdct searches neighbours or ts aligns frames. Only
// PCL calls live here; which points go in, and what is kept of the answer, stay in
// codec/pdct/kdtree.cpp and codec/ts/align.cpp.
#include <pcl/kdtree/kdtree_flann.h>
#include <pcl/point_cloud.h>
#include <pcl/point_types.h>
#include <pcl/registration/transformation_estimation_svd.h>

#include "codec/pcl_geom.h"

namespace capz {
namespace geom {
namespace {

pcl::PointCloud<pcl::PointXYZ> cloud_of(const float* p, size_t n) {
  pcl::PointCloud<pcl::PointXYZ> c;
  c.reserve(n);
  for (size_t i = 0; i < n; ++i) c.push_back(pcl::PointXYZ(p[3 * i], p[3 * i + 1], p[3 * i + 2]));
  return c;
}

class PclGeom : public Backend {
 public:
  void knn(const float* points, size_t n, const float* queries, size_t nq, int want,
           std::vector<int>* idx, std::vector<int>* found) const override {
    pcl::PointCloud<pcl::PointXYZ>::Ptr pc(new pcl::PointCloud<pcl::PointXYZ>(cloud_of(points, n)));
    pcl::KdTreeFLANN<pcl::PointXYZ> tree;
    tree.setSortedResults(true);
    tree.setInputCloud(pc);
    const size_t w = static_cast<size_t>(want);
    idx->assign(nq * w, -1);
    found->assign(nq, 0);
    std::vector<int> k(w);
    std::vector<float> d2(w);
    for (size_t q = 0; q < nq; ++q) {
      const float* p = queries + 3 * q;
      const int got = tree.nearestKSearch(pcl::PointXYZ(p[0], p[1], p[2]), want, k, d2);
      (*found)[q] = got;
      for (int j = 0; j < got && j < want; ++j)
        (*idx)[q * w + static_cast<size_t>(j)] = k[static_cast<size_t>(j)];
    }
  }
  void rigid(const float* src, const float* tgt, size_t n, double m[16]) const override {
    pcl::registration::TransformationEstimationSVD<pcl::PointXYZ, pcl::PointXYZ, double> est;
    Eigen::Matrix4d t = Eigen::Matrix4d::Identity();
    est.estimateRigidTransformation(cloud_of(src, n), cloud_of(tgt, n), t);
    for (int r = 0; r < 4; ++r)
      for (int c = 0; c < 4; ++c) m[4 * r + c] = t(r, c);
  }
};

}  // namespace
}  // namespace geom
}  // namespace capz

extern "C" __attribute__((visibility("default"))) const capz::geom::Backend*
CAPZ_GEOM_BACKEND_ENTRY() {
  static const capz::geom::PclGeom backend;
  return &backend;
}
