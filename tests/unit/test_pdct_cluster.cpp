#include <gtest/gtest.h>

#include <set>

#include "codec/pdct/cluster.h"
#include "codec/pdct/seeds.h"
#include "synthetic.h"

using namespace capz::pdct;

TEST(PdctCluster, GivenTwoRigidBodiesWhenClusteredThenEachBodyTogether) {
  const size_t per = 30;
  const auto t = capz_test::rigid_bodies(2, per, 60, 5, 0.01);
  const auto v = t.view();
  // One triangle on each body (points 0-2 on body 0, 30-32 on body 1).
  std::vector<Lcf> lcfs;
  const uint32_t tri[2][3] = {{0, 1, 2}, {30, 31, 32}};
  for (int k = 0; k < 2; ++k)
    for (size_t f = 0; f < t.frames; ++f) {
      const double* b = &t.xyz[3 * f * t.points];
      lcfs.push_back(make_lcf(b + 3 * tri[k][0], b + 3 * tri[k][1], b + 3 * tri[k][2]));
    }
  std::vector<uint8_t> fp(t.points, 0);
  for (auto& tr : tri)
    for (uint32_t i : tr) fp[i] = 1;
  const auto c = assign_clusters(v, lcfs, 2, fp, ClusterParams{});
  for (size_t i = 0; i < t.points; ++i) {
    if (fp[i]) {
      EXPECT_EQ(c[i], -1);
      continue;
    }
    EXPECT_EQ(c[i], i < per ? 0 : 1) << "point " << i;
  }
}

TEST(PdctCluster, GivenSeedsFromFarthestPointWhenClusteredThenBodiesNotMixed) {
  // End to end over the encoder's stages: seeds, triangles, clustering, on three bodies.
  const size_t per = 25;
  const auto t = capz_test::rigid_bodies(3, per, 50, 9, 0.01);
  const auto v = t.view();
  const auto seeds = farthest_point_seeds(t.xyz.data(), t.points, nullptr, SeedParams{3});
  const auto tris = seed_triangles(v, seeds, TriangleParams{});
  ASSERT_EQ(tris.size(), 3u);
  std::set<size_t> bodies;
  std::vector<Lcf> lcfs;
  std::vector<uint8_t> fp(t.points, 0);
  for (const auto& tr : tris) {
    // Each triangle is rigid: all three points on one body.
    EXPECT_EQ(tr.p1 / per, tr.p2 / per);
    EXPECT_EQ(tr.p1 / per, tr.p3 / per);
    bodies.insert(tr.p1 / per);
    fp[tr.p1] = fp[tr.p2] = fp[tr.p3] = 1;
    for (size_t f = 0; f < t.frames; ++f) {
      const double* b = &t.xyz[3 * f * t.points];
      lcfs.push_back(make_lcf(b + 3 * tr.p1, b + 3 * tr.p2, b + 3 * tr.p3));
    }
  }
  EXPECT_EQ(bodies.size(), 3u);  // farthest-point seeds land on three different bodies
  const auto c = assign_clusters(v, lcfs, 3, fp, ClusterParams{});
  for (size_t i = 0; i < t.points; ++i)
    if (!fp[i]) {
      EXPECT_EQ(tris[static_cast<size_t>(c[i])].p1 / per, i / per) << "point " << i;
    }
}
