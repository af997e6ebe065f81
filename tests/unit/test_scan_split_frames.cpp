// Split frames (docs/FORMAT.md "Split frames"): a window whose frames are split into an octree
// near part and a per-point far part decodes to each frame's near points then its far points,
// the parts joined into the window's frames; a near part keeps the previous near part's cells
// through a far part; the header's checks; and real data at 1 cm (a hesai-qt64 sweep, the first
// two robosense-helios16p sweeps) on which the encoder chooses the split, smaller than without it
// and within the bound.
#include <gtest/gtest.h>

#include <cmath>
#include <random>

#include "capz/error.h"
#include "capz/io.h"
#include "codec/grid.h"
#include "codec/point_order.h"
#include "coding/scan_octree.h"
#include "coding/scan_shared.h"
#include "test_util.h"

namespace capz {
namespace {

// A frame's two parts on a 2 cm grid (50 a metre): near, a wall and a floor within a metre with
// several points a cell (and `gaps` gaps after them, octree order); far, `far` points 10-30 m
// away, one a cell, in file order.
struct Parts {
  ScanGeometry near, far;
};

Parts frame_parts(uint32_t near, uint32_t far, uint32_t gaps, unsigned seed) {
  std::mt19937 rng(seed);
  std::uniform_real_distribution<double> u(0, 1);
  Parts p;
  for (uint32_t i = 0; i < near; ++i) {
    const double a = u(rng), b = u(rng);
    const double v[3] = {u(rng) < 0.5 ? 0.6 : 0.8 * a, b - 0.5, u(rng) < 0.5 ? -0.5 : 0.5 * a};
    for (double x : v) p.near.q.push_back(static_cast<int32_t>(std::floor(x * 50 + 0.5)));
    p.near.valid.push_back(1);
  }
  for (uint32_t i = 0; i < gaps; ++i) p.near.q.insert(p.near.q.end(), {0, 0, 0});
  p.near.valid.resize(near + gaps, 0);
  p.near.counts.push_back(near + gaps);
  ScanGeometry sorted = p.near;
  const std::vector<uint32_t> order = octree_frame_order(p.near, 0, near + gaps);
  for (size_t j = 0; j < order.size(); ++j) {
    sorted.valid[j] = p.near.valid[order[j]];
    std::copy_n(&p.near.q[3 * size_t{order[j]}], 3, &sorted.q[3 * j]);
  }
  p.near = sorted;
  for (uint32_t i = 0; i < far; ++i) {
    const double r = 10 + 20 * u(rng), phi = 6.283 * u(rng);
    const double v[3] = {r * std::cos(phi), r * std::sin(phi), 2 * u(rng) - 1};
    for (double x : v) p.far.q.push_back(static_cast<int32_t>(std::floor(x * 50 + 0.5)));
    p.far.valid.push_back(1);
  }
  p.far.counts.push_back(far);
  return p;
}

// g with `part`'s frame appended (no frame when `part` has no point and `skip_empty`).
void append(ScanGeometry* g, const ScanGeometry& part) {
  g->counts.push_back(part.counts.at(0));
  g->q.insert(g->q.end(), part.q.begin(), part.q.end());
  g->valid.insert(g->valid.end(), part.valid.begin(), part.valid.end());
}

// A window of frames given as {near, far, gaps} points: the near geometry (one frame each), the
// far one (a frame for each frame with far points or no near point), which frames have a far
// part, and the decoded window expected (each frame's near points then its far ones).
struct Window {
  ScanGeometry near, far, whole;
  std::vector<uint8_t> has_far;
};

Window window(const std::vector<std::array<uint32_t, 3>>& frames) {
  Window w;
  unsigned seed = 1;
  for (const std::array<uint32_t, 3>& f : frames) {
    const Parts p = frame_parts(f[0], f[1], f[0] > 0 ? f[2] : 0, seed++);
    append(&w.near, p.near);
    ScanGeometry far = p.far;
    if (f[0] == 0) {  // gaps go with the far part when there is no near point
      far.valid.resize(f[1] + f[2], 0);
      far.q.resize(3 * far.valid.size(), 0);
      far.counts[0] = f[1] + f[2];
    }
    w.has_far.push_back(f[0] == 0 || f[1] > 0);
    if (w.has_far.back()) append(&w.far, far);
    ScanGeometry both = p.near;
    both.counts[0] += far.counts[0];
    both.q.insert(both.q.end(), far.q.begin(), far.q.end());
    both.valid.insert(both.valid.end(), far.valid.begin(), far.valid.end());
    append(&w.whole, both);
  }
  return w;
}

std::vector<uint8_t> split_payload(const Window& w) {
  return encode_scan_split(w.near, encode_scan_geometry(w.far), w.has_far);
}

TEST(ScanSplitFrames, GivenAWindowOfSplitFramesThenEachFrameIsItsNearThenItsFarPoints) {
  // Split with gaps, far only with gaps, near only (an octree frame), split without gaps.
  const Window w = window({{{3000, 500, 20}}, {{0, 400, 10}}, {{2000, 0, 0}}, {{2500, 300, 0}}});
  const std::vector<uint8_t> p = split_payload(w);
  ASSERT_FALSE(p.empty());
  const ScanGeometry d = decode_scan_geometry(p.data(), p.size(), "split");
  EXPECT_TRUE(d.octree);
  EXPECT_EQ(d.counts, w.whole.counts);
  EXPECT_EQ(d.valid, w.whole.valid);
  EXPECT_EQ(d.q, w.whole.q);
  const scan::Header h = scan::read_header(p.data(), p.size(), "split", SIZE_MAX);
  ASSERT_EQ(h.counts.size(), 6u);  // the two split frames' far parts are frames of the payload
  const uint8_t near = scan::kOctreeFrame | scan::kNearPart | scan::kCells;
  EXPECT_EQ(h.flags[0], near | scan::kSomeValid);
  EXPECT_FALSE(scan::octree_frame(h.flags[1]));
  EXPECT_FALSE(scan::octree_frame(h.flags[2]));
  EXPECT_EQ(h.flags[3], scan::kOctreeFrame | scan::kCells);
  EXPECT_EQ(h.flags[4], near);
  EXPECT_FALSE(scan::octree_frame(h.flags[5]));
  std::vector<uint64_t> counts(w.whole.counts.begin(), w.whole.counts.end());
  EXPECT_EQ(scan_frame_counts(p.data(), p.size(), "split"), counts);
}

// FORMAT.md "Split frames": after a far part, a near part's previous cells are those of the near
// part before it. Two equal split frames: the second's near part costs a fraction of the first's
// (the far parts, points off any table, cost about the same each).
TEST(ScanSplitFrames, GivenTheSameSplitFrameTwiceThenTheSecondNearPartSeesTheFirst) {
  Window one = window({{{6000, 50, 0}}});
  Window two = one;
  append(&two.near, one.near);
  append(&two.far, one.far);
  append(&two.whole, one.whole);
  two.has_far.push_back(1);
  const std::vector<uint8_t> p1 = split_payload(one), p2 = split_payload(two);
  const ScanGeometry d = decode_scan_geometry(p2.data(), p2.size(), "split");
  EXPECT_EQ(d.q, two.whole.q);
  EXPECT_EQ(d.counts, two.whole.counts);
  const std::vector<uint8_t> far1 = encode_scan_geometry(one.far),
                             far2 = encode_scan_geometry(two.far);
  const size_t near1 = p1.size() - far1.size(), near2 = p2.size() - far2.size();
  EXPECT_LT(near2 - near1, near1 / 2) << near1 << " then " << near2;
}

// Decoding p is corrupt, saying `why`.
void expect_corrupt(const std::vector<uint8_t>& p, const std::string& why) {
  try {
    decode_scan_geometry(p.data(), p.size(), "split");
    ADD_FAILURE() << "decoded";
  } catch (const Error& e) {
    EXPECT_EQ(e.code(), ErrorCode::kCorrupt);
    EXPECT_NE(std::string(e.what()).find(why), std::string::npos) << e.what();
  }
}

TEST(ScanSplitFrames, GivenANearPartWithoutAFarPartThenCorrupt) {
  const std::string why = "near part is not followed by a far part";
  // The payload's last frame an octree frame with bit 3.
  const Window w = window({{{0, 400, 0}}, {{2000, 0, 0}}});
  std::vector<uint8_t> p = split_payload(w);
  const scan::Header h = scan::read_header(p.data(), p.size(), "split", SIZE_MAX);
  ASSERT_EQ(h.flags[1], scan::kOctreeFrame | scan::kCells);
  p[h.flags_end - 1] |= scan::kNearPart;
  expect_corrupt(p, why);
  // A near part followed by an octree frame.
  const Window two = window({{{2000, 0, 0}}, {{2000, 0, 0}}});
  std::vector<uint8_t> q = split_payload(two);
  const scan::Header hq = scan::read_header(q.data(), q.size(), "split", SIZE_MAX);
  q[hq.flags_end - 2] |= scan::kNearPart;
  expect_corrupt(q, why);
  // With bit 3 cleared the first window decodes again: the bit is all that was wrong.
  p[h.flags_end - 1] &= static_cast<uint8_t>(~scan::kNearPart);
  EXPECT_EQ(decode_scan_geometry(p.data(), p.size(), "split").q, w.whole.q);
}

// Damage anywhere in a split window's payload: corrupt (never another error, never a crash), or
// a window of the same frames' worth of points at most.
TEST(ScanSplitFrames, GivenDamagedSplitPayloadsThenCorruptOrBounded) {
  const Window w = window({{{3000, 500, 20}}, {{0, 400, 10}}, {{2500, 300, 0}}});
  const std::vector<uint8_t> p = split_payload(w);
  std::mt19937 rng(11);
  for (int k = 0; k < 300; ++k) {
    std::vector<uint8_t> d = p;
    if (k % 3 == 0)
      d.resize(rng() % d.size());
    else
      d[rng() % d.size()] ^= static_cast<uint8_t>(1u << (rng() % 8));
    try {
      const ScanGeometry g = decode_scan_geometry(d.data(), d.size(), "split", 20000);
      EXPECT_LE(g.total(), 20000u);
    } catch (const Error& e) {
      EXPECT_EQ(e.code(), ErrorCode::kCorrupt) << e.what();
    }
  }
}

// Window b coded by reorder_window on a 2 cm grid (1 cm bound) with and without split frames:
// the split chosen (its payload's frames `frames`, the first a near part), smaller than without,
// and each decoded point within the bound of its source point in the coded order.
void expect_split_chosen(FrameBlock b, size_t frames, const char* name) {
  Grid grid;
  grid.step = 0.02;
  grid.bound = 0.01;
  FrameBlock without = b;
  std::vector<uint8_t> coded, plain;
  reorder_window(&b, grid, {}, {}, &coded, nullptr, nullptr, true, nullptr, true);
  reorder_window(&without, grid, {}, {}, &plain, nullptr, nullptr, true, nullptr, false);
  const scan::Header h = scan::read_header(coded.data(), coded.size(), name, SIZE_MAX);
  ASSERT_EQ(h.counts.size(), frames);
  EXPECT_TRUE(scan::near_part(h.flags[0]));
  std::printf("%s at 1 cm: %zu B split, %zu B without\n", name, coded.size(), plain.size());
  EXPECT_LT(coded.size(), plain.size());
  const ScanGeometry d = decode_scan_geometry(coded.data(), coded.size(), name);
  ASSERT_EQ(d.valid, b.valid);
  for (size_t i = 0; i < d.valid.size(); ++i)
    for (size_t a = 0; a < 3 && d.valid[i]; ++a)
      ASSERT_LE(std::fabs(d.q[3 * i + a] * grid.step - b.xyz[3 * i + a]), grid.bound + 1e-9);
}

// A real sweep (hesai-qt64, 24k points, half of them within a metre) at 1 cm (grid 2 cm): the
// encoder's --point-order any splits it (docs/lab/2026-11-30-near-far-split.md), and the split
// window is smaller than the window it chooses without split frames; each decoded point within
// the bound of its source point in the coded order.
TEST(ScanSplitFrames, GivenHesaiQt64At1cmThenTheSplitIsChosenAndSmaller) {
  const std::string root = capz_test::shared_data_or_skip("scan/single");
  if (root.empty()) return;
  const Take t = read_take(root + "/hesai-qt64.pcd");
  FrameBlock b;
  b.reset_ragged(0, {t.total_points()});
  b.xyz = t.xyz;
  b.valid = t.valid;
  expect_split_chosen(b, 2, "hesai-qt64");
}

// A sequence (robosense-helios16p's first two sweeps, 57k points each) at 1 cm: split_estimate
// alone ranked its radii wrongly and put them all above the octree window's payload, and no
// split was coded; the radius chosen on the first sweep (docs/lab/2026-11-30-split-radius.md)
// splits the window, smaller than the window chosen without split frames.
TEST(ScanSplitFrames, GivenTwoHeliosSweepsAt1cmThenTheSplitIsChosenAndSmaller) {
  const std::string root = capz_test::shared_data_or_skip("scan/robosense-helios16p");
  if (root.empty()) return;
  const Take t = read_take(root);
  ASSERT_GE(t.frames, 2u);
  const size_t n = t.frame_points(0) + t.frame_points(1);
  FrameBlock b;
  b.reset_ragged(0, {t.frame_points(0), t.frame_points(1)});
  b.xyz.assign(t.xyz.begin(), t.xyz.begin() + static_cast<std::ptrdiff_t>(3 * n));
  b.valid.assign(t.valid.begin(), t.valid.begin() + static_cast<std::ptrdiff_t>(n));
  expect_split_chosen(b, 4, "robosense-helios16p, 2 sweeps");
}

}  // namespace
}  // namespace capz
