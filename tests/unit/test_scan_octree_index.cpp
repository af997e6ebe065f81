// The octree walk's shortcuts that must not change a context (docs/lab/2026-11-30-octree-speed.md):
// the cone index's rings of a box against the box test of every ring, on random tables and on
// the tables fitted to real sweeps; the neighbours' keys by key arithmetic against their
// coordinates' keys; the walk's and the counts' contexts against lookups by coordinates.
#include <gtest/gtest.h>

#include <cmath>
#include <limits>
#include <random>

#include "capz/error.h"
#include "capz/io.h"
#include "coding/scan_octree.h"
#include "coding/scan_shared.h"
#include "scan_geometry_expect.h"
#include "support/octree_reference.h"
#include "test_util.h"

namespace capz {
namespace {

using scan::Cones;

std::vector<uint16_t> every_ring(const Cones& c, const int64_t* a, int64_t side) {
  std::vector<uint16_t> all(c.rings()), out;
  for (size_t k = 0; k < all.size(); ++k) all[k] = static_cast<uint16_t>(k);
  scan::octree::crossing(c, a, side, all.data(), all.size(), &out);
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

// A crafted table's extremes (docs/lab/2026-11-30-octree-review.md): f32 slopes and offsets up to
// FLT_MAX, denormals, many equal, and boxes up to the grid integers' ends with sides to 2^21.
// Every product and sum stays finite in binary64 (|s rho| < 2^128 2^32), so the sort's order is
// strict and weak, and the bisection's runs hold: the same rings as the box test.
TEST(ScanOctreeIndex, GivenExtremeTablesAndBoxesThenTheIndexFindsTheRingsOfTheBoxTest) {
  std::mt19937 rng(23);
  const float big = std::numeric_limits<float>::max(),
              tiny = std::numeric_limits<float>::denorm_min();
  const std::vector<float> some = {big,  -big,  1e30f, -1e30f, 1e-30f, -1e-30f, tiny, -tiny,
                                   0.0f, -0.0f, 1.0f,  -1.0f,  3e9f,   -3e9f,   0.5f, -0.5f};
  const int64_t ends[] = {-(int64_t{1} << 31), (int64_t{1} << 31) - 1, 0, -1, 1};
  size_t crossed = 0, boxes = 0;
  for (int t = 0; t < 300; ++t) {
    Cones c;
    const size_t rings = 1 + rng() % 256;
    for (size_t k = 0; k < rings; ++k) {
      c.slope.push_back(some[rng() % (t % 2 == 0 ? 4 : some.size())]);
      c.z0.push_back(t % 3 == 0 ? 0.0f : some[rng() % some.size()]);
    }
    std::vector<int64_t> b;
    for (int j = 0; j < 200; ++j) {
      const int64_t side = int64_t{1} << (rng() % 22);
      int64_t a[3];
      for (int64_t& x : a) {  // at the ends, about 0, or anywhere, within [-2^31, 2^31 - side]
        const int64_t e = ends[rng() % 5], top = (int64_t{1} << 31) - side;
        x = rng() % 3 == 0 ? static_cast<int64_t>(rng() % (uint64_t{1} << 32)) - (int64_t{1} << 31)
                           : e - side / 2;
        x = std::min(std::max(x, -(int64_t{1} << 31)), top);
      }
      b.insert(b.end(), {a[0], a[1], a[2], side});
    }
    boxes += b.size() / 4;
    expect_same_rings(c, b, &crossed);
  }
  EXPECT_GT(crossed, boxes / 8);
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

// The walk's child bits, and the contexts it asks for.
struct Recorder {
  std::vector<std::vector<uint64_t>> levels;
  std::vector<int> ctx;
  bool bit(int c, int l, uint64_t k) {
    ctx.push_back(c);
    const std::vector<uint64_t>& n = levels[static_cast<size_t>(l) + 1];
    return std::binary_search(n.begin(), n.end(), k);
  }
  [[noreturn]] void too_many() { throw Error(ErrorCode::kInternal, "too many"); }
  [[noreturn]] void too_much() { throw Error(ErrorCode::kInternal, "too much"); }
};

// Sorted distinct keys of the cells (x y z from lo, 4 ints a cell as the previous frame's).
std::vector<uint64_t> keys_of(const std::vector<int32_t>& cells, const int64_t* lo) {
  std::vector<uint64_t> k;
  for (size_t j = 0; j + 3 < cells.size(); j += 4)
    k.push_back(scan::octree::key(uint64_t(cells[j] - lo[0]), uint64_t(cells[j + 1] - lo[1]),
                                  uint64_t(cells[j + 2] - lo[2])));
  std::sort(k.begin(), k.end());
  k.erase(std::unique(k.begin(), k.end()), k.end());
  return k;
}

// Cells of a depth-d cube from lo: clusters on a few surfaces and scattered ones, on its faces
// too, with points 1-12 each.
std::vector<int32_t> some_cells(std::mt19937* rng, int d, const int64_t* lo, size_t n) {
  const int64_t side = int64_t{1} << d;
  std::uniform_int_distribution<int64_t> u(0, side - 1);
  std::vector<int32_t> c;
  for (size_t j = 0; j < n; ++j) {
    int64_t v[3] = {u(*rng), u(*rng), u(*rng)};
    if (j % 3 == 0) v[2] = (v[0] / 2 + v[1] / 3) % side;  // a slanted plane
    if (j % 7 == 0) v[j % 3] = j % 2 == 0 ? 0 : side - 1;
    for (int a = 0; a < 3; ++a) c.push_back(static_cast<int32_t>(lo[a] + v[a]));
    c.push_back(static_cast<int32_t>(1 + (*rng)() % 12));
  }
  return c;
}

// The walk's contexts against FORMAT.md step 4 worked out with hash lookups of coordinates
// (bit_context over KeySets of each level, of the next level so far and of the previous frame's
// cells), on random trees with and without a previous frame.
TEST(ScanOctreeIndex, GivenRandomTreesThenTheWalksContextsAreTheLookupsOfTheirCoordinates) {
  std::mt19937 rng(17);
  size_t asked = 0;
  for (int t = 0; t < 12; ++t) {
    const int d = 3 + t % 5;
    const int64_t lo[3] = {-37, 5, -(int64_t{1} << d) / 2};
    const std::vector<int32_t> cells = some_cells(&rng, d, lo, 40u << (t % 5));
    const std::vector<int32_t> prev = t % 2 ? some_cells(&rng, d, lo, 200) : std::vector<int32_t>{};
    Recorder io;
    io.levels.resize(static_cast<size_t>(d) + 1);
    io.levels.back() = keys_of(cells, lo);
    for (int l = d - 1; l >= 0; --l)
      for (uint64_t k : io.levels[static_cast<size_t>(l) + 1])
        if (io.levels[size_t(l)].empty() || io.levels[size_t(l)].back() != k >> 3)
          io.levels[size_t(l)].push_back(k >> 3);
    const std::vector<uint64_t> got =
        scan::octree::code_tree(io, d, io.levels.back().size(), lo, prev);
    ASSERT_EQ(got, io.levels.back());
    std::vector<std::vector<uint64_t>> earlier;
    scan::octree::previous_levels(prev, lo, d, &earlier);
    size_t at = 0;
    for (int l = 0; l < d; ++l) {
      const std::vector<uint64_t>& level = io.levels[size_t(l)];
      const std::vector<uint64_t>& below = io.levels[size_t(l) + 1];
      scan::octree::KeySet here, next, before;
      here.reset(level.size());
      for (uint64_t k : level) here.insert(k, 0);
      next.reset(below.size());
      before.reset(earlier[size_t(l) + 1].size());
      for (uint64_t k : earlier[size_t(l) + 1]) before.insert(k, 0);
      const int64_t side = int64_t{1} << l;
      for (uint64_t pk : level) {
        int64_t p[3];
        scan::octree::coords(pk, p);
        int nb[27];
        for (int e = 0; e < 27; ++e) {
          const int64_t c[3] = {p[0] + e / 9 - 1, p[1] + (e / 3) % 3 - 1, p[2] + e % 3 - 1};
          nb[e] = capz_test::has(here, c, side);
        }
        int ones = 0;
        for (int i = 0; i < 8; ++i) {
          const uint64_t ck = pk << 3 | uint64_t(i);
          if (i < 7 || ones > 0) {
            ASSERT_LT(at, io.ctx.size());
            ASSERT_EQ(io.ctx[at], capz_test::bit_context(nb, next, before, p, l, d, i, ones))
                << "tree " << t << " level " << l << " child " << ck;
            ++at;
          }
          if (!std::binary_search(below.begin(), below.end(), ck)) continue;
          next.insert(ck, 0);
          ++ones;
        }
      }
    }
    EXPECT_EQ(at, io.ctx.size());
    asked += at;
  }
  EXPECT_GT(asked, 10000u);
}

// A cell's count context (FORMAT.md step 5) against its 26 neighbours looked up by coordinates.
TEST(ScanOctreeIndex, GivenRandomCellsThenTheCountContextsNeighboursAreTheCellsBeforeThem) {
  std::mt19937 rng(19);
  for (int t = 0; t < 6; ++t) {
    const int d = 4 + t;
    const int64_t lo[3] = {3, -9, 0};
    const std::vector<int32_t> c = some_cells(&rng, d, lo, 60u << t);
    const std::vector<uint64_t> cells = keys_of(c, lo);
    scan::octree::KeySet set, none;
    set.reset(cells.size());
    for (size_t j = 0; j < cells.size(); ++j) set.insert(cells[j], static_cast<uint32_t>(j));
    none.reset(0);
    std::vector<uint32_t> points(cells.size());
    for (size_t j = 0; j < cells.size(); ++j) points[j] = 1 + static_cast<uint32_t>(rng() % 12);
    for (size_t j = 0; j < cells.size(); ++j) {
      int64_t v[3], a[3];
      scan::octree::coords(cells[j], v);
      for (int e = 0; e < 3; ++e) a[e] = v[e] + lo[e];
      uint64_t k = 0, sum = 0;
      for (int e = 0; e < 27; ++e) {
        const int64_t n[3] = {v[0] + e / 9 - 1, v[1] + (e / 3) % 3 - 1, v[2] + e % 3 - 1};
        if (e == 13 || n[0] < 0 || n[1] < 0 || n[2] < 0) continue;
        const int64_t at =
            set.find(scan::octree::key(uint64_t(n[0]), uint64_t(n[1]), uint64_t(n[2])));
        if (at >= 0 && size_t(at) < j) ++k, sum += points[size_t(at)];
      }
      // the class of the neighbours' mean points (FORMAT.md step 5): none, < 1.5, 2.5, 4, 8, more
      const double mean = k == 0 ? 0 : double(sum) / double(k);
      const int nc = k == 0 ? 0 : 1 + (mean >= 1.5) + (mean >= 2.5) + (mean >= 4) + (mean >= 8);
      const int ctx = scan::octree::count_context(cells, set, points, j, a, none, {});
      ASSERT_EQ((ctx - scan::kOctCountCtx) / 6 % 6, nc) << t << " " << j;
    }
  }
}

}  // namespace
}  // namespace capz
