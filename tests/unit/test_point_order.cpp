// --point-order any (docs/FORMAT.md "Points reordered"): each frame's points come back in the
// coded order, every point with its own fields, within the bound, gaps after the valid points;
// HEAD bit 5 says so (describe, the promise check pairs the points as sets); the default keeps
// the order; --lossless is refused.
#include <gtest/gtest.h>

#include <algorithm>
#include <cmath>
#include <cstring>
#include <map>
#include <random>

#include "capz/codec.h"
#include "capz/error.h"
#include "capz/stream.h"
#include "capz/tool/file.h"
#include "capz/tool/verify.h"
#include "metrics/point_match.h"
#include "synthetic.h"
#include "test_util.h"

namespace capz {
namespace {

// Synthetic sweeps whose frames hold their points shuffled (a driver's file order that is not
// the firing order), with an `id` field U4 naming each point (its place in the take) and gaps.
Take shuffled_scan(size_t frames) {
  Take t = capz_test::synthetic_sweeps(frames, 150, 37, 5, 40, 3, 0.3, 7, 23, 5);
  std::mt19937 rng(5);
  for (size_t f = 0; f < t.frames; ++f) {
    const size_t p0 = t.frame_begin(f), n = t.frame_points(f);
    std::vector<size_t> perm(n);
    for (size_t j = 0; j < n; ++j) perm[j] = p0 + j;
    std::shuffle(perm.begin(), perm.end(), rng);
    const std::vector<double> xyz = t.xyz;
    const std::vector<uint8_t> valid = t.valid;
    for (size_t j = 0; j < n; ++j) {
      std::copy_n(&xyz[3 * perm[j]], 3, &t.xyz[3 * (p0 + j)]);
      t.valid[p0 + j] = valid[perm[j]];
    }
  }
  t.pcd->fields = {{"x", 'F', 4, 1}, {"y", 'F', 4, 1}, {"z", 'F', 4, 1}, {"id", 'U', 4, 1}};
  PointAttribute id;
  id.name = "id";
  id.type = 'U';
  id.size = 4;
  for (size_t i = 0; i < t.total_points(); ++i)
    for (int k = 0; k < 4; ++k) id.data.push_back(static_cast<uint8_t>(i >> (8 * k)));
  t.attributes.push_back(id);
  return t;
}

uint32_t id_of(const Take& t, size_t i) {
  uint32_t v;
  std::memcpy(&v, &t.attributes.at(0).data[4 * i], 4);
  return v;
}

CompressOptions any_order(double bound) {
  CompressOptions o;
  o.max_error = bound;
  o.any_point_order = true;
  return o;
}

// Each decoded point is, by its id, a distinct source point of the same frame, within the bound;
// each frame keeps its count and its number of gaps, the gaps last.
void expect_same_points(const Take& src, const Take& d, double bound) {
  ASSERT_TRUE(d.ragged());
  ASSERT_EQ(d.frame_offsets, src.frame_offsets);
  for (size_t f = 0; f < src.frames; ++f) {
    const size_t p0 = src.frame_begin(f), n = src.frame_points(f);
    std::vector<bool> seen(n, false);
    size_t gaps = 0, src_gaps = 0;
    for (size_t j = p0; j < p0 + n; ++j) src_gaps += !src.valid[j];
    for (size_t j = p0; j < p0 + n; ++j) {
      if (!d.valid[j]) {
        ++gaps;
        continue;
      }
      EXPECT_EQ(gaps, 0u) << "a valid point after a gap in frame " << f;
      const uint32_t i = id_of(d, j);
      ASSERT_GE(i, p0);
      ASSERT_LT(i, p0 + n);
      ASSERT_FALSE(seen[i - p0]) << "point " << i << " twice";
      seen[i - p0] = true;
      ASSERT_TRUE(src.valid[i]);
      for (size_t a = 0; a < 3; ++a)
        EXPECT_LE(std::fabs(static_cast<float>(d.xyz[3 * j + a]) - src.xyz[3 * i + a]), bound);
    }
    EXPECT_EQ(gaps, src_gaps);
  }
}

TEST(PointOrder, GivenShuffledSweepsThenSamePointsWithTheirFieldsSmallerThanKept) {
  const Take t = shuffled_scan(4);
  for (double bound : {0.001, 0.01}) {
    SCOPED_TRACE(bound);
    CompressOptions o = any_order(bound);
    o.window_frames = 2;
    const std::vector<uint8_t> z = compress(t, o);
    const Take d = decompress(z.data(), z.size());
    expect_same_points(t, d, bound);
    const StreamInfo si = describe(z.data(), z.size());
    EXPECT_TRUE(si.points_reordered);
    EXPECT_TRUE(check_promise(t, d, promise_of(si)).holds)
        << check_promise(t, d, promise_of(si)).why;
    // The order moved (the firing order is not the shuffle), and the stream is smaller kept off.
    size_t moved = 0;
    for (size_t j = 0; j < d.total_points(); ++j) moved += d.valid[j] && id_of(d, j) != j;
    EXPECT_GT(moved, d.total_points() / 2);
    CompressOptions kept = o;
    kept.any_point_order = false;
    CompressOptions drop_any = o, drop_kept = kept;
    drop_any.drop_fields = drop_kept.drop_fields = true;
    EXPECT_LT(compress(t, drop_any).size(), compress(t, drop_kept).size());
    const std::vector<uint8_t> zk = compress(t, kept);
    EXPECT_FALSE(describe(zk.data(), zk.size()).points_reordered);
  }
}

TEST(PointOrder, GivenAPointMovedOrAFieldChangedThenThePromiseBreaks) {
  const Take t = shuffled_scan(2);
  const std::vector<uint8_t> z = compress(t, any_order(0.001));
  const Promise p = promise_of(describe(z.data(), z.size()));
  Take d = decompress(z.data(), z.size());
  ASSERT_TRUE(check_promise(t, d, p).holds);
  Take moved = d;
  size_t j = 0;
  while (!moved.valid[j]) ++j;
  moved.xyz[3 * j] += 0.0025;
  const PromiseResult r = check_promise(t, moved, p);
  EXPECT_FALSE(r.holds);
  EXPECT_NE(r.why.find("compared as a set"), std::string::npos) << r.why;
  Take field = d;
  field.attributes[0].data[4 * j] ^= 1;
  EXPECT_FALSE(check_promise(t, field, p).holds);
  // Block by block (compress --rm's check): the same pairing, frames [0, 1) then [1, 2).
  for (const Take* dec : {&d, &moved}) {
    PromiseCheck c(p);
    ASSERT_TRUE(c.header(t, *dec));
    std::unique_ptr<FrameSource> a = take_frames(t), b = take_frames(*dec);
    FrameBlock x, y;
    for (size_t f = 0; f < t.frames; ++f) {
      a->read(f, 1, &x);
      b->read(f, 1, &y);
      c.frames(x, y);
    }
    EXPECT_EQ(c.finish(), dec == &d) << c.why();
  }
  // The same decoded take read as if its order were the source's breaks too.
  Promise kept = p;
  kept.points_reordered = false;
  EXPECT_FALSE(check_promise(t, d, kept).holds);
}

// Two points whose partners a nearest-first pairing would swap wrongly: A at 0 is nearer B's
// decoded point (0.96) than its own (-0.98), and B at 1.95 reaches only 0.96; the pairing moves
// A to its own along an augmenting path. A third point with no partner is named.
TEST(PointOrder, GivenCrowdedPointsThenThePairingFindsTheOneThatHolds) {
  Take o, d;
  o.resize_ragged({2});
  o.xyz = {0, 0, 0, 1.95, 0, 0};
  o.valid = {1, 1};
  d = o;
  d.xyz = {0.96, 0, 0, -0.98, 0, 0};
  std::vector<size_t> partner;
  std::string why;
  ASSERT_TRUE(match_reordered(points_of(o), points_of(d), 1.0, {}, &partner, &why)) << why;
  EXPECT_EQ(partner, (std::vector<size_t>{1, 0}));
  std::vector<double> xyz;
  std::vector<uint8_t> valid;
  std::vector<std::vector<uint8_t>> fields;
  move_to_partners(points_of(o), partner, &xyz, &valid, &fields);
  EXPECT_EQ(xyz, (std::vector<double>{1.95, 0, 0, 0, 0, 0}));
  EXPECT_EQ(valid, (std::vector<uint8_t>{1, 1}));
  d.xyz[0] = 3.5;  // now nothing decoded is within 1 of B
  EXPECT_FALSE(match_reordered(points_of(o), points_of(d), 1.0, {}, &partner, &why));
  EXPECT_NE(why.find("frame 0, point 1 has no decoded point within the bound"), std::string::npos)
      << why;
}

// Points each decoded within the bound at its own place but nearer the next point's original
// (as raster frames on their rays decode, moved within the bound): a nearest-first pairing
// takes every next point's partner, and the chain of 200 is beyond any augmenting path's depth;
// the pairing at the points' own places holds.
TEST(PointOrder, GivenPointsMovedTowardTheirNeighboursThenTheOwnPlacePairingHolds) {
  Take o, d;
  const size_t n = 200;
  o.resize_ragged({static_cast<uint32_t>(n)});
  o.valid.assign(n, 1);
  o.xyz.assign(3 * n, 0.0);
  for (size_t i = 0; i < n; ++i) o.xyz[3 * i] = static_cast<double>(i);
  d = o;
  for (size_t i = 0; i < n; ++i) d.xyz[3 * i] -= 0.55;  // 0.45 from point i - 1's original
  std::vector<size_t> partner;
  std::string why;
  ASSERT_TRUE(match_reordered(points_of(o), points_of(d), 0.6, {}, &partner, &why)) << why;
  for (size_t j = 0; j < n; ++j) ASSERT_EQ(partner[j], j);
}

// shuffled_scan's frames cut to one count (a fixed take, as a folder of fixed-size sweeps is read),
// its ids renumbered to the fixed index f x points + j; with `organized`, HEIGHT 2.
Take fixed_shuffled_scan(size_t frames, bool organized) {
  const Take r = shuffled_scan(frames);
  size_t least = r.frame_points(0);
  for (size_t f = 0; f < r.frames; ++f) least = std::min(least, r.frame_points(f));
  least -= least % 2;
  Take t = r;
  t.frame_offsets.clear();
  t.resize(r.frames, least);
  std::vector<uint8_t>& id = t.attributes.at(0).data;
  id.assign(4 * t.frames * least, 0);
  for (size_t f = 0; f < r.frames; ++f)
    for (size_t j = 0; j < least; ++j) {
      std::copy_n(r.at(f, j), 3, t.at(f, j));
      const size_t i = f * least + j;
      t.valid[i] = r.valid[r.frame_begin(f) + j];
      for (int k = 0; k < 4; ++k) id[4 * i + k] = static_cast<uint8_t>(i >> (8 * k));
    }
  t.pcd->width = organized ? least / 2 : least;
  t.pcd->height = organized ? 2 : 1;
  return t;
}

// Unorganized frames of one count (a driver's fixed-size sweeps) are reordered as sweeps of their
// own counts are: the archive says so, each frame's points come back as a set with their fields
// within the bound, and it is smaller than the order kept (it used to stay a fixed take in its
// order through POSW alone, 3.4x larger than kept at 1 cm on five real sweeps cut so:
// docs/lab/2026-11-30-fixed-count-any.md). An organized take keeps its layout and order.
TEST(PointOrder, GivenFixedSizeSweepsThenAnyReordersThemUnlessOrganized) {
  const Take t = fixed_shuffled_scan(4, false);
  ASSERT_FALSE(t.ragged());
  Take as_ragged = t;
  as_ragged.resize_ragged(std::vector<size_t>(t.frames, t.points));
  as_ragged.xyz = t.xyz;
  as_ragged.valid = t.valid;
  for (double bound : {0.001, 0.01}) {
    SCOPED_TRACE(bound);
    CompressOptions o = any_order(bound);
    const std::vector<uint8_t> z = compress(t, o);
    const StreamInfo si = describe(z.data(), z.size());
    EXPECT_TRUE(si.points_reordered);
    const Take d = decompress(z.data(), z.size());
    expect_same_points(as_ragged, d, bound);
    EXPECT_TRUE(check_promise(t, d, promise_of(si)).holds)
        << check_promise(t, d, promise_of(si)).why;
    CompressOptions kept = o;
    kept.any_point_order = false;
    EXPECT_LT(z.size(), compress(t, kept).size());
  }
  // An organized take: the order kept, the same bytes as asking for it (both coders tried).
  const Take organized = fixed_shuffled_scan(4, true);
  const std::vector<uint8_t> zo = compress(organized, any_order(0.01));
  EXPECT_FALSE(describe(zo.data(), zo.size()).points_reordered);
  CompressOptions kept = any_order(0.01);
  kept.any_point_order = false;
  EXPECT_EQ(zo, compress(organized, kept));
  // Past the both-ways coding of 4 frames (the estimate from the prefix, then the whole coded):
  // streamed, the same bytes as in memory.
  const Take six = fixed_shuffled_scan(6, false);
  const std::vector<uint8_t> z6 = compress(six, any_order(0.01));
  EXPECT_TRUE(describe(z6.data(), z6.size()).points_reordered);
  capz_test::TempDir dir("capz_point_order_stream");
  std::unique_ptr<FrameSource> src = take_frames(six);
  compress_stream(*src, any_order(0.01), dir.file("s.capz"), true);
  EXPECT_EQ(read_file(dir.file("s.capz")), z6);
}

TEST(PointOrder, GivenLosslessThenRefusedByName) {
  CompressOptions o;
  o.lossless = true;
  o.any_point_order = true;
  std::string msg;
  EXPECT_EQ(capz_test::error_of([&] { compress(shuffled_scan(2), o); }, &msg),
            ErrorCode::kInvalidParameter);
  EXPECT_NE(msg.find("--point-order any with --lossless"), std::string::npos) << msg;
}

}  // namespace
}  // namespace capz
