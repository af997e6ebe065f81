// Shared files whose POINT:UNITS capz once could not read compress at the default bound
// (0.1 mm) through the library, and every coordinate comes back within it.
#include <gtest/gtest.h>

#include <cmath>
#include <filesystem>
#include <string>

#include "capz/codec.h"
#include "capz/io.h"

using namespace capz;

namespace {

const std::string kRoot = std::string(CAPZ_SHARED_DATA) + "/c3d";

void compress_at_default_bound(const std::string& rel, const std::string& units, double metres) {
  const std::string path = kRoot + "/" + rel;
  if (!std::filesystem::exists(path)) GTEST_SKIP() << path << " not found (shared data absent)";
  const Take t = read_c3d(path);
  EXPECT_EQ(t.units, units);
  EXPECT_DOUBLE_EQ(units_to_metres(t.units), metres);
  CompressOptions opts;
  opts.max_error = parse_length("0.1mm", t.units);  // what `capz compress` does by default
  EXPECT_DOUBLE_EQ(opts.max_error, 0.0001 / metres);
  const std::vector<uint8_t> bytes = compress(t, opts);
  const Take back = decompress(bytes.data(), bytes.size(), rel);
  ASSERT_EQ(back.frames, t.frames);
  ASSERT_EQ(back.points, t.points);
  EXPECT_EQ(back.valid, t.valid);
  EXPECT_EQ(back.units, t.units);
  double worst = 0;
  for (size_t i = 0; i < t.frames * t.points; ++i)
    if (t.valid[i])
      for (int a = 0; a < 3; ++a)
        worst = std::max(worst, std::fabs(back.xyz[3 * i + a] - t.xyz[3 * i + a]));
  EXPECT_LE(worst, opts.max_error);
}

}  // namespace

// c3d.org sample 15: POINT:UNITS is "mete" (metres cut to 4 characters).
TEST(UnitsConformance, FP1CompressesAtTheDefaultBound) {
  compress_at_default_bound("c3dorg/sample_15/FP1.C3D", "mete", 1.0);
}
TEST(UnitsConformance, FP2CompressesAtTheDefaultBound) {
  compress_at_default_bound("c3dorg/sample_15/FP2.C3D", "mete", 1.0);
}
