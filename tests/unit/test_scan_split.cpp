// The float32 split of lossless scan windows (src/coding/scan_split.h; FORMAT.md "Lossless
// ragged streams"): every float32 back bit for bit through a grid integer and a correction
// within its budget, and clean failures on corrections the format calls corrupt.
#include <gtest/gtest.h>

#include <cfloat>
#include <cmath>
#include <cstring>
#include <limits>
#include <random>

#include "capz/error.h"
#include "coding/scan_split.h"

namespace capz {
namespace {

uint32_t bits_of(float f) {
  uint32_t b;
  std::memcpy(&b, &f, 4);
  return b;
}

// Splits `values` (one coordinate each, as x with y z 0) at exponent e, checks every correction
// against its budget and the decoder gives every value's float32 bits back.
void expect_round_trip(const std::vector<float>& values, int e) {
  const size_t n = values.size();
  std::vector<double> xyz(3 * n, 0.0);
  for (size_t i = 0; i < n; ++i) {
    xyz[3 * i] = values[i];
    xyz[3 * i + 1] = -static_cast<double>(values[i]);
    xyz[3 * i + 2] = 0.0;
  }
  std::vector<uint8_t> valid(n, 1);
  std::vector<int32_t> q;
  std::vector<uint32_t> t;
  ASSERT_TRUE(scan::split_coordinates(xyz.data(), valid.data(), n, e, scan::kMaxSplitInt, &q, &t))
      << "e " << e;
  for (size_t k = 0; k < 3 * n; ++k) {
    const int b = scan::split_budget(q[k], e);
    if (b < 32) {
      EXPECT_LT(uint64_t{t[k]}, uint64_t{1} << b) << xyz[k] << " at e " << e;
    }
    EXPECT_LE(b, q[k] == 0 ? 32 : 24);
  }
  const std::vector<uint8_t> block = scan::encode_split(e, q, t, valid);
  std::vector<double> out(3 * n, 7.0);
  scan::decode_split(block.data(), block.size(), "split", e, q, valid, out.data());
  for (size_t k = 0; k < 3 * n; ++k)
    EXPECT_EQ(bits_of(static_cast<float>(out[k])), bits_of(static_cast<float>(xyz[k])))
        << xyz[k] << " comes back as " << out[k] << " at e " << e;
}

// Float32s within `steps` ulps of 2^k, for k over the range the exponent's integers reach.
std::vector<float> near_powers_of_two(int e, int steps) {
  std::vector<float> v;
  for (int k = -149; k <= 127; ++k) {
    const float p = std::ldexp(1.0f, k);
    if (!(std::fabs(std::ldexp(static_cast<double>(p), e)) < 0.25 * scan::kMaxSplitInt)) continue;
    float lo = p, hi = p;
    v.push_back(p);
    for (int s = 0; s < steps; ++s) {
      lo = std::nextafter(lo, 0.0f);
      hi = std::nextafter(hi, FLT_MAX);
      v.push_back(lo);
      v.push_back(hi);
    }
  }
  return v;
}

TEST(ScanSplit, BudgetsFollowTheFloat32SpacingAtTheCell) {
  // q = 1 at E = 10: m = 2^-11, spacing 2^-34, u = 2^-34 < s = 2^-10: 24 bits.
  EXPECT_EQ(scan::split_budget(1, 10), 24);
  EXPECT_EQ(scan::split_budget(-1, 10), 24);
  EXPECT_EQ(scan::split_budget(0, 10), scan::kZeroBudget);
  // 10 m at a 1 mm-ish grid (2^-10): 10240 s, spacing 2^-20: 10 bits.
  EXPECT_EQ(scan::split_budget(10240, 10), 10);
  // Integers whose cell holds float32s at the grid spacing or coarser: no bits.
  EXPECT_EQ(scan::split_budget(1 << 29, 0), 0);
  EXPECT_EQ(scan::split_budget(-(1 << 24), 0), 0);
  // At 2^24 s the spacing reaches s.
  EXPECT_EQ(scan::split_budget(1 << 23, 0), 1);
  EXPECT_EQ(scan::split_budget((1 << 23) + 1, 0), 0);
}

TEST(ScanSplit, ZerosSubnormalsAndTinyValuesKeepTheirBits) {
  const std::vector<float> v = {0.0f,
                                -0.0f,
                                std::numeric_limits<float>::denorm_min(),
                                -std::numeric_limits<float>::denorm_min(),
                                FLT_MIN,
                                std::nextafter(FLT_MIN, 0.0f),
                                -FLT_MIN,
                                1e-30f,
                                -3e-12f};
  for (int e : {-64, -10, 0, 10, 17, 64}) expect_round_trip(v, e);
}

TEST(ScanSplit, EveryFloat32NearAPowerOfTwoComesBack) {
  for (int e : {-64, -20, -1, 0, 1, 7, 10, 13, 17, 24, 40, 64})
    expect_round_trip(near_powers_of_two(e, 40), e);
}

TEST(ScanSplit, HalfCellsAndRandomCoordinatesComeBack) {
  std::mt19937 rng(37);
  std::uniform_real_distribution<double> u(-120, 120);
  for (int e : {7, 10, 12, 17}) {
    const double s = std::ldexp(1.0, -e);
    std::vector<float> v;
    for (int i = 0; i < 4000; ++i) v.push_back(static_cast<float>(u(rng)));
    for (int k = -5; k <= 5; ++k) {  // cell edges: q s +- s/2 and their neighbours
      const float edge = static_cast<float>((k + 0.5) * s);
      v.push_back(edge);
      v.push_back(std::nextafter(edge, 0.0f));
      v.push_back(std::nextafter(edge, FLT_MAX));
      v.push_back(-edge);
    }
    expect_round_trip(v, e);
  }
}

TEST(ScanSplit, CoordinatesBeyondTheIntegersOrNotFiniteAreNotSplit) {
  std::vector<uint8_t> valid = {1};
  std::vector<int32_t> q;
  std::vector<uint32_t> t;
  for (double v : {static_cast<double>(FLT_MAX), -static_cast<double>(FLT_MAX),
                   std::numeric_limits<double>::infinity(), std::nan("")}) {
    const double xyz[3] = {v, 0, 0};
    EXPECT_FALSE(scan::split_coordinates(xyz, valid.data(), 1, -64, scan::kMaxSplitInt, &q, &t));
  }
  const double big[3] = {1e6, 0, 0};  // 1e6 2^10 > 2^29
  EXPECT_FALSE(scan::split_coordinates(big, valid.data(), 1, 10, int64_t{1} << 29, &q, &t));
  EXPECT_TRUE(scan::split_coordinates(big, valid.data(), 1, 0, int64_t{1} << 29, &q, &t));
  // A gap's NaN is no coordinate.
  valid[0] = 0;
  const double gap[3] = {std::nan(""), std::nan(""), std::nan("")};
  EXPECT_TRUE(scan::split_coordinates(gap, valid.data(), 1, 10, scan::kMaxSplitInt, &q, &t));
}

// decode_split of one point's corrections t at integers q throws kCorrupt.
void expect_corrupt(int e, std::vector<int32_t> q, std::vector<uint32_t> t) {
  const std::vector<uint8_t> valid = {1};
  const std::vector<uint8_t> block = scan::encode_split(e, q, t, valid);
  std::vector<double> out(3);
  try {
    scan::decode_split(block.data(), block.size(), "SCNW window 0", e, q, valid, out.data());
    ADD_FAILURE() << "decoded";
  } catch (const Error& err) {
    EXPECT_EQ(err.code(), ErrorCode::kCorrupt) << err.what();
  }
}

TEST(ScanSplit, CorruptCorrectionsAreRefused) {
  // A budget of 2 bits (q = 3 2^21 at E = 0) given the correction 4: over its budget.
  ASSERT_EQ(scan::split_budget(3 << 20, 0), 2);
  expect_corrupt(0, {3 << 20, 5, 5}, {4, 0, 0});
  // q = 2^20 at E = 20 is 1.0: 1 + 2^-24 lies in the cell but is no float32.
  ASSERT_EQ(scan::split_budget(1 << 20, 20), 4);
  expect_corrupt(20, {1 << 20, 1, 1}, {9, 0, 0});
  // q = 0 with a value outside half a step (1.0 at s = 2^-10) or NaN.
  expect_corrupt(10, {0, 1, 1}, {bits_of(1.0f), 0, 0});
  expect_corrupt(10, {0, 1, 1}, {0x7fc00000u, 0, 0});
  // An integer of 2^30.
  expect_corrupt(0, {1 << 30, 1, 1}, {0, 0, 0});
}

TEST(ScanSplit, DamagedBlocksAreRefused) {
  const std::vector<uint8_t> valid = {1, 1};
  const std::vector<int32_t> q = {10240, -300, 7, 0, 20000, -1};
  const std::vector<uint32_t> t = {513, 17, 99, bits_of(-0.0f), 3, (1u << 23) + 12345};
  std::vector<uint8_t> block = scan::encode_split(10, q, t, valid);
  std::vector<double> out(6);
  scan::decode_split(block.data(), block.size(), "w", 10, q, valid, out.data());
  EXPECT_TRUE(std::signbit(out[3]) && out[3] == 0.0);
  EXPECT_EQ(out[0], 10.0 + std::ldexp(1.0, -20));
  std::vector<uint8_t> longer = block;
  longer.push_back(0);
  EXPECT_THROW(scan::decode_split(longer.data(), longer.size(), "w", 10, q, valid, out.data()),
               Error);
  for (size_t cut = 0; cut < block.size(); ++cut)
    EXPECT_THROW(scan::decode_split(block.data(), cut, "w", 10, q, valid, out.data()), Error)
        << cut;
  EXPECT_THROW(scan::decode_split(block.data(), block.size(), "w", 65, q, valid, out.data()),
               Error);
}

}  // namespace
}  // namespace capz
