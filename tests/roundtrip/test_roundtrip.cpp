// Real files from ../shared/data through compress -> decompress (-> write -> re-read):
// the per-coordinate bound holds on every valid sample, gap masks and analog come back exactly,
// lossless is bit for bit, metadata comes back, and a frame range decodes alone.
#include <gtest/gtest.h>
#include <unistd.h>

#include <cmath>
#include <cstring>
#include <filesystem>

#include "capz/codec.h"
#include "capz/error.h"
#include "capz/io.h"
#include "capz/metrics.h"
#include "test_util.h"

namespace capz {
namespace {

namespace fs = std::filesystem;
struct Case {
  const char* path;               // under the shared real data
  size_t max_lossless_bytes = 0;  // if set: lossless POSW + MASK bytes must stay under it
};

const Case kCases[] = {
    {"c3d/c3dorg/sample_01/Eb015pr.c3d"},              // float storage
    {"c3d/c3dorg/sample_01/Eb015si.c3d"},              // int16 storage, analog
    {"c3d/btkdata/PiG/PiG_Motion-FlatFoot-Hole.c3d"},  // gaps, analog
    {"c3d/c3dorg/sample_17/128analogchannels.c3d"},    // many analog channels
    {"c3d/btkdata/others/FunctionalLHip.c3d"},         // heavy occlusion
    {"trc/opensim/dataWithNaNsWithSpaces.trc"},        // NaN gaps
    {"trc/opensim/walk_free_01.trc"},
    {"pcd/pcow"},  // PCD folder, no units
    // Frames 24-47 repeat 0-23 (format 3.0's period predictor). xz -9e makes its raw float32
    // positions 1,993,776 B; format 2.0 coded them in 2,573,710 B (docs/BENCHMARKS.md).
    {"pcd/horse-gallop", 1900000},
};

void expect_same_mask(const Take& a, const Take& b) {
  ASSERT_EQ(a.valid.size(), b.valid.size());
  size_t diff = 0;
  for (size_t i = 0; i < a.valid.size(); ++i) diff += (a.valid[i] != 0) != (b.valid[i] != 0);
  EXPECT_EQ(diff, 0u);
}

void expect_same_analog(const Take& a, const Take& b) {
  EXPECT_EQ(a.analog.channels, b.analog.channels);
  EXPECT_EQ(a.analog.samples_per_frame, b.analog.samples_per_frame);
  EXPECT_EQ(a.analog.labels, b.analog.labels);
  ASSERT_EQ(a.analog.values.size(), b.analog.values.size());
  // memcmp must not see the null data() of an empty vector
  if (!a.analog.values.empty()) {
    EXPECT_EQ(
        std::memcmp(a.analog.values.data(), b.analog.values.data(), a.analog.values.size() * 8), 0);
  }
}

// Bound in the take's units: 0.1 mm / 1 mm converted; for PCD (no units) relative to the data.
double bound_for(const Take& t, double mm) {
  if (!t.units.empty()) return parse_length(std::to_string(mm) + "mm", t.units);
  return mm * 1e-3;  // PCD: the same number in the data's own units
}

class RoundTrip : public ::testing::TestWithParam<Case> {};

TEST_P(RoundTrip, GivenRealFileWhenCompressedAtBoundsThenBoundHoldsAndEverythingElseExact) {
  const std::string path = capz_test::shared_data_or_skip(GetParam().path);
  if (path.empty()) return;
  Take t = read_take(path);
  for (double mm : {0.1, 1.0}) {
    CompressOptions o;
    o.max_error = bound_for(t, mm);
    CompressStats st;
    std::vector<uint8_t> bytes = compress(t, o, &st);
    Take b = decompress(bytes.data(), bytes.size(), path);
    ASSERT_EQ(b.frames, t.frames);
    ASSERT_EQ(b.points, t.points);
    expect_same_mask(t, b);
    ErrorStats e = compare(t, b);
    EXPECT_LE(e.max_abs, o.max_error) << path << " at " << mm << " mm";
    EXPECT_NEAR(e.max_abs, st.error.max_abs, 1e-12);
    expect_same_analog(t, b);
    EXPECT_EQ(b.labels, t.labels);
    EXPECT_EQ(b.units, t.units);
    EXPECT_EQ(b.rate, t.rate);
    EXPECT_EQ(b.first_frame, t.first_frame);
    EXPECT_EQ(b.format, t.format);
    EXPECT_LT(bytes.size(), t.frames * t.points * 12 + 100000) << "no bigger than raw float32";
  }
}

TEST_P(RoundTrip, GivenRealFileWhenLosslessThenEveryStoredCoordinateBitExact) {
  const std::string path = capz_test::shared_data_or_skip(GetParam().path);
  if (path.empty()) return;
  Take t = read_take(path);
  CompressOptions o;
  o.lossless = true;
  CompressStats st;
  std::vector<uint8_t> bytes = compress(t, o, &st);
  EXPECT_TRUE(st.lossless);
  Take b = decompress(bytes.data(), bytes.size(), path);
  expect_same_mask(t, b);
  size_t differ = 0;
  for (size_t i = 0; i < t.valid.size(); ++i)
    if (t.valid[i]) differ += std::memcmp(&t.xyz[i * 3], &b.xyz[i * 3], 24) != 0;
  EXPECT_EQ(differ, 0u) << path << " (" << st.mode << ")";
  if (GetParam().max_lossless_bytes) {
    EXPECT_LT(st.position_bytes, GetParam().max_lossless_bytes);
  }
  expect_same_analog(t, b);
  if (t.c3d) {
    ASSERT_TRUE(b.c3d);
    EXPECT_EQ(b.c3d->camera_mask, t.c3d->camera_mask);
    ASSERT_EQ(b.c3d->residual.size(), t.c3d->residual.size());
    EXPECT_EQ(
        std::memcmp(b.c3d->residual.data(), t.c3d->residual.data(), t.c3d->residual.size() * 4), 0);
    EXPECT_EQ(b.c3d->groups.size(), t.c3d->groups.size());
    EXPECT_EQ(b.c3d->header_events.size(), t.c3d->header_events.size());
  }
  if (t.trc) {
    ASSERT_TRUE(b.trc);
    EXPECT_EQ(b.trc->times, t.trc->times);
    EXPECT_EQ(b.trc->frame_numbers, t.trc->frame_numbers);
  }
  if (t.pcd) {
    ASSERT_TRUE(b.pcd);
    EXPECT_EQ(b.pcd->frame_names, t.pcd->frame_names);
  }
}

TEST_P(RoundTrip, GivenSmallWindowsWhenAFrameRangeIsDecodedThenItMatchesTheFullDecode) {
  const std::string path = capz_test::shared_data_or_skip(GetParam().path);
  if (path.empty()) return;
  Take t = read_take(path);
  ASSERT_GE(t.frames, 10u) << "every case is long enough for a range inside it";
  CompressOptions o;
  o.max_error = bound_for(t, 0.5);
  o.window_frames = 64;
  std::vector<uint8_t> bytes = compress(t, o);
  Take all = decompress(bytes.data(), bytes.size());
  const size_t first = t.frames / 3, count = t.frames / 3;
  Take part = decompress_frames(bytes.data(), bytes.size(), first, count);
  ASSERT_EQ(part.frames, count);
  const size_t N = t.points;
  for (size_t i = 0; i < count * N; ++i) {
    ASSERT_EQ(part.valid[i], all.valid[first * N + i]);
    for (int a = 0; a < 3; ++a) ASSERT_EQ(part.xyz[i * 3 + a], all.xyz[first * N * 3 + i * 3 + a]);
  }
  const size_t row = static_cast<size_t>(t.analog.channels) * t.analog.samples_per_frame;
  for (size_t i = 0; i < count * row; ++i)
    ASSERT_EQ(part.analog.values[i], all.analog.values[first * row + i]);
}

INSTANTIATE_TEST_SUITE_P(Shared, RoundTrip, ::testing::ValuesIn(kCases),
                         [](const ::testing::TestParamInfo<Case>& i) {
                           std::string s = fs::path(i.param.path).filename().string();
                           for (char& c : s)
                             if (!std::isalnum(static_cast<unsigned char>(c))) c = '_';
                           return s;
                         });

// decompress of a C3D input writes a C3D that re-reads to the same take within the bound: the
// bound holds in the written file, float32 rounding included (bigparlove has coordinates near
// 2^18 mm, where a float32 step is 0.03 mm; test1 is in metres).
TEST(RoundTripC3D, GivenC3DWhenDecompressedAndWrittenThenRereadsWithinBound) {
  for (const char* rel :
       {"c3d/c3dorg/sample_01/Eb015pr.c3d", "c3d/btkdata/PiG/PiG_Motion-FlatFoot-Hole.c3d",
        "c3d/c3dorg/sample_33/bigparlove.c3d",
        "c3d/c3dorg/sample_00/NexGen Ergonomics/test1.c3d"}) {
    const std::string path = capz_test::shared_data_or_skip(rel);
    if (path.empty()) return;
    Take t = read_take(path);
    const std::string tmp =
        fs::temp_directory_path() / ("capz_rt_" + std::to_string(getpid()) + ".c3d");
    for (const char* bound : {"lossless", "0.03mm", "0.1mm"}) {
      const bool lossless = std::string(bound) == "lossless";
      CompressOptions o;
      o.lossless = lossless;
      o.max_error = lossless ? 0 : parse_length(bound, t.units);
      std::vector<uint8_t> bytes = compress(t, o);
      Take b = decompress(bytes.data(), bytes.size());
      WriteOptions wo;
      wo.overwrite = true;
      write_c3d(b, tmp, wo);
      Take r = read_c3d(tmp);
      fs::remove(tmp);
      ASSERT_EQ(r.frames, t.frames);
      expect_same_mask(t, r);
      ErrorStats e = compare(t, r);
      EXPECT_LE(e.max_abs, o.max_error) << rel << " at " << bound;
      EXPECT_EQ(r.labels, t.labels);
      EXPECT_EQ(r.rate, t.rate);
      expect_same_analog(t, r);
    }
  }
}

}  // namespace
}  // namespace capz
