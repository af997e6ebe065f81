// Octree frames (docs/FORMAT.md "Scans (format 1.1)", "Octree frames"): a frame's valid points
// as the cells of an octree with their counts. The coder alone here (an octree block of one or
// more frames round trip in octree order, one cell, gaps, damaged blocks, each corrupt case of
// the spec crafted); the payload's octree frames in test_scan_octree_payload.cpp.
#include <gtest/gtest.h>

#include <cmath>
#include <random>

#include "capz/error.h"
#include "coding/scan_octree.h"

namespace capz {
namespace {

// A near sweep on a 2 cm grid: returns of 32 rings over a turn from a wavy wall 0.5-1.1 m away
// (so many share a cell), `gaps` of them NaN.
ScanGeometry near_sweep(double gaps, uint32_t seed) {
  std::mt19937 rng(seed);
  std::uniform_real_distribution<double> u(0, 1);
  ScanGeometry g;
  uint32_t n = 0;
  for (int c = 0; c < 1000; ++c)
    for (int k = 0; k < 32; ++k, ++n) {
      if (u(rng) < gaps) {
        g.valid.push_back(0);
        g.q.insert(g.q.end(), {0, 0, 0});
        continue;
      }
      const double az = 0.00628 * c, el = -0.4 + 0.025 * k;
      const double range = 0.8 + 0.3 * std::sin(3 * az) + 0.004 * u(rng);
      const double rho = range * std::cos(el);
      const double p[3] = {rho * std::cos(az), rho * std::sin(az), range * std::sin(el)};
      g.valid.push_back(1);
      for (double v : p) g.q.push_back(static_cast<int32_t>(std::floor(v / 0.02 + 0.5)));
    }
  g.counts.push_back(n);
  return g;
}

// g's frame [first, first + n) in the order given (indices from first).
ScanGeometry reordered(const ScanGeometry& g, const std::vector<uint32_t>& order) {
  ScanGeometry s;
  s.counts.push_back(static_cast<uint32_t>(order.size()));
  for (uint32_t j : order) {
    s.valid.push_back(g.valid[j]);
    for (int a = 0; a < 3; ++a) s.q.push_back(g.valid[j] ? g.q[3 * j + a] : 0);
  }
  return s;
}

uint32_t copies_of(const ScanGeometry& s) {
  uint32_t c = 0;
  for (size_t i = 1; i < s.valid.size(); ++i)
    c +=
        s.valid[i] && s.valid[i - 1] && std::equal(&s.q[3 * i], &s.q[3 * i] + 3, &s.q[3 * (i - 1)]);
  return c;
}

std::vector<uint8_t> encode(const ScanGeometry& s, uint32_t copies) {
  IntEncoder enc(scan::kOctreeContexts);
  scan::start_octree_block(&enc);
  std::vector<int32_t> prev;
  encode_octree_frame(s, 0, s.valid.size(), copies, &prev, &enc);
  return enc.finish();
}

ScanGeometry decode(const std::vector<uint8_t>& block, size_t n, uint32_t copies, bool gaps) {
  IntDecoder dec(block.data(), block.size(), scan::kOctreeContexts, "octree");
  scan::start_octree_block(&dec);
  ScanGeometry d;
  d.q.assign(3 * n, -1);
  d.valid.assign(n, 2);
  std::vector<int32_t> prev;
  size_t cells_left = SIZE_MAX;
  scan::decode_octree_frame(&dec, n, copies, gaps, &cells_left, &prev, d.q.data(), d.valid.data());
  if (!dec.at_end()) throw Error(ErrorCode::kCorrupt, "octree: bytes left");
  return d;
}

TEST(ScanOctree, GivenANearSweepInOctreeOrderWhenCodedThenItsPointsComeBackInThatOrder) {
  for (double gaps : {0.0, 0.03}) {
    const ScanGeometry g = near_sweep(gaps, 5);
    const ScanGeometry s = reordered(g, octree_frame_order(g, 0, g.valid.size()));
    const uint32_t copies = copies_of(s);
    ASSERT_GT(copies, s.valid.size() / 4);  // a near sweep: many points share a cell
    const std::vector<uint8_t> block = encode(s, copies);
    const ScanGeometry d = decode(block, s.valid.size(), copies, gaps > 0);
    EXPECT_EQ(d.valid, s.valid);
    EXPECT_EQ(d.q, s.q);
    // The cells of a smooth wall: a few bits a cell (counts included).
    const size_t cells = s.valid.size() - copies -
                         static_cast<size_t>(std::count(s.valid.begin(), s.valid.end(), 0));
    EXPECT_LT(8.0 * static_cast<double>(block.size()) / static_cast<double>(cells), 5.0);
  }
}

TEST(ScanOctree, GivenTheOrderWhenBuiltThenValidPointsAreByMortonKeyWithCopiesTogetherAndGapsLast) {
  const ScanGeometry g = near_sweep(0.05, 9);
  const std::vector<uint32_t> order = octree_frame_order(g, 0, g.valid.size());
  const ScanGeometry s = reordered(g, order);
  std::vector<uint32_t> sorted = order;
  std::sort(sorted.begin(), sorted.end());
  for (size_t j = 0; j < sorted.size(); ++j) ASSERT_EQ(sorted[j], j);  // a permutation
  int64_t lo[3] = {INT32_MAX, INT32_MAX, INT32_MAX};
  for (size_t i = 0; i < s.valid.size(); ++i)
    for (int a = 0; a < 3; ++a)
      if (s.valid[i]) lo[a] = std::min<int64_t>(lo[a], s.q[3 * i + a]);
  uint64_t last = 0;
  bool gap = false;
  for (size_t i = 0; i < s.valid.size(); ++i) {
    if (!s.valid[i]) {
      gap = true;
      continue;
    }
    ASSERT_FALSE(gap) << "a valid point after a gap";
    const uint64_t k = scan::octree::key(static_cast<uint64_t>(s.q[3 * i] - lo[0]),
                                         static_cast<uint64_t>(s.q[3 * i + 1] - lo[1]),
                                         static_cast<uint64_t>(s.q[3 * i + 2] - lo[2]));
    ASSERT_GE(k, last);
    last = k;
  }
}

TEST(ScanOctree, GivenOneCellOfManyPointsWhenCodedThenTheTreeHasDepthZero) {
  ScanGeometry s;
  s.counts.push_back(9);
  for (int j = 0; j < 9; ++j) {
    s.valid.push_back(1);
    s.q.insert(s.q.end(), {-40, 7, 123456});
  }
  const std::vector<uint8_t> block = encode(s, 8);
  const ScanGeometry d = decode(block, 9, 8, false);
  EXPECT_EQ(d.q, s.q);
  EXPECT_EQ(d.valid, s.valid);
  EXPECT_LT(block.size(), 16u);
}

TEST(ScanOctree, GivenADamagedBlockWhenDecodedThenItIsCorruptOrDecodesToAFrameOfItsSize) {
  const ScanGeometry g = near_sweep(0.0, 3);
  const ScanGeometry s = reordered(g, octree_frame_order(g, 0, g.valid.size()));
  const uint32_t copies = copies_of(s);
  const std::vector<uint8_t> block = encode(s, copies);
  // The wrong copies: the cells or the counts disagree.
  EXPECT_THROW(decode(block, s.valid.size(), copies + 1, false), Error);
  EXPECT_THROW(decode(block, s.valid.size() + 1, copies, false), Error);
  // Cuts and flips: never a crash, never a frame of another size.
  std::mt19937 rng(1);
  for (int t = 0; t < 200; ++t) {
    std::vector<uint8_t> bad = block;
    if (t % 2) {
      bad.resize(rng() % bad.size());
    } else {
      bad[rng() % bad.size()] ^= static_cast<uint8_t>(1u << (rng() % 8));
    }
    try {
      const ScanGeometry d = decode(bad, s.valid.size(), copies, false);
      EXPECT_EQ(d.valid.size(), s.valid.size());
    } catch (const Error& e) {
      EXPECT_EQ(e.code(), ErrorCode::kCorrupt);
    }
  }
}

// Writes scripted child bits (symbols, 2 and above too) under the contexts the walk gives.
class ScriptedBits {
 public:
  ScriptedBits(IntEncoder* enc, std::vector<int> symbols) : enc_(enc), s_(std::move(symbols)) {}
  bool bit(int ctx, int, uint64_t) {
    const int s = at_ < s_.size() ? s_[at_++] : 0;
    enc_->put_symbol(s, ctx);
    return s == 1;
  }
  [[noreturn]] void too_many() { throw Error(ErrorCode::kInternal, "scripted: too many"); }
  [[noreturn]] void too_much() { throw Error(ErrorCode::kInternal, "scripted: too much"); }

 private:
  IntEncoder* enc_;
  std::vector<int> s_;
  size_t at_ = 0;
};

// A block of one frame: G (when > 0), D, the corner, the child bits (for a walk that allows
// `room` nodes a level), then the counts.
std::vector<uint8_t> crafted(uint32_t gaps, uint32_t d, const std::vector<int32_t>& lo,
                             const std::vector<int>& bits, size_t room,
                             const std::vector<uint32_t>& counts) {
  IntEncoder enc(scan::kOctreeContexts);
  scan::start_octree_block(&enc);
  if (gaps > 0) enc.put(gaps, scan::kOctCornerCtx);
  enc.put(d, scan::kOctDepthCtx);
  for (int32_t v : lo) enc.put_signed(v, scan::kOctCornerCtx);
  ScriptedBits io(&enc, bits);
  const int64_t lo64[3] = {lo[0], lo[1], lo[2]};
  if (d <= 21) scan::octree::code_tree(io, static_cast<int>(d), room, lo64, {});
  for (uint32_t c : counts) enc.put(c, scan::kOctCountCtx);  // cell 0 at the origin: context 2
  return enc.finish();
}

void expect_corrupt(const std::vector<uint8_t>& block, size_t n, uint32_t copies, bool gaps,
                    const char* says) {
  try {
    decode(block, n, copies, gaps);
    ADD_FAILURE() << "decoded; expected: " << says;
  } catch (const Error& e) {
    EXPECT_EQ(e.code(), ErrorCode::kCorrupt) << e.what();
    EXPECT_NE(std::string(e.what()).find(says), std::string::npos) << e.what();
  }
}

// Each corrupt case of FORMAT.md's octree frame, crafted, with the decoder's message.
TEST(ScanOctree, GivenEachCorruptCaseOfTheSpecThenCorruptSayingWhich) {
  const std::vector<int32_t> origin = {0, 0, 0};
  // The frame decodes as crafted: two cells (0,0,0) and (0,0,1) at depth 1.
  EXPECT_EQ(decode(crafted(0, 1, origin, {1, 1, 0, 0, 0, 0, 0, 0}, 2, {}), 2, 0, false).q,
            (std::vector<int32_t>{0, 0, 0, 0, 0, 1}));
  const char* gaps = "gaps are out of range";
  expect_corrupt(crafted(0, 0, origin, {}, 1, {}), 5, 0, true, gaps);  // G = 0 read
  expect_corrupt(crafted(5, 0, origin, {}, 1, {}), 5, 0, true, gaps);  // G = n: no cell
  expect_corrupt(crafted(4, 0, origin, {}, 1, {}), 5, 1, true, gaps);  // G = n - d: no cell
  expect_corrupt(crafted(0, 22, origin, {}, 1, {}), 2, 0, false, "deeper than 21");
  expect_corrupt(crafted(0, 0, origin, {}, 1, {}), 2, 0, false, "depth 0 with more than one");
  const std::vector<int32_t> top = {0, INT32_MAX, 0};
  expect_corrupt(crafted(0, 1, top, {1}, 1, {}), 1, 0, false, "beyond the grid integers");
  expect_corrupt(crafted(0, 1, origin, {2}, 1, {}), 1, 0, false, "neither 0 nor 1");
  expect_corrupt(crafted(0, 1, origin, {1, 1}, 8, {}), 1, 0, false, "more nodes than cells");
  expect_corrupt(crafted(0, 1, origin, {1, 0, 0, 0, 0, 0, 0, 0}, 1, {}), 2, 0, false,
                 "fewer cells");
  // One cell at depth 0 with 2 copies: a count of 3 is above them, 1 falls short.
  expect_corrupt(crafted(0, 0, origin, {}, 1, {3}), 3, 2, false, "exceeds the frame's copies");
  expect_corrupt(crafted(0, 0, origin, {}, 1, {1}), 3, 2, false, "fall short");
  EXPECT_EQ(decode(crafted(0, 0, origin, {}, 1, {2}), 3, 2, false).q, std::vector<int32_t>(9, 0));
}

// A cell's neighbours outside the cube are no cells (FORMAT.md step 5), also at depth 21, where
// the neighbour at x = 2^21 has no 21-bit key: it must not be taken for the cell at x = 0.
TEST(ScanOctree, GivenACellAtTheFarFaceOfADepth21CubeThenItsCountContextHasNoNeighbour) {
  const uint64_t far = (uint64_t{1} << 21) - 1;
  const std::vector<uint64_t> cells = {scan::octree::key(0, 0, 0), scan::octree::key(far, 0, 0)};
  scan::octree::KeySet set, before;
  set.reset(2);
  set.insert(cells[0], 0);
  set.insert(cells[1], 1);
  before.reset(0);
  const std::vector<uint32_t> points = {9, 1};  // the cell at 0 has 9 points
  const int64_t abs[3] = {static_cast<int64_t>(far), 0, 0};
  // Octave 15 (x^2 has 42 bits), no neighbour before it (nc 0), no previous frame (pc 0).
  EXPECT_EQ(scan::octree::count_context(cells, set, points, 1, abs, before, {}),
            scan::kOctCountCtx + 6 * (6 * 15 + 0) + 0);
}

}  // namespace
}  // namespace capz
