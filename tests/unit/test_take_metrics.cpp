#include <gtest/gtest.h>

#include <cmath>

#include "capz/error.h"
#include "capz/metrics.h"
#include "capz/take.h"
#include "coding/bytes.h"

using namespace capz;

TEST(Take, ResizeGivesAllGaps) {
  Take t;
  t.resize(3, 4);
  EXPECT_EQ(t.xyz.size(), 36u);
  EXPECT_EQ(t.gap_samples(), 12u);
  t.valid[5] = 1;
  EXPECT_TRUE(t.is_valid(1, 1));
  EXPECT_EQ(t.gap_samples(), 11u);
}

TEST(Units, KnownAndUnknown) {
  EXPECT_DOUBLE_EQ(units_to_metres(" MM "), 0.001);
  EXPECT_DOUBLE_EQ(units_to_metres("m"), 1.0);
  EXPECT_DOUBLE_EQ(units_to_metres("cm"), 0.01);
  EXPECT_EQ(units_to_metres("furlong"), 0.0);
}

TEST(Metrics, GivenOffsetWhenComparedThenMaxAndKgMatchHandComputation) {
  // Two frames, two points at x = -1 and +1 (centroid 0): ||A - E(A)||_F^2 = 4.
  Take a;
  a.resize(2, 2);
  for (size_t f = 0; f < 2; ++f) {
    a.at(f, 0)[0] = -1;
    a.at(f, 1)[0] = 1;
    a.valid[f * 2] = a.valid[f * 2 + 1] = 1;
  }
  Take b = a;
  b.at(1, 1)[1] = 0.5;  // one coordinate off by 0.5
  ErrorStats s = compare(a, b);
  EXPECT_EQ(s.samples, 4u);
  EXPECT_DOUBLE_EQ(s.max_error, 0.5);
  EXPECT_DOUBLE_EQ(s.rmse, std::sqrt(0.25 / 4));
  EXPECT_DOUBLE_EQ(s.kg_error, 100.0 * 0.5 / 2.0);
}

TEST(Metrics, GapsAreIgnored) {
  Take a;
  a.resize(1, 2);
  a.valid[0] = 1;
  a.at(0, 0)[0] = 1;
  Take b = a;
  b.at(0, 1)[2] = 1000;  // a gap sample differs: must not count
  EXPECT_EQ(compare(a, b).max_error, 0.0);
}

TEST(Metrics, ShapeMismatchThrows) {
  Take a, b;
  a.resize(1, 2);
  b.resize(2, 2);
  EXPECT_THROW(compare(a, b), Error);
}

TEST(Bytes, RoundTripAndTruncation) {
  ByteWriter w;
  w.u32(0xdeadbeef);
  w.svarint(-123456789);
  w.f64(3.25);
  w.str("hello");
  ByteReader r(w.buffer().data(), w.size(), "test");
  EXPECT_EQ(r.u32(), 0xdeadbeefu);
  EXPECT_EQ(r.svarint(), -123456789);
  EXPECT_EQ(r.f64(), 3.25);
  EXPECT_EQ(r.str(), "hello");
  EXPECT_TRUE(r.at_end());
  EXPECT_THROW(r.u8(), Error);
  // A length that claims more than the buffer holds is rejected before any allocation.
  ByteWriter big;
  big.varint(uint64_t{1} << 40);
  ByteReader r2(big.buffer().data(), big.size(), "test");
  EXPECT_THROW(r2.str(), Error);
}
