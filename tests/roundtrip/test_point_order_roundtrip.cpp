// --point-order any on data/scan_small (four Helios 16P sweeps with their fields): at 1 mm and
// 1 cm each frame comes back with the same multiset of point fields and the same number of gaps,
// every point within the bound of its partner (the promise check pairs them, capz/tool/verify.h),
// and the archive is not larger than the order-kept one without fields. A RoboSense E1 sweep
// with its fields at 1 cm is coded as octree frames, its fields with their points.
#include <gtest/gtest.h>

#include <algorithm>
#include <cmath>
#include <map>
#include <string>
#include <vector>

#include "../corrupt/chunk_util.h"
#include "capz/codec.h"
#include "capz/io.h"
#include "capz/tool/verify.h"
#include "coding/bytes.h"
#include "coding/scan_shared.h"
#include "test_util.h"

namespace capz {
namespace {

// Point i of t's fields as one row of bytes.
std::vector<uint8_t> field_row(const Take& t, size_t i) {
  std::vector<uint8_t> r;
  for (const PointAttribute& a : t.attributes) {
    const size_t b = a.bytes_per_point();
    r.insert(r.end(), a.data.begin() + static_cast<std::ptrdiff_t>(i * b),
             a.data.begin() + static_cast<std::ptrdiff_t>((i + 1) * b));
  }
  return r;
}

// Frame f's points as rows of their field bytes, sorted: the frame's fields as a multiset.
std::vector<std::vector<uint8_t>> field_rows(const Take& t, size_t f) {
  std::vector<std::vector<uint8_t>> rows;
  for (size_t i = t.frame_begin(f); i < t.frame_begin(f) + t.frame_points(f); ++i)
    rows.push_back(field_row(t, i));
  std::sort(rows.begin(), rows.end());
  return rows;
}

// --point-order any within `bound`.
CompressOptions any_at(double bound) {
  CompressOptions o;
  o.max_error = bound;
  o.any_point_order = true;
  return o;
}

TEST(PointOrderRoundTrip, GivenScanSmallThenEachFramesPointsAndFieldsAsASetWithinTheBound) {
  const Take t = read_take(std::string(CAPZ_REPO_DATA) + "/scan_small");
  ASSERT_TRUE(t.ragged());
  ASSERT_FALSE(t.attributes.empty());
  for (double bound : {0.001, 0.01}) {
    SCOPED_TRACE(bound);
    const CompressOptions o = any_at(bound);
    CompressStats st;
    const std::vector<uint8_t> z = compress(t, o, &st);
    EXPECT_LE(st.error.max_abs, bound);
    const Take d = decompress(z.data(), z.size());
    ASSERT_EQ(d.frame_offsets, t.frame_offsets);
    ASSERT_EQ(d.attributes.size(), t.attributes.size());
    for (size_t f = 0; f < t.frames; ++f) {
      EXPECT_EQ(field_rows(d, f), field_rows(t, f)) << "frame " << f;
      size_t gaps_t = 0, gaps_d = 0;
      for (size_t i = t.frame_begin(f); i < t.frame_begin(f) + t.frame_points(f); ++i)
        gaps_t += !t.valid[i], gaps_d += !d.valid[i];
      EXPECT_EQ(gaps_d, gaps_t);
    }
    const StreamInfo si = describe(z.data(), z.size());
    ASSERT_TRUE(si.points_reordered);
    const PromiseResult r = check_promise(t, d, promise_of(si));
    EXPECT_TRUE(r.holds) << r.why;
    EXPECT_LE(r.error.max_abs, bound);
    EXPECT_GT(r.error.max_abs, 0.0);
    CompressOptions drop = o, kept = o;
    drop.drop_fields = kept.drop_fields = true;
    kept.any_point_order = false;
    EXPECT_LE(compress(t, drop).size(), compress(t, kept).size());
    // With the fields the window is kept in the order whose SCNW and ATTR are smaller together:
    // sorted, these Helios sweeps' timestamps and angles cost more than the positions save.
    CompressOptions kept_fields = o;
    kept_fields.any_point_order = false;
    EXPECT_LE(z.size(), compress(t, kept_fields).size());
  }
}

// Whether the first SCNW of archive z holds octree frames (FORMAT.md "Octree frames": the
// payload's octree block; a 1 cm stream lists no negative zeros and has no split).
bool codes_octree_frames(const std::vector<uint8_t>& z) {
  const size_t at = capz_test::find_chunk(z, "SCNW");
  if (at == std::string::npos) return false;
  const uint8_t* p = z.data() + at + 8;
  const size_t n = capz_test::chunk_len(z, at);
  ByteReader r(p, n, "SCNW");
  r.varint();  // window
  const uint64_t total = r.varint();
  r.u8();  // gaps
  return scan::read_header(p + r.offset(), n - r.offset(), "SCNW", total).octree_size > 0;
}

// With its fields kept, a near sweep at 1 cm whose octree window (geometry and fields) is smaller
// than its best sorted one is coded as octree frames: each field value comes back with its point
// (a decoded point's field bytes are those of an original point within the bound of it).
TEST(PointOrderRoundTrip, GivenAnE1SweepWithFieldsAt1cmThenOctreeFramesAndFieldsWithTheirPoints) {
  const std::string path =
      capz_test::shared_data_or_skip("scan/robosense-e1/1693393248892823096.pcd");
  if (path.empty()) return;
  const Take t = read_take(path);
  ASSERT_FALSE(t.attributes.empty());
  const double bound = 0.01;
  const CompressOptions o = any_at(bound);
  CompressStats st;
  const std::vector<uint8_t> z = compress(t, o, &st);
  EXPECT_LE(st.error.max_abs, bound);
  EXPECT_TRUE(codes_octree_frames(z));
  CompressOptions kept = o;  // the file's order: no octree frames
  kept.any_point_order = false;
  EXPECT_FALSE(codes_octree_frames(compress(t, kept)));
  const Take d = decompress(z.data(), z.size());
  ASSERT_EQ(d.frame_offsets, t.frame_offsets);
  ASSERT_EQ(d.attributes.size(), t.attributes.size());
  EXPECT_EQ(field_rows(d, 0), field_rows(t, 0));
  std::multimap<std::vector<uint8_t>, size_t> by_row;  // original valid points by their fields
  for (size_t i = 0; i < t.total_points(); ++i)
    if (t.valid[i]) by_row.emplace(field_row(t, i), i);
  size_t paired = 0, valid = 0;
  for (size_t i = 0; i < d.total_points(); ++i) {
    if (!d.valid[i]) continue;
    ++valid;
    const auto range = by_row.equal_range(field_row(d, i));
    for (auto it = range.first; it != range.second; ++it) {
      bool within = true;
      for (size_t a = 0; a < 3; ++a)
        within = within && std::abs(d.xyz[3 * i + a] - t.xyz[3 * it->second + a]) <= bound;
      if (within) {
        ++paired, by_row.erase(it);
        break;
      }
    }
  }
  EXPECT_GT(valid, 20000u);
  EXPECT_EQ(paired, valid);
  const PromiseResult r = check_promise(t, d, promise_of(describe(z.data(), z.size())));
  EXPECT_TRUE(r.holds) << r.why;
}

}  // namespace
}  // namespace capz
