#include <gtest/gtest.h>

#include <random>
#include <set>

#include "codec/ts/cluster.h"

using namespace capz::ts;

TEST(TsCluster, GivenThreePlantedPosesWhenClusteredThenFramesGroupedByPose) {
  const int dim = 60, per = 20;
  std::mt19937 rng(3);
  std::normal_distribution<double> n01(0, 1);
  Eigen::MatrixXd centre(dim, 3);
  for (int c = 0; c < 3; ++c)
    for (int i = 0; i < dim; ++i) centre(i, c) = 5 * n01(rng);
  // Frames cycle through the poses in time (0,1,2,0,1,2,...) with small noise.
  Eigen::MatrixXd x(dim, 3 * per);
  std::vector<int> truth(3 * per);
  for (int f = 0; f < 3 * per; ++f) {
    truth[f] = f % 3;
    for (int i = 0; i < dim; ++i) x(i, f) = centre(i, truth[f]) + 0.1 * n01(rng);
  }
  ClusterParams p;
  p.k = 3;
  Clustering cl = kmeans_frames(x, p);
  ASSERT_EQ(cl.k, 3);
  // Same partition up to renumbering; labels are numbered by first appearance.
  for (int f = 0; f < 3 * per; ++f) EXPECT_EQ(cl.label[f], truth[f]) << "frame " << f;
  // Deterministic.
  Clustering again = kmeans_frames(x, p);
  EXPECT_EQ(again.label, cl.label);
}

TEST(TsCluster, GivenMoreClustersThanFramesThenEveryFrameItsOwn) {
  Eigen::MatrixXd x(2, 3);
  x << 0, 1, 5, 0, 1, 5;
  ClusterParams p;
  p.k = 10;
  Clustering cl = kmeans_frames(x, p);
  EXPECT_EQ(cl.k, 3);
  EXPECT_EQ(std::set<int>(cl.label.begin(), cl.label.end()).size(), 3u);
}
