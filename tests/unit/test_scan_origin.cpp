// Origin points (docs/FORMAT.md "Ragged frames: HEAD and the window chunk", SCNW's `gaps` bit 0):
// a sweep whose no-return points are written at exactly 0 0 0 (as Ouster's ROS driver writes
// them) codes them as gaps and gives them back as +0.0 bit for bit, in about the bytes of the
// same sweep with NaN gaps; a window with both NaN and zero points keeps its zeros as points;
// a gaps byte with another bit is corrupt.
#include <gtest/gtest.h>

#include <cstdint>
#include <cstring>
#include <limits>
#include <string>
#include <vector>

#include "capz/codec.h"
#include "capz/error.h"
#include "coding/bytes.h"
#include "coding/crc32c.h"
#include "synthetic.h"

namespace capz {
namespace {

// 4 sweeps of 16 beams, a fifth of the points without a return (NaN gaps), with a U2 field.
Take nan_sweeps() {
  return capz_test::with_u2_field(capz_test::synthetic_sweeps(4, 300, 7, 5, 30, 3, 0.3, 5, 5, 2),
                                  "intensity", [](size_t i) { return i * 7 % 23; });
}

// t with its gaps made valid points at +0.0 +0.0 +0.0.
Take zero_sweeps(Take t) {
  for (size_t i = 0; i < t.valid.size(); ++i)
    if (!t.valid[i]) t.valid[i] = 1, t.xyz[3 * i] = t.xyz[3 * i + 1] = t.xyz[3 * i + 2] = 0.0;
  return t;
}

bool origin(const Take& t, size_t i) {
  static const double zero = 0.0;
  return t.valid[i] && std::memcmp(&t.xyz[3 * i], &zero, 8) == 0 &&
         std::memcmp(&t.xyz[3 * i + 1], &zero, 8) == 0 &&
         std::memcmp(&t.xyz[3 * i + 2], &zero, 8) == 0;
}

CompressOptions two_window_1mm() {
  CompressOptions o;
  o.max_error = 0.001;
  o.window_frames = 2;
  return o;
}

// d has t's gaps, its origin points at +0.0 bit for bit, every other point within 1 mm (as
// float32) and its field byte for byte.
void expect_back(const Take& t, const Take& d) {
  ASSERT_EQ(d.valid, t.valid);
  ASSERT_EQ(d.xyz.size(), t.xyz.size());
  size_t zeros = 0;
  for (size_t i = 0; i < t.valid.size(); ++i) {
    if (!t.valid[i]) continue;
    if (origin(t, i)) {
      EXPECT_TRUE(origin(d, i)) << "point " << i;
      ++zeros;
      continue;
    }
    for (size_t a = 0; a < 3; ++a)
      EXPECT_NEAR(static_cast<float>(d.xyz[3 * i + a]), t.xyz[3 * i + a], 0.001 + 1e-9);
  }
  EXPECT_GT(zeros, 0u);
  ASSERT_EQ(d.attributes.size(), 1u);
  EXPECT_EQ(d.attributes[0].data, t.attributes[0].data);
}

// Zero points come back bit for bit and cost what NaN gaps cost (the payloads code the same
// gaps); coded as points (the encoder's only way before, and still in a window that also has a
// NaN gap) they cost far more.
TEST(ScanOrigin, ZeroPointsCodeAsGapsAndComeBackExact) {
  const Take nan = nan_sweeps(), zero = zero_sweeps(nan);
  Take both = zero;  // one NaN in each window: its zeros stay points
  for (size_t f : {size_t{0}, size_t{2}}) {
    const size_t i = zero.frame_offsets[f] + 1;
    ASSERT_FALSE(origin(zero, i));
    both.valid[i] = 0;
    both.xyz[3 * i] = both.xyz[3 * i + 1] = both.xyz[3 * i + 2] =
        std::numeric_limits<double>::quiet_NaN();
  }
  for (bool fields : {false, true}) {
    CompressOptions o = two_window_1mm();
    o.drop_fields = !fields;
    const std::vector<uint8_t> zn = compress(nan, o), zz = compress(zero, o),
                               zb = compress(both, o);
    SCOPED_TRACE(std::to_string(zn.size()) + " " + std::to_string(zz.size()) + " " +
                 std::to_string(zb.size()));
    EXPECT_LE(zz.size(), zn.size() + 8);       // measured: the same size
    EXPECT_LT(zz.size() * 10, zb.size() * 8);  // measured: 35,840 against 52,521 (0.68)
    if (!fields) continue;
    expect_back(zero, decompress(zz.data(), zz.size()));
    expect_back(both, decompress(zb.data(), zb.size()));
  }
}

// Lossless (mode 2, float32 coordinates): the zero points, coded as gaps, come back bit for bit
// as every other coordinate does, in fewer bytes than the window with a NaN that keeps them.
TEST(ScanOrigin, LosslessGivesZeroPointsBackBitForBit) {
  const Take zero = zero_sweeps(nan_sweeps());
  Take both = zero;
  both.valid[1] = 0;
  both.xyz[3] = both.xyz[4] = both.xyz[5] = std::numeric_limits<double>::quiet_NaN();
  CompressOptions o;
  o.lossless = true;
  o.drop_fields = true;
  const std::vector<uint8_t> z = compress(zero, o), zb = compress(both, o);
  EXPECT_LT(z.size(), zb.size());
  const Take d = decompress(z.data(), z.size());
  ASSERT_EQ(d.valid, zero.valid);
  ASSERT_EQ(d.xyz.size(), zero.xyz.size());
  EXPECT_EQ(std::memcmp(d.xyz.data(), zero.xyz.data(), 8 * zero.xyz.size()), 0);
}

// The SCNW of window 0 with its gaps byte set to 2 (CRC recomputed): corrupt, naming SCNW.
TEST(ScanOrigin, GapsByteWithOtherBitsIsCorrupt) {
  const Take zero = zero_sweeps(nan_sweeps());
  CompressOptions o = two_window_1mm();
  o.drop_fields = true;
  std::vector<uint8_t> z = compress(zero, o);
  size_t off = 0;
  for (size_t i = 0; i + 4 <= z.size() && off == 0; ++i)
    if (std::memcmp(&z[i], "SCNW", 4) == 0) off = i;
  ASSERT_GT(off, 0u);
  const uint32_t len = load_le32(&z[off + 4]);
  size_t g = off + 8 + 1;   // after the window's varint (0)
  while (z[g] & 0x80) ++g;  // the total's varint
  ++g;
  ASSERT_EQ(z[g], 1) << "window 0 of the zero sweeps has origin points";
  for (uint8_t bad : {uint8_t{2}, uint8_t{3}, uint8_t{0x81}}) {
    z[g] = bad;
    const uint32_t crc = crc32c_update(crc32c(&z[off], 4), &z[off + 8], len);
    for (int k = 0; k < 4; ++k) z[off + 8 + len + k] = static_cast<uint8_t>(crc >> (8 * k));
    try {
      decompress(z.data(), z.size());
      FAIL() << "gaps byte " << int(bad) << " accepted";
    } catch (const Error& e) {
      EXPECT_EQ(e.code(), ErrorCode::kCorrupt) << e.what();
      EXPECT_NE(std::string(e.what()).find("SCNW"), std::string::npos) << e.what();
    }
  }
}

}  // namespace
}  // namespace capz
