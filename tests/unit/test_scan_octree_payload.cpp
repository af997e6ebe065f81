// Octree frames in the scan geometry payload (docs/FORMAT.md "Octree frames"): a window of
// octree frames (with copies, gaps, a frame without a valid point) decodes to its points in
// octree order and says it holds octree frames; the header's checks of octree frames' flags,
// empty frames and the octree block's length.
#include <gtest/gtest.h>

#include <cmath>
#include <random>

#include "capz/error.h"
#include "coding/bytes.h"
#include "coding/scan_octree.h"
#include "coding/scan_shared.h"

namespace capz {
namespace {

// Three frames of a near scene on a 2 cm grid (a wall and a floor, many points a cell), the
// second with gaps, the third without a valid point; each in octree order.
ScanGeometry window() {
  std::mt19937 rng(4);
  std::uniform_real_distribution<double> u(0, 1);
  ScanGeometry g;
  for (int f = 0; f < 3; ++f) {
    const uint32_t n = f == 2 ? 5 : 4000;
    for (uint32_t i = 0; i < n; ++i) {
      const bool gap = f == 2 || (f == 1 && u(rng) < 0.05);
      g.valid.push_back(!gap);
      const double a = u(rng), b = u(rng);
      const double p[3] = {u(rng) < 0.5 ? 1.0 + 0.01 * f : 2 * a, 2 * b - 1,
                           u(rng) < 0.5 ? -0.5 : a};
      for (double v : p) g.q.push_back(gap ? 0 : static_cast<int32_t>(std::floor(v / 0.02 + 0.5)));
    }
    g.counts.push_back(n);
  }
  ScanGeometry s = g;
  size_t first = 0;
  for (uint32_t n : g.counts) {
    const std::vector<uint32_t> order = octree_frame_order(g, first, n);
    for (size_t j = 0; j < n; ++j) {
      s.valid[first + j] = g.valid[first + order[j]];
      for (int a = 0; a < 3; ++a) s.q[3 * (first + j) + a] = g.q[3 * (first + order[j]) + a];
    }
    first += n;
  }
  return s;
}

TEST(ScanOctreePayload, GivenAWindowOfOctreeFramesWhenDecodedThenItsPointsAndTheFlagComeBack) {
  const ScanGeometry g = window();
  const std::vector<uint8_t> p = encode_scan_octree(g);
  ASSERT_FALSE(p.empty());
  const ScanGeometry d = decode_scan_geometry(p.data(), p.size(), "octree");
  EXPECT_TRUE(d.octree);
  EXPECT_EQ(d.counts, g.counts);
  EXPECT_EQ(d.valid, g.valid);
  EXPECT_EQ(d.q, g.q);
  const scan::Header h = scan::read_header(p.data(), p.size(), "octree", SIZE_MAX);
  EXPECT_EQ(h.flags[0], scan::kOctreeFrame | scan::kCells);
  EXPECT_EQ(h.flags[1], scan::kOctreeFrame | scan::kCells | scan::kSomeValid);
  EXPECT_EQ(h.flags[2], scan::kNoneValid);
  // The scene's cells cost far less than a point each: 8000 points in well under 2 bytes each.
  EXPECT_LT(p.size(), 8000u * 2);
}

// The previous frame's cells (FORMAT.md step 4, pv): a still sensor's second sweep, the same
// cells as its first, costs a fraction of the first; decoded exactly.
TEST(ScanOctreePayload, GivenASweepAfterTheSameSweepThenItCostsAFractionOfTheFirst) {
  ScanGeometry one = window();
  one.counts.resize(1);
  one.valid.resize(one.counts[0]);
  one.q.resize(3 * one.valid.size());
  ScanGeometry two = one;
  two.counts.push_back(one.counts[0]);
  two.valid.insert(two.valid.end(), one.valid.begin(), one.valid.end());
  two.q.insert(two.q.end(), one.q.begin(), one.q.end());
  const std::vector<uint8_t> p1 = encode_scan_octree(one), p2 = encode_scan_octree(two);
  const ScanGeometry d = decode_scan_geometry(p2.data(), p2.size(), "octree");
  EXPECT_EQ(d.q, two.q);
  EXPECT_EQ(d.valid, two.valid);
  // Without pv the second frame's tree would cost about what the first's does.
  EXPECT_LT(p2.size() - p1.size(), p1.size() / 2) << p1.size() << " then " << p2.size();
}

// The previous frame's count of a cell (FORMAT.md step 5): a still sensor's cells keep their
// counts, so three repeats of a sweep of random counts cost about what the sweep does (1,111
// against 1,132 B); without that context 2,598 (each repeat's counts as dear as the first's).
TEST(ScanOctreePayload, GivenRepeatedSweepsThenTheirCountsCostLittle) {
  std::mt19937 rng(8);
  ScanGeometry one;
  uint32_t n = 0;
  for (int x = 0; x < 60; ++x)
    for (int y = 0; y < 40; ++y) {
      const int z = (x * x + 3 * y) % 7 == 0 ? 1 : 0;  // a floor with a few steps
      const uint32_t c = 1 + rng() % 6;
      for (uint32_t k = 0; k < c; ++k, ++n) {
        one.valid.push_back(1);
        one.q.insert(one.q.end(), {x, y, z});
      }
    }
  one.counts.push_back(n);
  ScanGeometry s = one;  // in octree order
  const std::vector<uint32_t> order = octree_frame_order(one, 0, n);
  for (size_t j = 0; j < n; ++j)
    for (size_t a = 0; a < 3; ++a) s.q[3 * j + a] = one.q[3 * order[j] + a];
  ScanGeometry four = s;
  for (int f = 1; f < 4; ++f) {
    four.counts.push_back(n);
    four.valid.insert(four.valid.end(), s.valid.begin(), s.valid.end());
    four.q.insert(four.q.end(), s.q.begin(), s.q.end());
  }
  const std::vector<uint8_t> p1 = encode_scan_octree(s), p4 = encode_scan_octree(four);
  EXPECT_EQ(decode_scan_geometry(p4.data(), p4.size(), "octree").q, four.q);
  EXPECT_LT(p4.size() - p1.size(), p1.size() * 3 / 2) << p1.size() << " then " << p4.size();
}

TEST(ScanOctreePayload, GivenAFrameTooWideOrTooHighForAnOctreeThenNoOctreePayload) {
  ScanGeometry g;
  g.counts.push_back(2);
  g.valid = {1, 1};
  g.q = {0, 0, 0, 1 << 22, 0, 0};
  EXPECT_TRUE(encode_scan_octree(g).empty());
  // A cube that would pass the int32 integers (FORMAT.md step 3): 3 apart below 2^31 - 1.
  g.q = {0, 0, INT32_MAX - 2, 0, 0, INT32_MAX};
  EXPECT_TRUE(encode_scan_octree(g).empty());
  g.q = {0, 0, INT32_MAX - 3, 0, 0, INT32_MAX};  // a cube of side 4 ending at 2^31 - 1: fine
  const std::vector<uint8_t> p = encode_scan_octree(g);
  ASSERT_FALSE(p.empty());
  EXPECT_EQ(decode_scan_geometry(p.data(), p.size(), "octree").q, g.q);
}

// Decoding p is corrupt for more cells than its octree block can hold.
void expect_too_many_cells(const std::vector<uint8_t>& p) {
  try {
    decode_scan_geometry(p.data(), p.size(), "octree");
    ADD_FAILURE() << "decoded";
  } catch (const Error& e) {
    EXPECT_EQ(e.code(), ErrorCode::kCorrupt);
    EXPECT_NE(std::string(e.what()).find("more cells than the octree block can hold"),
              std::string::npos)
        << e.what();
  }
}

// A frame of few cells and many gaps (a sweep that mostly missed): G is one value of the block,
// so the gaps do not count against its bytes (FORMAT.md, the bound on cells per byte).
TEST(ScanOctreePayload, GivenAFrameOfFewCellsAndManyGapsThenItDecodes) {
  ScanGeometry g;
  g.counts.push_back(100000);
  g.valid.assign(100000, 0);
  g.q.assign(3 * 100000, 0);
  g.valid[0] = g.valid[1] = 1;
  g.q[3] = 1;  // cells (0, 0, 0) and (1, 0, 0), in octree order: the gaps last
  const std::vector<uint8_t> p = encode_scan_octree(g);
  ASSERT_FALSE(p.empty());
  ASSERT_LT(p.size(), 100u);
  const ScanGeometry d = decode_scan_geometry(p.data(), p.size(), "octree");
  EXPECT_EQ(d.valid, g.valid);
  EXPECT_EQ(d.q, g.q);
  // The same frame said to have one gap: 99998 cells, more than its few bytes can hold.
  ByteWriter w;
  w.varint(1);
  w.varint(100000);
  w.u8(scan::kOctreeFrame | scan::kSomeValid);
  w.varint(0);
  IntEncoder tree(scan::kOctreeContexts);
  tree.put(1, scan::kOctCornerCtx);
  tree.put(17, scan::kOctDepthCtx);
  const std::vector<uint8_t> block = tree.finish();
  w.varint(block.size());
  w.bytes(block);
  IntEncoder m(scan::kContexts);
  w.bytes(m.finish());
  expect_too_many_cells(w.buffer());
}

// The payload of window() with frame 0's flags byte, or the octree block's length, changed.
std::vector<uint8_t> with_flags(uint8_t flags0) {
  std::vector<uint8_t> p = encode_scan_octree(window());
  const scan::Header h = scan::read_header(p.data(), p.size(), "octree", SIZE_MAX);
  p[h.flags_end - 3] = flags0;
  return p;
}

TEST(ScanOctreePayload, GivenBadOctreeFlagsOrBlockThenCorrupt) {
  const uint8_t cells = scan::kOctreeFrame | scan::kCells;
  for (uint8_t bad :
       {uint8_t(cells | scan::kRingWalk), uint8_t(cells | scan::kHypot),
        uint8_t(cells | scan::kRingPairs), uint8_t(cells | scan::kNoneValid), uint8_t(cells | 3)}) {
    const std::vector<uint8_t> p = with_flags(bad);
    EXPECT_THROW(decode_scan_geometry(p.data(), p.size(), "octree"), Error) << int(bad);
  }
  // Frame 0 said to have gaps: its G is read where D is, and the frame does not decode as coded.
  const std::vector<uint8_t> gaps = with_flags(cells | scan::kSomeValid);
  EXPECT_THROW(decode_scan_geometry(gaps.data(), gaps.size(), "octree"), Error);
  // An empty octree frame.
  ByteWriter w;
  w.varint(1);
  w.varint(0);
  w.u8(scan::kOctreeFrame);
  w.varint(0);
  std::vector<uint8_t> empty = w.buffer();
  IntEncoder m(scan::kContexts);
  const std::vector<uint8_t> block = m.finish();
  empty.insert(empty.end(), block.begin(), block.end());
  EXPECT_THROW(decode_scan_geometry(empty.data(), empty.size(), "octree"), Error);
  // The octree block's length beyond the bytes left, and cut short.
  std::vector<uint8_t> p = encode_scan_octree(window());
  const scan::Header h = scan::read_header(p.data(), p.size(), "octree", SIZE_MAX);
  ByteWriter o;
  o.varint(p.size());
  std::vector<uint8_t> longer(p.begin(), p.begin() + static_cast<long>(h.octree));
  size_t len_at = h.octree - 1;
  while (len_at > 0 && (p[len_at - 1] & 0x80)) --len_at;
  longer.resize(len_at);
  longer.insert(longer.end(), o.buffer().begin(), o.buffer().end());
  longer.insert(longer.end(), p.begin() + static_cast<long>(h.octree), p.end());
  EXPECT_THROW(decode_scan_geometry(longer.data(), longer.size(), "octree"), Error);
  // An empty octree block (O = 0) with octree frames: they, even with gaps, hold a cell each.
  std::vector<uint8_t> none(p.begin(), p.begin() + static_cast<long>(len_at));
  none.push_back(0);
  none.insert(none.end(), p.begin() + static_cast<long>(h.octree + h.octree_size), p.end());
  for (uint8_t f : {uint8_t(cells), uint8_t(cells | scan::kSomeValid)}) {
    none[h.flags_end - 3] = f;
    expect_too_many_cells(none);
  }
  p.resize(p.size() - 1);
  EXPECT_THROW(decode_scan_geometry(p.data(), p.size(), "octree"), Error);
}

}  // namespace
}  // namespace capz
