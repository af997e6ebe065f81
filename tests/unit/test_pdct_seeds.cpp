#include <gtest/gtest.h>

#include <cmath>
#include <limits>
#include <random>

#include "codec/pdct/kdtree.h"
#include "codec/pdct/seeds.h"
#include "synthetic.h"

using namespace capz::pdct;

namespace {
double d2(const double* a, const double* b) {
  return (a[0] - b[0]) * (a[0] - b[0]) + (a[1] - b[1]) * (a[1] - b[1]) +
         (a[2] - b[2]) * (a[2] - b[2]);
}
}  // namespace

TEST(PdctSeeds, GivenCloudWhenSelectingThenFarthestPointOrder) {
  std::mt19937 rng(11);
  std::uniform_real_distribution<double> u(-100, 100);
  const size_t P = 500;
  std::vector<double> xyz(P * 3);
  for (double& v : xyz) v = u(rng);
  const auto seeds = farthest_point_seeds(xyz.data(), P, nullptr, SeedParams{20});
  ASSERT_EQ(seeds.size(), 20u);
  // First: farthest from the centroid.
  double c[3] = {0, 0, 0};
  for (size_t i = 0; i < P; ++i)
    for (int a = 0; a < 3; ++a) c[a] += xyz[3 * i + a] / P;
  for (size_t i = 0; i < P; ++i) EXPECT_LE(d2(&xyz[3 * i], c), d2(&xyz[3 * seeds[0]], c));
  // Each next: maximises the distance to the nearest earlier seed (brute force check).
  for (size_t s = 1; s < seeds.size(); ++s) {
    auto nearest = [&](size_t i) {
      double m = std::numeric_limits<double>::infinity();
      for (size_t t = 0; t < s; ++t) m = std::min(m, d2(&xyz[3 * i], &xyz[3 * seeds[t]]));
      return m;
    };
    const double got = nearest(seeds[s]);
    for (size_t i = 0; i < P; ++i) EXPECT_LE(nearest(i), got);
  }
}

TEST(PdctSeeds, GivenCandidateMaskWhenSelectingThenOnlyCandidates) {
  const double xyz[12] = {0, 0, 0, 100, 0, 0, 1, 0, 0, 2, 0, 0};
  const uint8_t cand[4] = {1, 0, 1, 1};
  const auto seeds = farthest_point_seeds(xyz, 4, cand, SeedParams{3});
  ASSERT_EQ(seeds.size(), 3u);
  for (uint32_t s : seeds) EXPECT_NE(s, 1u);
}

TEST(PdctSeeds, GivenDegenerateTriplesWhenTestedThenRejected) {
  const double a[3] = {0, 0, 0}, b[3] = {10, 0, 0}, c[3] = {5, 8, 0};
  EXPECT_TRUE(triangle_ok(a, b, c, 1.0, 10));
  const double on_line[3] = {20, 0.5, 0};  // angle at a ~1.4 degrees
  EXPECT_FALSE(triangle_ok(a, b, on_line, 1.0, 10));
  const double near_a[3] = {0.5, 0.5, 0};  // edge (a, near_a) ~0.7 < 1
  EXPECT_FALSE(triangle_ok(a, b, near_a, 1.0, 10));
  const double obtuse[3] = {5, 0.3, 0};  // angle at c near 180 degrees
  EXPECT_FALSE(triangle_ok(a, b, obtuse, 1.0, 10));
  EXPECT_FALSE(triangle_ok(a, a, c, 0.0, 10));
}

TEST(PdctSeeds, GivenTripleDegenerateInOneLaterFrameWhenChoosingThenRejected) {
  // 4 points: seed 0 and neighbours 1, 2, 3. Triple (0, 1, 2) is fine in frame 0 but collinear in
  // frame 2; (0, 1, 3) and (0, 2, 3) stay good, so the chosen triangle must avoid {1, 2} together.
  const size_t F = 3, P = 4;
  std::vector<double> xyz(F * P * 3);
  std::vector<uint8_t> valid(F * P, 1);
  const double base[12] = {0, 0, 0, 10, 0, 0, 0, 10, 0, 0, 0, 12};
  for (size_t f = 0; f < F; ++f)
    for (int i = 0; i < 12; ++i) xyz[f * 12 + i] = base[i];
  xyz[2 * 12 + 3 * 2 + 0] = 20;  // point 2 in frame 2 moves onto the x axis
  xyz[2 * 12 + 3 * 2 + 1] = 0;
  const capz::PositionsView v{F, P, xyz.data(), valid.data()};
  TriangleParams tp;
  tp.knn = 3;
  const auto tris = seed_triangles(v, {0}, tp);
  ASSERT_EQ(tris.size(), 1u);
  EXPECT_EQ(tris[0].p1, 0u);
  const bool has1 = tris[0].p2 == 1 || tris[0].p3 == 1, has2 = tris[0].p2 == 2 || tris[0].p3 == 2;
  EXPECT_FALSE(has1 && has2);
  // Every frame passes the test for the chosen triple.
  for (size_t f = 0; f < F; ++f)
    EXPECT_TRUE(triangle_ok(&xyz[3 * (f * P + tris[0].p1)], &xyz[3 * (f * P + tris[0].p2)],
                            &xyz[3 * (f * P + tris[0].p3)], 1e-3 * first_frame_diagonal(v), 10));
}

TEST(PdctSeeds, GivenAllTriplesCollinearWhenChoosingThenSeedDropped) {
  const size_t F = 2, P = 5;
  std::vector<double> xyz(F * P * 3, 0.0);
  std::vector<uint8_t> valid(F * P, 1);
  for (size_t f = 0; f < F; ++f)
    for (size_t i = 0; i < P; ++i) xyz[3 * (f * P + i)] = 10.0 * i + f;  // all on the x axis
  const capz::PositionsView v{F, P, xyz.data(), valid.data()};
  EXPECT_TRUE(seed_triangles(v, {0, 4}, TriangleParams{}).empty());
}

TEST(PdctSeeds, GivenRigidAndSoftNeighboursWhenChoosingThenRigidPreferred) {
  // Body 0 is rigid; point 5 sits near it but wobbles. Seed 0's triangle must avoid point 5.
  auto t = capz_test::rigid_bodies(1, 5, 40, 21);
  const size_t P = 6;
  std::vector<double> xyz(t.frames * P * 3);
  std::vector<uint8_t> valid(t.frames * P, 1);
  for (size_t f = 0; f < t.frames; ++f) {
    for (size_t i = 0; i < 5; ++i)
      for (int a = 0; a < 3; ++a) xyz[3 * (f * P + i) + a] = t.xyz[3 * (f * 5 + i) + a];
    for (int a = 0; a < 3; ++a)
      xyz[3 * (f * P + 5) + a] = xyz[3 * (f * P + 0) + a] + 5.0 + 4.0 * std::sin(0.7 * f + a);
  }
  const capz::PositionsView v{t.frames, P, xyz.data(), valid.data()};
  const auto tris = seed_triangles(v, {0}, TriangleParams{});
  ASSERT_EQ(tris.size(), 1u);
  EXPECT_NE(tris[0].p2, 5u);
  EXPECT_NE(tris[0].p3, 5u);
}

TEST(PdctKdtree, GivenCloudWhenQueryingThenNearestFirstWithoutSelf) {
  const double xyz[15] = {0, 0, 0, 1, 0, 0, 3, 0, 0, 0, 2, 0, 10, 10, 10};
  const auto nb = nearest_neighbours(xyz, 5, nullptr, {0, 4}, KnnParams{3});
  ASSERT_EQ(nb.size(), 2u);
  ASSERT_EQ(nb[0].size(), 3u);
  EXPECT_EQ(nb[0][0], 1u);
  EXPECT_EQ(nb[0][1], 3u);
  EXPECT_EQ(nb[0][2], 2u);
  for (uint32_t i : nb[1]) EXPECT_NE(i, 4u);
}
