// The octree walk's shortcuts that must not change a context (docs/lab/2026-11-30-octree-speed.md):
// the cone index's rings of a box against the box test of every ring, on random tables and on
// the tables fitted to real sweeps; the neighbours' keys by key arithmetic against their
// coordinates' keys.
#include <gtest/gtest.h>

#include <cmath>
#include <random>

#include "capz/io.h"
#include "coding/scan_octree.h"
#include "coding/scan_shared.h"
#include "scan_geometry_expect.h"
#include "test_util.h"

namespace capz {
namespace {

using scan::Cones;

std::vector<uint16_t> every_ring(const Cones& c, const int64_t* a, int64_t side) {
  std::vector<uint16_t> all(c.rings()), out;
  for (size_t k = 0; k < all.size(); ++k) all[k] = static_cast<uint16_t>(k);
  scan::octree::crossing(c, a, side, all.data(), all.size(), all.size(), &out);
  return out;
}

// Whether the index gives every box of `boxes` (x y z side, 4 a box) the rings of the box test;
// the boxes' crossings summed in *crossed.
void expect_same_rings(const Cones& c, const std::vector<int64_t>& boxes, size_t* crossed) {
  const scan::octree::ConeIndex index(c);
  std::vector<uint16_t> got;
  for (size_t j = 0; j + 3 < boxes.size(); j += 4) {
    got.assign(1, 9999);  // appended after what is there
    index.crossing_all(c, &boxes[j], boxes[j + 3], &got);
    const std::vector<uint16_t> want = every_ring(c, &boxes[j], boxes[j + 3]);
    ASSERT_EQ(std::vector<uint16_t>(got.begin() + 1, got.end()), want)
        << "box " << boxes[j] << " " << boxes[j + 1] << " " << boxes[j + 2] << " side "
        << boxes[j + 3];
    *crossed += want.size();
  }
}

TEST(ScanOctreeIndex, GivenRandomTablesAndBoxesThenTheIndexFindsTheRingsOfTheBoxTest) {
  std::mt19937 rng(11);
  std::uniform_real_distribution<double> u(-1, 1);
  size_t crossed = 0, boxes = 0;
  for (int t = 0; t < 200; ++t) {
    Cones c;
    const int rings = 1 + t % 130;
    const double steep = t % 3 == 0 ? 4.0 : 0.4, spread = t % 4 == 0 ? 0.0 : 30.0;
    for (int k = 0; k < rings; ++k) {
      // some equal slopes, some zero and negative zero, offsets from none to wide
      const double s = t % 5 == 0 ? std::round(8 * u(rng)) / 8 : steep * u(rng);
      c.slope.push_back(k % 17 == 3 ? -0.0 : static_cast<float>(s));
      c.z0.push_back(static_cast<float>(spread * u(rng)));
    }
    std::vector<int64_t> b;
    const double reach = t % 2 == 0 ? 300 : 3e6;
    for (int j = 0; j < 400; ++j) {
      const int64_t side = int64_t{1} << (j % 11);
      const double zr = t % 2 == 0 ? 0.6 * reach : 0.05 * reach;
      b.insert(b.end(), {static_cast<int64_t>(reach * u(rng)), static_cast<int64_t>(reach * u(rng)),
                         static_cast<int64_t>(zr * u(rng)), side});
      if (j % 7 == 0) b.insert(b.end(), {-side / 2, -side / 2, b[b.size() - 2], side});  // axis
    }
    boxes += b.size() / 4;
    expect_same_rings(c, b, &crossed);
  }
  EXPECT_GT(crossed, boxes / 4);  // the boxes meet rings, not only miss them
}

// The cones of a sweep's fitted table (the encoder's, octree_cone_table) at per_metre integers a
// metre, and its valid points' integers.
Cones sweep_cones(const std::string& path, double per_metre, std::vector<int32_t>* q) {
  ScanHints hints;
  const ScanGeometry g = sweep_geometry(read_take(path), per_metre, &hints);
  for (size_t i = 0; i < g.valid.size(); ++i)
    if (g.valid[i]) q->insert(q->end(), &g.q[3 * i], &g.q[3 * i] + 3);
  return scan::table_cones(octree_cone_table(g, hints));
}

TEST(ScanOctreeIndex, GivenRealSweepsTablesThenTheIndexFindsTheRingsOfTheBoxTest) {
  const std::string root = capz_test::shared_data_or_skip("scan/single");
  if (root.empty()) return;
  for (const char* name : {"hesai-xt32", "hesai-64", "velodyne-vlp16", "hesai-at128"}) {
    for (const double per_metre : {50.0, 100.0}) {
      std::vector<int32_t> q;
      const Cones c = sweep_cones(root + "/" + name + ".pcd", per_metre, &q);
      ASSERT_GE(c.rings(), 12u) << name;
      // Every 7th point's boxes of sides 1 to 64 holding it (as the walk's), and random ones.
      std::vector<int64_t> b;
      for (size_t i = 0; i + 2 < q.size(); i += 3 * 7)
        for (int64_t side = 1; side <= 64; side *= 2)
          b.insert(b.end(), {q[i] & -side, q[i + 1] & -side, q[i + 2] & -side, side});
      std::mt19937 rng(5);
      std::uniform_int_distribution<int64_t> u(-20000, 20000);
      for (int j = 0; j < 20000; ++j) b.insert(b.end(), {u(rng), u(rng), u(rng) / 10, 4});
      size_t crossed = 0;
      expect_same_rings(c, b, &crossed);
      EXPECT_GT(crossed, b.size() / 8) << name;
    }
  }
}

TEST(ScanOctreeIndex, GivenNodesThenTheirNeighboursKeysAreTheKeysOfTheirCoordinates) {
  std::mt19937_64 rng(13);
  size_t inside = 0, outside = 0;
  for (int t = 0; t < 20000; ++t) {
    const int bits = 1 + t % 21;
    const int64_t side = int64_t{1} << bits;
    int64_t v[3];
    for (int64_t& x : v) {  // often at a face of the cube
      const uint64_t r = rng();
      x = r % 4 == 0 ? 0 : r % 4 == 1 ? side - 1 : static_cast<int64_t>(rng() % uint64_t(side));
    }
    const uint64_t k = scan::octree::key(uint64_t(v[0]), uint64_t(v[1]), uint64_t(v[2]));
    std::vector<std::pair<int, uint64_t>> got, want;
    scan::octree::Around(k, v, side).each([&](int e, uint64_t n) { got.emplace_back(e, n); });
    for (int e = 0; e < 27; ++e) {
      const int64_t c[3] = {v[0] + e / 9 - 1, v[1] + (e / 3) % 3 - 1, v[2] + e % 3 - 1};
      bool in = e != 13;
      for (int64_t x : c) in = in && x >= 0 && x < side;
      if (in)
        want.emplace_back(e, scan::octree::key(uint64_t(c[0]), uint64_t(c[1]), uint64_t(c[2])));
    }
    ASSERT_EQ(got, want) << t;
    inside += want.size();
    outside += 26 - want.size();
  }
  EXPECT_GT(outside, 20000u);
  EXPECT_GT(inside, 20000u);
}

}  // namespace
}  // namespace capz
