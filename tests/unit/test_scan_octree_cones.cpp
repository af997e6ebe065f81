// Octree frames' cone class and counting models (docs/FORMAT.md "Octree frames", "The block's
// flags"): the box test against hand-worked boxes, a child's rings among its parent's, the
// contexts' numbers, the walk's classes against the box test of every ring, the counting
// model's steps, round trips of a window and of a real sweep with each L, and the corrupt flags.
#include <gtest/gtest.h>

#include <cmath>
#include <random>

#include "capz/error.h"
#include "capz/io.h"
#include "coding/bytes.h"
#include "coding/scan_octree.h"
#include "coding/scan_shared.h"
#include "scan_geometry_expect.h"
#include "support/octree_reference.h"
#include "test_util.h"

namespace capz {
namespace {

using scan::Cones;

std::vector<uint16_t> crossing(const Cones& c, int64_t x, int64_t y, int64_t z, int64_t side) {
  std::vector<uint16_t> all(c.rings()), out;
  for (size_t k = 0; k < all.size(); ++k) all[k] = static_cast<uint16_t>(k);
  const int64_t a[3] = {x, y, z};
  scan::octree::crossing(c, a, side, all.data(), all.size(), &out);
  return out;
}

TEST(ScanOctreeCones, GivenHandWorkedBoxesThenTheRingsThatCrossThemAreThoseOfTheSpec) {
  // A flat ring on z = -0.5: it touches the top face of the cells at z = -1 and the bottom
  // face of those at z = 0 (the box is closed), not the cells at z = 1 or -2.
  Cones flat;
  flat.slope = {0.0};
  flat.z0 = {-0.5};
  EXPECT_EQ(crossing(flat, 10, 0, 0, 1).size(), 1u);
  EXPECT_EQ(crossing(flat, 10, 0, -1, 1).size(), 1u);
  EXPECT_EQ(crossing(flat, 10, 0, 1, 1).size(), 0u);
  EXPECT_EQ(crossing(flat, 10, 0, -2, 1).size(), 0u);
  // z = 0.1 rho over the cell at (95, 0): rho from 94.5 to sqrt(95.5^2 + 0.5^2), z from 9.45 to
  // 9.5501: the cells at z = 9 ([8.5, 9.5]) and 10 ([9.5, 10.5]) cross, the one at 8 does not.
  Cones up;
  up.slope = {0.1};
  up.z0 = {0.0};
  EXPECT_EQ(crossing(up, 95, 0, 9, 1).size(), 1u);
  EXPECT_EQ(crossing(up, 95, 0, 10, 1).size(), 1u);
  EXPECT_EQ(crossing(up, 95, 0, 8, 1).size(), 0u);
  EXPECT_EQ(crossing(up, 95, 0, 11, 1).size(), 0u);
  // A box over the sensor's axis (x and y from -2.5 to 1.5): its nearest rho is 0, so a steep
  // cone from z0 = 0.2 crosses it at its apex (with the nearest |x|, |y| of 0.5, not 0, it
  // would be at z = 0.2 - 5 * 0.71 there, below the box).
  Cones steep;
  steep.slope = {-5.0};
  steep.z0 = {0.2};
  EXPECT_EQ(crossing(steep, -2, -2, 0, 4).size(), 1u);
  EXPECT_EQ(crossing(steep, 1, 1, 0, 4).size(), 0u);  // x, y from 0.5: z at most -3.34
  // Several rings: their indices in order.
  Cones three;
  three.slope = {0.1, 0.0, 0.1};
  three.z0 = {0.0, -0.5, -0.3};
  EXPECT_EQ(crossing(three, 95, 0, 9, 1), (std::vector<uint16_t>{0, 2}));
  EXPECT_EQ(crossing(three, 95, 0, 0, 1), (std::vector<uint16_t>{1}));
}

TEST(ScanOctreeCones, GivenRandomBoxesThenAChildsRingsAreAmongItsParents) {
  std::mt19937 rng(7);
  std::uniform_real_distribution<double> u(-1, 1);
  Cones c;
  for (int k = 0; k < 64; ++k) {
    c.slope.push_back(static_cast<float>(0.4 * u(rng)));
    c.z0.push_back(static_cast<float>(20 * u(rng)));
  }
  size_t crossed = 0;
  for (int t = 0; t < 3000; ++t) {
    const int64_t side = int64_t{1} << (t % 6 + 1);
    const int64_t p[3] = {static_cast<int64_t>(400 * u(rng)), static_cast<int64_t>(400 * u(rng)),
                          static_cast<int64_t>(60 * u(rng))};
    const std::vector<uint16_t> parent = crossing(c, p[0], p[1], p[2], side);
    for (int i = 0; i < 8; ++i) {
      const int64_t a[3] = {p[0] + (i >> 2) * side / 2, p[1] + ((i >> 1) & 1) * side / 2,
                            p[2] + (i & 1) * side / 2};
      const std::vector<uint16_t> all = crossing(c, a[0], a[1], a[2], side / 2);
      std::vector<uint16_t> from;
      scan::octree::crossing(c, a, side / 2, parent.data(), parent.size(), &from);
      EXPECT_EQ(from, all);
      crossed += all.size();
    }
  }
  EXPECT_GT(crossed, 1000u);
}

TEST(ScanOctreeCones, GivenAConeClassThenTheChildBitsContextIsTheSpecsNumber) {
  int none[27] = {0}, full[27];
  std::fill(full, full + 27, 1);
  scan::octree::KeySet empty, next, before;
  empty.reset(0);
  const int64_t p[3] = {3, 3, 3};
  // Level l = 4 of a tree of depth 5: lc = 0; level 3: lc = 1.
  EXPECT_EQ(capz_test::bit_context(none, empty, empty, p, 4, 5, 0, 0, 1), 19011 + 2 * 1);
  EXPECT_EQ(capz_test::bit_context(none, empty, empty, p, 3, 5, 0, 0, 0), 19011 + 2 * 2);
  EXPECT_EQ(capz_test::bit_context(none, empty, empty, p, 3, 5, 0, 1, 1),
            19011 + 2 * ((1 * 2 + 1) * 2 + 1));
  EXPECT_EQ(capz_test::bit_context(none, empty, empty, p, 4, 5, 0, 0, 2), 578);
  EXPECT_EQ(capz_test::bit_context(none, empty, empty, p, 4, 5, 0, 0), 578);
  // The last context: every neighbour, the three child-level ones, two siblings, lc 1, r 1, pv.
  next.reset(3);
  before.reset(1);
  const int i = 0;  // child (6, 6, 6) at level 4: neighbours (5, 6, 6), (6, 5, 6), (6, 6, 5)
  next.insert(scan::octree::key(5, 6, 6), 0);
  next.insert(scan::octree::key(6, 5, 6), 1);
  next.insert(scan::octree::key(6, 6, 5), 2);
  before.insert(scan::octree::key(6, 6, 6), 0);
  EXPECT_EQ(capz_test::bit_context(full, next, before, p, 3, 5, i, 2, 1),
            scan::kOctreeContexts - 1);
  EXPECT_EQ(scan::kOctreeContexts, 43587);
}

// The contexts a walk asks for, and the bits of a tree given by its cells.
struct Recorder {
  std::vector<std::vector<uint64_t>> levels;
  std::vector<int> ctx, level;
  std::vector<uint64_t> child;
  bool bit(int c, int l, uint64_t k) {
    ctx.push_back(c), level.push_back(l), child.push_back(k);
    const std::vector<uint64_t>& n = levels[static_cast<size_t>(l) + 1];
    return std::binary_search(n.begin(), n.end(), k);
  }
  [[noreturn]] void too_many() { throw Error(ErrorCode::kInternal, "too many"); }
  [[noreturn]] void too_much() { throw Error(ErrorCode::kInternal, "too much"); }
};

TEST(ScanOctreeCones, GivenATreeThenTheWalksClassesAreTheBoxTestOfEveryRing) {
  // Cells on two cones and scattered between them, in a depth-7 cube from lo.
  std::mt19937 rng(3);
  std::uniform_real_distribution<double> u(0, 1);
  Cones c;
  c.slope = {0.05f, 0.2f, -0.1f};
  c.z0 = {1.0f, -2.0f, 0.5f};
  const int64_t lo[3] = {-40, -60, -20};
  const int d = 7;
  std::vector<uint64_t> cells;
  for (int j = 0; j < 3000; ++j) {
    const double x = lo[0] + 127 * u(rng), y = lo[1] + 127 * u(rng);
    const double rho = std::hypot(x, y);
    const size_t k = static_cast<size_t>(j % 4);
    const double z = k < 3 ? c.z0[k] + c.slope[k] * rho : lo[2] + 127 * u(rng);
    const int64_t v[3] = {std::llround(x) - lo[0], std::llround(y) - lo[1],
                          std::llround(z) - lo[2]};
    if (v[2] < 0 || v[2] > 127) continue;
    cells.push_back(scan::octree::key(static_cast<uint64_t>(v[0]), static_cast<uint64_t>(v[1]),
                                      static_cast<uint64_t>(v[2])));
  }
  std::sort(cells.begin(), cells.end());
  cells.erase(std::unique(cells.begin(), cells.end()), cells.end());
  Recorder io;
  io.levels.resize(d + 1);
  io.levels[d] = cells;
  for (int l = d - 1; l >= 0; --l)
    for (uint64_t k : io.levels[static_cast<size_t>(l) + 1])
      if (io.levels[static_cast<size_t>(l)].empty() ||
          io.levels[static_cast<size_t>(l)].back() != k >> 3)
        io.levels[static_cast<size_t>(l)].push_back(k >> 3);
  Recorder plain = io;
  EXPECT_EQ(scan::octree::code_tree(io, d, cells.size(), lo, {}, &c), cells);
  scan::octree::code_tree(plain, d, cells.size(), lo, {});
  ASSERT_EQ(io.ctx.size(), plain.ctx.size());
  size_t classed[3] = {0, 0, 0};
  for (size_t j = 0; j < io.ctx.size(); ++j) {
    const int l = io.level[j];
    int r = 2;
    if (l >= d - 2) {
      int64_t v[3];
      scan::octree::coords(io.child[j], v);
      const int64_t side = int64_t{1} << (d - l - 1);
      r = static_cast<int>(std::min<size_t>(
          crossing(c, lo[0] + side * v[0], lo[1] + side * v[1], lo[2] + side * v[2], side).size(),
          2));
    }
    ++classed[r];
    // The plain walk's context with this class: the same neighbours, siblings and level.
    const int base = plain.ctx[j] - scan::kOctBitCtx;  // 2 (((o7 8 + cn) 3 + sib) 3 + lc) + pv
    const int lc = (base / 2) % 3, rest = base / 6, pv = base % 2;
    const int want = r == 2 ? plain.ctx[j] : scan::kOctConeCtx + 2 * ((rest * 2 + lc) * 2 + r) + pv;
    ASSERT_EQ(io.ctx[j], want) << j;
  }
  EXPECT_GT(classed[0], 100u);
  EXPECT_GT(classed[1], 100u);
  EXPECT_GT(classed[2], 100u);
}

TEST(ScanOctreeCones, GivenBitsThenTheCountingModelMovesAsTheSpecSays) {
  Cones none;
  scan::OctreeMode m(none, true);
  const int c = scan::kOctBitCtx + 10;
  EXPECT_EQ(m.one(c), 16384u);
  m.update(c, true);  // + (32768 - 16384) / 2
  EXPECT_EQ(m.one(c), 24576u);
  m.update(c, true);  // + 8192 / 3 = 2730
  EXPECT_EQ(m.one(c), 27306u);
  m.update(c, false);  // + trunc(-27306 / 4) = -6826
  EXPECT_EQ(m.one(c), 20480u);
  // At N = 62 a step of less than 1 truncates to 0: P stays at 63 from either end.
  for (int k = 0; k < 2000; ++k) m.update(c, false);
  EXPECT_EQ(m.one(c), 63u);
  for (int k = 0; k < 4000; ++k) m.update(c, true);
  EXPECT_EQ(m.one(c), 32768u - 63u);
  EXPECT_EQ(m.one(scan::kOctConeCtx), 16384u);  // contexts of their own
  EXPECT_EQ(m.flags(), 2u);
}

// The cone index is built once a window, and only by a frame whose walk classes children (which
// its cone work pays for): a crafted window of depth-0 frames (one cell, no cone work) built it
// for each frame, 2.8 us a frame with 256 rings, 20x the decoding of such a window without
// cones (docs/lab/2026-11-30-octree-review.md).
TEST(ScanOctreeCones, GivenFramesThenTheConeIndexIsBuiltOnceAWindowByAFrameWithConeWork) {
  Cones c;
  for (int k = 0; k < 256; ++k) c.slope.push_back(k % 7 / 64.0), c.z0.push_back(k % 3);
  const int64_t lo[3] = {-4, -4, -4};
  Recorder one;  // depth 0: the root is the cell, nothing classed
  one.levels.assign(1, {0});
  for (int f = 0; f < 3; ++f) EXPECT_EQ(scan::octree::code_tree(one, 0, 1, lo, {}, &c).size(), 1u);
  EXPECT_EQ(c.index, nullptr);
  EXPECT_EQ(c.work, 0u);
  Recorder io;  // depth 3: cells (0 0 0) and (7 7 7)
  io.levels = {{0}, {0, 7}, {0, 63}, {0, 511}};
  EXPECT_EQ(scan::octree::code_tree(io, 3, 2, lo, {}, &c), io.levels[3]);
  ASSERT_NE(c.index, nullptr);
  const scan::octree::ConeIndex* built = c.index.get();
  EXPECT_EQ(c.work, 256u * (2 + 2));  // two parents at each of levels 1 and 2
  EXPECT_EQ(scan::octree::code_tree(io, 3, 2, lo, {}, &c), io.levels[3]);
  EXPECT_EQ(c.index.get(), built);
}

// A table of the cones z = z0 + slope rho (grid units), step 1 and one column, as the encoder's.
scan::Table table_of(const std::vector<float>& slope, const std::vector<float>& z0) {
  scan::Table t;
  t.step = 1;
  t.columns = 1;
  t.azimuth0.assign(slope.size(), 0.0f);
  t.slope = slope;
  t.z0 = z0;
  return t;
}

// Two near sweeps of 32 rings on a 2 cm grid (returns from a wavy wall 0.5-1.1 m away), the
// second with gaps, each in octree order; *t: their rings' cones.
ScanGeometry near_window(scan::Table* t) {
  std::mt19937 rng(5);
  std::uniform_real_distribution<double> u(0, 1);
  ScanGeometry g;
  std::vector<float> slope;
  for (int k = 0; k < 32; ++k) slope.push_back(static_cast<float>(std::tan(-0.4 + 0.025 * k)));
  *t = table_of(slope, std::vector<float>(32, 0.0f));
  for (int f = 0; f < 2; ++f) {
    ScanGeometry one;
    for (int c = 0; c < 1000; ++c)
      for (int k = 0; k < 32; ++k) {
        const bool gap = f == 1 && u(rng) < 0.03;
        const double az = 0.00628 * c, el = -0.4 + 0.025 * k;
        const double range = 0.8 + 0.3 * std::sin(3 * az + f * 0.01) + 0.004 * u(rng);
        const double rho = range * std::cos(el);
        const double p[3] = {rho * std::cos(az), rho * std::sin(az), range * std::sin(el)};
        one.valid.push_back(!gap);
        for (double v : p)
          one.q.push_back(gap ? 0 : static_cast<int32_t>(std::floor(v / 0.02 + 0.5)));
      }
    const std::vector<uint32_t> order = octree_frame_order(one, 0, one.valid.size());
    for (uint32_t j : order) {
      g.valid.push_back(one.valid[j]);
      g.q.insert(g.q.end(), &one.q[3 * j], &one.q[3 * j] + 3);
    }
    g.counts.push_back(static_cast<uint32_t>(order.size()));
  }
  return g;
}

// The octree block's flags L of payload p (0 without a table: not coded).
uint32_t flags_of(const std::vector<uint8_t>& p) {
  const scan::Header h = scan::read_header(p.data(), p.size(), "octree", SIZE_MAX);
  if (h.table.rings() == 0) return 0;
  IntDecoder dec(p.data() + h.octree, h.octree_size, scan::kOctreeContexts, "octree");
  return dec.get(scan::kOctFlagsCtx);
}

TEST(ScanOctreeCones, GivenAWindowWithEachFlagThenItsPointsComeBack) {
  scan::Table t;
  const ScanGeometry g = near_window(&t);
  size_t bytes[8] = {};
  const std::vector<uint8_t> none = encode_scan_octree(g);
  for (uint32_t l : {0u, 1u, 2u, 3u, 6u, 7u}) {  // 6 and 7: with the mix (bit 2)
    const std::vector<uint8_t> p = encode_scan_octree(g, &t, l);
    ASSERT_FALSE(p.empty());
    EXPECT_EQ(flags_of(p), l);
    const ScanGeometry d = decode_scan_geometry(p.data(), p.size(), "octree");
    EXPECT_EQ(d.valid, g.valid) << l;
    EXPECT_EQ(d.q, g.q) << l;
    bytes[l] = scan::read_header(p.data(), p.size(), "octree", SIZE_MAX).octree_size;
    EXPECT_EQ(scan::read_header(p.data(), p.size(), "octree", SIZE_MAX).table.rings(), 32u);
  }
  // Without a table L is not coded: the block is L = 0's less that symbol.
  const scan::Header h = scan::read_header(none.data(), none.size(), "octree", SIZE_MAX);
  EXPECT_EQ(h.table.rings(), 0u);
  EXPECT_LE(h.octree_size, bytes[0]);
  EXPECT_EQ(decode_scan_geometry(none.data(), none.size(), "octree").q, g.q);
  std::printf("octree blocks, L = 0..3, 6, 7: %zu %zu %zu %zu %zu %zu B\n", bytes[0], bytes[1],
              bytes[2], bytes[3], bytes[6], bytes[7]);
  // The counting models learn a skewed context within a few bits (10,243 -> 9,454 B). The cones
  // add nothing here: on a wall at 0.8 m every cell has a ring or two (the real sweep below).
  EXPECT_LT(static_cast<double>(bytes[2]), 0.95 * static_cast<double>(bytes[0]));
  // More rings than a cone class may take: the encoder leaves them out (L bit 0 clear).
  const scan::Table big = table_of(std::vector<float>(257, 0.1f), std::vector<float>(257, 0.0f));
  EXPECT_EQ(flags_of(encode_scan_octree(g, &big, 3)), 2u);
}

// A payload of one octree frame of one cell (depth 0) whose block starts with L (with a table t
// of some rings; else it has none).
std::vector<uint8_t> one_cell(uint32_t l, const scan::Table& t) {
  ByteWriter w;
  w.varint(1);
  w.varint(1);
  w.u8(scan::kOctreeFrame);
  scan::write_table(t, &w);
  IntEncoder tree(scan::kOctreeContexts);
  scan::start_octree_block(&tree);
  if (t.rings() > 0) tree.put(l, scan::kOctFlagsCtx);
  tree.put(0, scan::kOctDepthCtx);
  for (int a = 0; a < 3; ++a) tree.put_signed(7, scan::kOctCornerCtx);
  const std::vector<uint8_t> block = tree.finish();
  w.varint(block.size());
  w.bytes(block);
  IntEncoder m(scan::kContexts);
  w.bytes(m.finish());
  return w.buffer();
}

void expect_corrupt(const std::vector<uint8_t>& p, const char* says) {
  try {
    decode_scan_geometry(p.data(), p.size(), "octree");
    ADD_FAILURE() << "decoded: " << says;
  } catch (const Error& e) {
    EXPECT_EQ(e.code(), ErrorCode::kCorrupt);
    EXPECT_NE(std::string(e.what()).find(says), std::string::npos) << e.what();
  }
}

TEST(ScanOctreeCones, GivenBadBlockFlagsThenCorruptSayingWhich) {
  const scan::Table none, two = table_of({0.1f, 0.2f}, {0.0f, 1.0f});
  const scan::Table many = table_of(std::vector<float>(257, 0.1f), std::vector<float>(257, 0.0f));
  for (uint32_t l : {0u, 1u, 2u, 3u, 6u, 7u}) {  // the valid ones decode: the cell at (7, 7, 7)
    const std::vector<uint8_t> p = one_cell(l, two);
    EXPECT_EQ(decode_scan_geometry(p.data(), p.size(), "octree").q,
              (std::vector<int32_t>{7, 7, 7}));
  }
  expect_corrupt(one_cell(8, two), "an octree block's flags have unknown bits");
  expect_corrupt(one_cell(4, two), "an octree block's mix without counting models");
  expect_corrupt(one_cell(5, two), "an octree block's mix without counting models");
  expect_corrupt(one_cell(7, many), "an octree block's cones from more than 256 rings");
  expect_corrupt(one_cell(1, many), "an octree block's cones from more than 256 rings");
  expect_corrupt(one_cell(3, many), "an octree block's cones from more than 256 rings");
  const std::vector<uint8_t> bare = one_cell(0, none);  // no table, no L
  EXPECT_EQ(decode_scan_geometry(bare.data(), bare.size(), "octree").q,
            (std::vector<int32_t>{7, 7, 7}));
  const std::vector<uint8_t> ok = one_cell(2, many);  // no cones: the table's size is no matter
  EXPECT_EQ(decode_scan_geometry(ok.data(), ok.size(), "octree").q,
            (std::vector<int32_t>{7, 7, 7}));
}

// A lattice of 32^3 cells 4 apart: each cell has a parent of its own at each of the last two
// levels, and its bits cost little, so 256 cones take more work than its bytes allow: the
// decoder refuses such a block, and the encoder codes the window without the cones.
TEST(ScanOctreeCones, GivenMoreConeWorkThanTheBlockAllowsThenCorruptAndTheEncoderGoesWithout) {
  ScanGeometry g;
  for (int x = 0; x < 32; ++x)
    for (int y = 0; y < 32; ++y)
      for (int z = 0; z < 32; ++z) g.q.insert(g.q.end(), {4 * x, 4 * y, 4 * z});
  g.valid.assign(g.q.size() / 3, 1);
  g.counts.push_back(static_cast<uint32_t>(g.valid.size()));
  const std::vector<uint32_t> order = octree_frame_order(g, 0, g.valid.size());
  ScanGeometry s = g;
  for (size_t j = 0; j < order.size(); ++j) std::copy_n(&g.q[3 * size_t{order[j]}], 3, &s.q[3 * j]);
  std::vector<float> slope;
  for (int k = 0; k < 256; ++k) slope.push_back(static_cast<float>(k) / 64);
  const scan::Table t = table_of(slope, std::vector<float>(256, 0.0f));
  // By hand, past the budget: 2 x 32768 parents x 256 rings.
  ByteWriter w;
  w.varint(1);
  w.varint(s.counts[0]);
  w.u8(scan::kOctreeFrame);
  scan::write_table(t, &w);
  IntEncoder tree(scan::kOctreeContexts);
  scan::start_octree_block(&tree);
  tree.put(3, scan::kOctFlagsCtx);
  scan::OctreeMode mode(scan::table_cones(t), true);
  std::vector<int32_t> prev;
  encode_octree_frame(s, 0, s.counts[0], 0, &prev, &tree, &mode);
  const std::vector<uint8_t> block = tree.finish();
  EXPECT_EQ(mode.cones()->work, 2u * 32768u * 256u);
  ASSERT_GT(mode.cones()->work, scan::kMaxConeWorkPerByte * block.size());
  w.varint(block.size());
  w.bytes(block);
  IntEncoder m(scan::kContexts);
  w.bytes(m.finish());
  expect_corrupt(w.buffer(),
                 "the octree's cone classes take more work than its block's bytes allow");
  const std::vector<uint8_t> p = encode_scan_octree(s, &t, 3);
  EXPECT_EQ(flags_of(p), 2u);
  EXPECT_EQ(decode_scan_geometry(p.data(), p.size(), "octree").q, s.q);
}

// A real sweep (hesai-xt32, 63k points) on capz's grid at 1 cm: the cones of the table the
// encoder fits and the counting models take its octree payload down by more than 5 %
// (docs/lab/2026-11-30-octree-cones.md), the mix by 5 % more, and it comes back exactly.
TEST(ScanOctreeCones, GivenARealSweepThenTheConesAndCountingModelsPay) {
  const std::string root = capz_test::shared_data_or_skip("scan/single");
  if (root.empty()) return;
  ScanHints hints;
  const ScanGeometry g = sweep_geometry(read_take(root + "/hesai-xt32.pcd"), 50, &hints);
  const scan::Table table = octree_cone_table(g, hints);
  EXPECT_EQ(table.rings(), 32u);
  ScanGeometry s = g;
  const std::vector<uint32_t> order = octree_frame_order(g, 0, g.valid.size());
  for (size_t j = 0; j < order.size(); ++j) {
    s.valid[j] = g.valid[order[j]];
    std::copy_n(&g.q[3 * size_t{order[j]}], 3, &s.q[3 * j]);
  }
  const std::vector<uint8_t> plain = encode_scan_octree(s),
                             cones = encode_scan_octree(s, &table, 3),
                             mixed = encode_scan_octree(s, &table, 7);
  for (const std::vector<uint8_t>* p : {&plain, &cones, &mixed}) {
    const ScanGeometry d = decode_scan_geometry(p->data(), p->size(), "xt32");
    EXPECT_EQ(d.q, s.q);
    EXPECT_EQ(d.valid, s.valid);
  }
  std::printf("hesai-xt32 octree payload: %zu B plain, %zu B with cones and counting models\n",
              plain.size(), cones.size());
  EXPECT_LT(static_cast<double>(cones.size()), 0.95 * static_cast<double>(plain.size()));
  // The mix (L = 7) takes it down again by more than 5 % (docs/lab/2026-11-30-octree-mixing.md).
  std::printf("hesai-xt32 octree payload with the mix: %zu B\n", mixed.size());
  EXPECT_LT(static_cast<double>(mixed.size()), 0.95 * static_cast<double>(cones.size()));
}

}  // namespace
}  // namespace capz
