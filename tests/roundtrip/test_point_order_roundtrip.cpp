// --point-order any on data/scan_small (four Helios 16P sweeps with their fields): at 1 mm and
// 1 cm each frame comes back with the same multiset of point fields and the same number of gaps,
// every point within the bound of its partner (the promise check pairs them, capz/tool/verify.h),
// and the archive is not larger than the order-kept one without fields.
#include <gtest/gtest.h>

#include <algorithm>
#include <string>
#include <vector>

#include "capz/codec.h"
#include "capz/io.h"
#include "capz/tool/verify.h"

namespace capz {
namespace {

// Frame f's points as rows of their field bytes, sorted: the frame's fields as a multiset.
std::vector<std::vector<uint8_t>> field_rows(const Take& t, size_t f) {
  std::vector<std::vector<uint8_t>> rows;
  for (size_t i = t.frame_begin(f); i < t.frame_begin(f) + t.frame_points(f); ++i) {
    std::vector<uint8_t> r;
    for (const PointAttribute& a : t.attributes) {
      const size_t b = a.bytes_per_point();
      r.insert(r.end(), a.data.begin() + static_cast<std::ptrdiff_t>(i * b),
               a.data.begin() + static_cast<std::ptrdiff_t>((i + 1) * b));
    }
    rows.push_back(std::move(r));
  }
  std::sort(rows.begin(), rows.end());
  return rows;
}

TEST(PointOrderRoundTrip, GivenScanSmallThenEachFramesPointsAndFieldsAsASetWithinTheBound) {
  const Take t = read_take(std::string(CAPZ_REPO_DATA) + "/scan_small");
  ASSERT_TRUE(t.ragged());
  ASSERT_FALSE(t.attributes.empty());
  for (double bound : {0.001, 0.01}) {
    SCOPED_TRACE(bound);
    CompressOptions o;
    o.max_error = bound;
    o.any_point_order = true;
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

}  // namespace
}  // namespace capz
