// The scan payload's cells with counts (docs/FORMAT.md "Scan geometry payload", "Cells with
// counts", flags_f bit 4): a window whose frames hold runs of the same grid integers codes each
// run once with a count; every decoding path gives the frames back whole; the encoder's grouping
// moves copies after their first point and keeps the rest in order; damaged copies, counts and
// counts blocks are corrupt; a near sweep's copies make the payload smaller.
#include <gtest/gtest.h>

#include <algorithm>
#include <cmath>
#include <random>

#include "capz/error.h"
#include "coding/bytes.h"
#include "coding/scan_cells.h"
#include "coding/scan_geometry.h"
#include "coding/scan_shared.h"
#include "scan_geometry_expect.h"

namespace capz {
namespace {

// A window of three sweeps of a 16-ring sensor, most returns within a metre (many in the same
// 2 cm cell: the integers on a 2 cm grid), 3 % gaps; frame 1 without a copy (its points a
// grid step apart), frame 2 one cell of many points with a gap between them.
ScanGeometry near_window(ScanHints* h) {
  std::mt19937 rng(11);
  std::uniform_real_distribution<double> u(0, 1);
  ScanGeometry g;
  for (int f = 0; f < 3; ++f) {
    uint32_t n = 0;
    for (int c = 0; c < (f == 2 ? 0 : 600); ++c) {
      for (uint32_t k = 0; k < 16; ++k, ++n) {
        if (u(rng) < 0.03) {  // a gap
          g.valid.push_back(0);
          g.q.insert(g.q.end(), {0, 0, 0});
          h->xyz.insert(h->xyz.end(), {NAN, NAN, NAN});
          h->ring.push_back(k);
          continue;
        }
        const double az = 0.0035 * c, el = -0.25 + 0.03 * k;
        const double range = f == 1 ? 3 + 0.02 * c : 0.6 + 0.3 * std::sin(3 * az) + 0.01 * u(rng);
        const double rho = range * std::cos(el);
        const double p[3] = {rho * std::cos(az), rho * std::sin(az), range * std::sin(el)};
        g.valid.push_back(1);
        for (int a = 0; a < 3; ++a) {
          g.q.push_back(static_cast<int32_t>(std::floor(p[a] / (f == 1 ? 0.0001 : 0.02) + 0.5)));
          h->xyz.push_back(static_cast<float>(p[a]));
        }
        h->ring.push_back(k);
      }
    }
    if (f == 2) {  // one cell, seven times, a gap after the third
      for (int j = 0; j < 8; ++j, ++n) {
        g.valid.push_back(j != 3);
        g.q.insert(g.q.end(), {j != 3 ? 40 : 0, j != 3 ? -7 : 0, j != 3 ? 3 : 0});
        h->xyz.insert(h->xyz.end(), {0.8f, -0.14f, 0.06f});
        h->ring.push_back(0);
      }
    }
    g.counts.push_back(n);
  }
  return g;
}

// The valid points of g equal to the valid point before them in their frame (the copies
// encode_scan_cells codes; the oracle of scan_grouped_copies).
size_t adjacent_copies(const ScanGeometry& g) {
  size_t copies = 0, first = 0;
  for (uint32_t n : g.counts) {
    for (size_t i = first + 1; i < first + n; ++i)
      copies += g.valid[i] && g.valid[i - 1] &&
                std::equal(&g.q[3 * i], &g.q[3 * i] + 3, &g.q[3 * (i - 1)]);
    first += n;
  }
  return copies;
}

// g with each frame's valid points grouped (a copy just after its first), as the encoder codes
// a reordered window.
ScanGeometry grouped(const ScanGeometry& g, ScanHints* h) {
  std::vector<uint32_t> order(g.total());
  for (size_t i = 0; i < order.size(); ++i) order[i] = static_cast<uint32_t>(i);
  order = group_cell_copies(g, order);
  ScanGeometry s = g;
  ScanHints t = *h;
  for (size_t j = 0; j < order.size(); ++j) {
    s.valid[j] = g.valid[order[j]];
    std::copy_n(&g.q[3 * size_t{order[j]}], 3, &s.q[3 * j]);
    t.ring[j] = h->ring[order[j]];
    std::copy_n(&h->xyz[3 * size_t{order[j]}], 3, &t.xyz[3 * j]);
  }
  *h = t;
  return s;
}

TEST(ScanCells, GivenRunsOfTheSamePointThenEveryDecodingPathGivesTheFramesBack) {
  ScanHints h;
  const ScanGeometry g = grouped(near_window(&h), &h);
  const size_t copies = adjacent_copies(g);
  ASSERT_GT(copies, g.total() / 4);
  const std::vector<uint8_t> p = encode_scan_cells(g, h, nullptr);
  ASSERT_FALSE(p.empty());
  const scan::Header hd = scan::read_header(p.data(), p.size(), "cells", 1u << 20);
  EXPECT_TRUE(hd.flags[0] & scan::kCells);
  EXPECT_FALSE(hd.flags[1] & scan::kCells);  // no copy in frame 1
  EXPECT_TRUE(hd.flags[2] & scan::kCells);
  EXPECT_EQ(hd.copies[2], 6u);  // seven of one cell (and a gap): six copies
  EXPECT_EQ(hd.copies[0] + hd.copies[1] + hd.copies[2], copies);
  expect_same(decode_scan_geometry(p.data(), p.size(), "cells"), g);
  std::vector<int32_t> space;
  expect_same(decode_scan_geometry(p.data(), p.size(), "cells", 1u << 20, &space), g);
  ScanGeometry frames;  // a frame at a time
  const ScanGeometry v =
      decode_scan_geometry(p.data(), p.size(), "cells", 1u << 20,
                           [&](size_t first, size_t n, const int32_t* q, const uint8_t* valid) {
                             EXPECT_EQ(first, frames.total());
                             frames.counts.push_back(static_cast<uint32_t>(n));
                             frames.q.insert(frames.q.end(), q, q + 3 * n);
                             frames.valid.insert(frames.valid.end(), valid, valid + n);
                           });
  EXPECT_EQ(v.valid, g.valid);
  expect_same(frames, g);
  // The copies coded once: smaller than the same window without cells.
  EXPECT_LT(p.size(), encode_scan_geometry(g, h).size());
}

TEST(ScanCells, GivenAnOrderThenCopiesFollowTheirFirstAndTheRestKeepsItsOrder) {
  ScanGeometry g;
  g.counts = {6, 3};
  // frame 0: A B A gap B A; frame 1: C gap(with C's integers) C
  g.q = {1, 2, 3, 4, 5, 6, 1, 2, 3, 1, 2, 3, 4, 5, 6, 1, 2, 3, 7, 7, 7, 7, 7, 7, 7, 7, 7};
  g.valid = {1, 1, 1, 0, 1, 1, 1, 0, 1};
  const std::vector<uint32_t> order = {5, 4, 3, 2, 1, 0, 6, 7, 8};  // frame 0 reversed
  EXPECT_EQ(group_cell_copies(g, order), (std::vector<uint32_t>{5, 2, 0, 4, 1, 3, 6, 8, 7}));
  ScanGeometry s = g;
  const std::vector<uint32_t> o = group_cell_copies(g, order);
  for (size_t j = 0; j < o.size(); ++j) {
    s.valid[j] = g.valid[o[j]];
    std::copy_n(&g.q[3 * size_t{o[j]}], 3, &s.q[3 * j]);
  }
  EXPECT_EQ(adjacent_copies(s), 4u);      // two A, one B, one C
  EXPECT_EQ(adjacent_copies(g), 0u);      // none adjacent as given
  EXPECT_EQ(scan_grouped_copies(g), 4u);  // the grouped order's, from any order
  EXPECT_TRUE(encode_scan_cells(g, {}, nullptr).empty());
  const std::vector<uint8_t> p = encode_scan_cells(s, {}, nullptr);
  expect_same(decode_scan_geometry(p.data(), p.size(), "cells"), s);
}

TEST(ScanCells, GivenAnyWindowThenTheGroupedCopiesAreCountedWithoutGrouping) {
  ScanHints h;
  ScanGeometry g = near_window(&h);
  std::vector<uint32_t> order(g.total());
  for (size_t j = 0; j < order.size(); ++j) order[j] = static_cast<uint32_t>(j);
  for (int pass = 0; pass < 2; ++pass) {  // the file's order, then each frame's reversed
    ScanGeometry s = g;
    const std::vector<uint32_t> o = group_cell_copies(g, order);
    for (size_t j = 0; j < o.size(); ++j) {
      s.valid[j] = g.valid[o[j]];
      std::copy_n(&g.q[3 * size_t{o[j]}], 3, &s.q[3 * j]);
    }
    EXPECT_GT(adjacent_copies(s), 0u);
    EXPECT_EQ(scan_grouped_copies(g), adjacent_copies(s));
    size_t first = 0;
    for (uint32_t n : g.counts) {
      std::reverse(order.begin() + static_cast<std::ptrdiff_t>(first),
                   order.begin() + static_cast<std::ptrdiff_t>(first + n));
      first += n;
    }
  }
}

TEST(ScanCells, GivenTheByRingOrderThenEachFramesPointsRingByRingGapsLast) {
  ScanHints h;
  const ScanGeometry g = near_window(&h);
  const std::vector<uint32_t> o = scan_point_order(g, h, ScanOrderTable::kPerFrameByRing);
  ASSERT_EQ(o.size(), g.total());
  // The per-frame order's fits give the same order ring by ring.
  std::vector<uint32_t> by_ring;
  EXPECT_EQ(scan_point_order(g, h, ScanOrderTable::kPerFrame, &by_ring),
            scan_point_order(g, h, ScanOrderTable::kPerFrame));
  EXPECT_EQ(by_ring, o);
  size_t first = 0;
  for (uint32_t n : {g.counts[0], g.counts[1]}) {  // frame 2 is one cell on one ring
    std::vector<uint32_t> seen(o.begin() + static_cast<std::ptrdiff_t>(first),
                               o.begin() + static_cast<std::ptrdiff_t>(first + n));
    size_t valid = 0;
    for (size_t j = 0; j < n; ++j) {
      ASSERT_GE(seen[j], first);
      ASSERT_LT(seen[j], first + n);
      if (!g.valid[seen[j]]) continue;
      EXPECT_EQ(j, valid++) << "a gap before a valid point";
      if (j > 0) {
        EXPECT_LE(h.ring[seen[j - 1]], h.ring[seen[j]]) << "frame at " << first;
      }
    }
    std::sort(seen.begin(), seen.end());
    EXPECT_EQ(std::unique(seen.begin(), seen.end()), seen.end());
    first += n;
  }
}

// p with its frame 0's d_f (the varint after the flags) set to d.
std::vector<uint8_t> with_copies(const std::vector<uint8_t>& p, uint64_t d) {
  ByteReader r(p.data(), p.size(), "t");
  const size_t frames = static_cast<size_t>(r.varint());
  for (size_t f = 0; f < frames; ++f) r.varint();
  r.bytes(frames);
  const size_t at = r.offset();
  r.varint();
  ByteWriter w;
  w.bytes(p.data(), at);
  w.varint(d);
  w.bytes(p.data() + r.offset(), p.size() - r.offset());
  return w.buffer();
}

TEST(ScanCells, GivenDamagedCopiesOrCountsThenCorrupt) {
  ScanHints h;
  ScanGeometry g = grouped(near_window(&h), &h);
  g.counts.resize(1);  // frame 0 alone
  g.valid.resize(g.counts[0]);
  g.q.resize(3 * g.counts[0]);
  const std::vector<uint8_t> p = encode_scan_cells(g, {}, nullptr);
  ASSERT_FALSE(p.empty());
  const uint32_t d = scan::read_header(p.data(), p.size(), "t", 1u << 20).copies[0];
  ASSERT_GT(d, 1u);
  expect_scan_corrupt(with_copies(p, 0));            // d_f of 0
  expect_scan_corrupt(with_copies(p, g.counts[0]));  // d_f of n_f
  expect_scan_corrupt(with_copies(p, d - 1));        // counts above the copies left
  std::vector<uint8_t> q = p;                        // bit 4 cleared: d_f read as the table
  q[2 + (g.counts[0] >= 128) + (g.counts[0] >= 16384)] &= static_cast<uint8_t>(~scan::kCells);
  EXPECT_THROW(decode_scan_geometry(q.data(), q.size(), "damaged"), Error);
  // The counts block cut short, or its length beyond the payload.
  const scan::Header hd = scan::read_header(p.data(), p.size(), "t", 1u << 20);
  ASSERT_GT(hd.cells_size, 2u);
  std::vector<uint8_t> cut(p.begin(), p.begin() + static_cast<std::ptrdiff_t>(hd.cells + 1));
  expect_scan_corrupt(cut);
  for (size_t i = hd.cells; i < hd.body; ++i) {  // every byte of the counts block changed
    std::vector<uint8_t> bad = p;
    bad[i] ^= 0x5a;
    try {
      const ScanGeometry back = decode_scan_geometry(bad.data(), bad.size(), "damaged");
      EXPECT_EQ(back.total(), g.total());  // a change the block can carry keeps the shape
    } catch (const Error& e) {
      EXPECT_EQ(e.code(), ErrorCode::kCorrupt);
    }
  }
}

}  // namespace
}  // namespace capz
