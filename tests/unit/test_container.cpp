// The container end to end on synthetic takes: bounds, lossless modes, gaps, analog, C3D words,
// frame ranges, CRC, quantiser rounding, unit parsing.
#include <gtest/gtest.h>

#include <cmath>
#include <cstring>
#include <limits>
#include <random>
#include <utility>
#include <vector>

#include "capz/codec.h"
#include "capz/error.h"
#include "capz/metrics.h"
#include "codec/encoder.h"
#include "coding/c3d_words.h"
#include "coding/container.h"
#include "coding/crc32c.h"
#include "coding/entropy.h"
#include "coding/mask.h"
#include "coding/quantiser.h"

namespace capz {
namespace {

// Smooth random trajectories (mm), with optional gaps.
Take synthetic(size_t frames, size_t points, double gap_rate, unsigned seed) {
  Take t;
  t.source = "synthetic";
  t.format = Format::kTRC;
  t.resize(frames, points);
  t.rate = 100;
  t.units = "mm";
  std::mt19937 rng(seed);
  std::normal_distribution<double> n(0, 1);
  for (size_t p = 0; p < points; ++p) {
    t.labels.push_back("M" + std::to_string(p));
    double x[3] = {n(rng) * 300, n(rng) * 300, 800 + n(rng) * 300};
    double v[3] = {0, 0, 0};
    bool gap = false;
    for (size_t f = 0; f < frames; ++f) {
      for (int a = 0; a < 3; ++a) {
        v[a] = 0.98 * v[a] + n(rng) * 0.3;
        x[a] += v[a];
        t.at(f, p)[a] = x[a];
      }
      if (gap_rate > 0 && std::uniform_real_distribution<double>(0, 1)(rng) < gap_rate) gap = !gap;
      t.valid[f * points + p] = gap ? 0 : 1;
      if (gap) std::fill_n(t.at(f, p), 3, 0.0);
    }
  }
  return t;
}

void expect_same_mask(const Take& a, const Take& b) {
  ASSERT_EQ(a.valid.size(), b.valid.size());
  for (size_t i = 0; i < a.valid.size(); ++i) ASSERT_EQ(a.valid[i] != 0, b.valid[i] != 0) << i;
}

TEST(Crc32c, GivenCheckStringThenKnownValue) {
  const char* s = "123456789";
  EXPECT_EQ(crc32c(reinterpret_cast<const uint8_t*>(s), 9), 0xE3069283u);
  std::vector<uint8_t> big(1000);
  for (size_t i = 0; i < big.size(); ++i) big[i] = static_cast<uint8_t>(i * 7);
  EXPECT_EQ(crc32c_update(crc32c(big.data(), 333), big.data() + 333, 667),
            crc32c(big.data(), 1000));
}

TEST(Quantiser, GivenHalfwayValuesThenRoundsAwayFromZero) {
  EXPECT_EQ(round_to_int(2.5), 3);
  EXPECT_EQ(round_to_int(-2.5), -3);
  EXPECT_EQ(round_to_int(2.4999), 2);
  EXPECT_EQ(round_to_int(-0.5), -1);
  EXPECT_EQ(round_to_int(0.0), 0);
  // The bound holds on the grid for values right at the half-step.
  const double e = 0.1, s = grid_step_for_bound(e);
  for (double x : {0.05, 0.1, 0.15, 1234.5678, -987.65, 0.1 * 12345 + 0.1}) {
    double back = round_to_int(x / s) * s;
    EXPECT_LE(std::fabs(back - x), e) << x;
  }
}

TEST(Quantiser, GivenFloatsThenOrderedMappingIsMonotoneAndExact) {
  std::vector<float> v = {-1e30f, -2.5f, -1e-30f, -0.0f, 0.0f, 1e-30f, 1.0f, 3e38f};
  for (size_t i = 0; i + 1 < v.size(); ++i)
    EXPECT_LE(float_to_ordered(v[i]), float_to_ordered(v[i + 1]));
  for (float f : v) {
    float b = ordered_to_float(float_to_ordered(f));
    EXPECT_EQ(std::memcmp(&b, &f, 4), 0);
  }
}

TEST(Units, GivenTypedLengthsThenConvertedToTakeUnits) {
  EXPECT_DOUBLE_EQ(parse_length("0.1mm", "m"), 0.0001);
  EXPECT_DOUBLE_EQ(parse_length("0.1", "m"), 0.1);
  EXPECT_DOUBLE_EQ(parse_length("2 cm", "mm"), 20);
  EXPECT_DOUBLE_EQ(parse_length("1mm", "", "m"), 0.001);
  EXPECT_THROW(parse_length("1mm", ""), Error);
  EXPECT_THROW(parse_length("abc", "mm"), Error);
  EXPECT_THROW(parse_length("-1mm", "mm"), Error);
  EXPECT_THROW(parse_length("1 furlong", "mm"), Error);
}

TEST(MaskCoding, GivenRandomMasksThenRoundTripExactly) {
  std::mt19937 rng(9);
  for (int trial = 0; trial < 20; ++trial) {
    size_t F = 1 + rng() % 300, N = 1 + rng() % 20;
    std::vector<uint8_t> v(F * N);
    for (auto& b : v) b = (rng() % 5) != 0;
    auto block = encode_mask(v.data(), F, N);
    std::vector<uint8_t> back(F * N, 7);
    decode_mask(block.data(), block.size(), F, N, back.data(), "mask");
    EXPECT_EQ(back, v);
  }
}

// C3D 4th words of a float file: residual = byte x scale for valid samples, -1 for gaps. With a
// scale that does not divide 1 (Capture0004's 0.0581 mm) the gaps' -1 is off the grid; mode 2
// must still apply (gaps decode to -1) and round-trip every word exactly.
TEST(C3dWordCoding, GivenGapsAndScaleNotDividingOneThenGridModeAndExact) {
  const double scale = 0.05810098350048065;
  const size_t frames = 50, points = 6, n = frames * points;
  std::mt19937 rng(7);
  std::vector<float> residual(n);
  std::vector<uint8_t> camera(n), valid(n);
  for (size_t i = 0; i < n; ++i) {
    valid[i] = rng() % 5 != 0;
    residual[i] = valid[i] ? static_cast<float>((rng() % 12) * scale) : -1.0f;
    camera[i] = valid[i] ? static_cast<uint8_t>(rng() % 4) : 0;
  }
  ASSERT_NE(static_cast<float>(std::round(-1.0 / scale) * scale), -1.0f);  // -1 is off the grid
  ASSERT_TRUE(residuals_on_grid(residual, valid, scale));
  std::vector<uint8_t> c =
      encode_c3d_words(residual.data(), camera.data(), valid.data(), n, points, scale, true);
  EXPECT_EQ(c[0], 2);  // on the grid
  std::vector<float> r(n);
  std::vector<uint8_t> cam(n);
  decode_c3d_words(c.data(), c.size(), valid.data(), n, points, scale, r.data(), cam.data(), "t");
  EXPECT_EQ(std::memcmp(r.data(), residual.data(), n * 4), 0);
  EXPECT_EQ(cam, camera);
  std::vector<uint8_t> bits =
      encode_c3d_words(residual.data(), camera.data(), valid.data(), n, points, scale, false);
  EXPECT_LT(c.size(), bits.size());
  EXPECT_EQ(bits[0], 3);  // the float bits
  // A gap whose residual is not -1 cannot use mode 2.
  for (size_t i = 0; i < n; ++i)
    if (!valid[i]) {
      residual[i] = 0.0f;
      break;
    }
  EXPECT_FALSE(residuals_on_grid(residual, valid, scale));
}

// Words that repeat for runs of frames (as most takes write them), with gaps: both residual
// modes (2 on the grid, 3 the float bits, each with a frame repeat flag) decode every word
// exactly; modes 0 and 1 (pre-release formats without the flags) and 4 are corrupt, and so is a
// flag above 1.
TEST(C3dWordCoding, GivenRepeatedFramesWhenCodedInEveryModeThenExactAndOtherModesCorrupt) {
  const double scale = 0.25;
  const size_t frames = 300, points = 9, n = frames * points;
  std::mt19937 rng(11);
  std::vector<float> residual(n);
  std::vector<uint8_t> camera(n), valid(n);
  float r = 0.5f;
  uint8_t cam = 3;
  for (size_t f = 0; f < frames; ++f) {
    if (f % 40 == 17) r = static_cast<float>((rng() % 8) * scale), cam = rng() % 16;
    for (size_t p = 0; p < points; ++p) {
      const size_t i = f * points + p;
      valid[i] = !(p == 4 && f >= 100 && f < 130);  // a gap of 30 frames
      residual[i] = valid[i] ? r : -1.0f;
      camera[i] = valid[i] ? cam : 0;
    }
  }
  ASSERT_TRUE(residuals_on_grid(residual, valid, scale));
  std::vector<float> back(n);
  std::vector<uint8_t> cb(n);
  for (int mode = 2; mode < 4; ++mode) {
    std::vector<uint8_t> c =
        encode_c3d_words(residual.data(), camera.data(), valid.data(), n, points, scale, mode == 2);
    ASSERT_EQ(c[0], mode);
    decode_c3d_words(c.data(), c.size(), valid.data(), n, points, scale, back.data(), cb.data(),
                     "t");
    EXPECT_EQ(std::memcmp(back.data(), residual.data(), n * 4), 0) << "mode " << mode;
    EXPECT_EQ(cb, camera) << "mode " << mode;
    for (const uint8_t other : {0, 1, 4}) {
      c[0] = other;
      EXPECT_THROW(decode_c3d_words(c.data(), c.size(), valid.data(), n, points, scale, back.data(),
                                    cb.data(), "t"),
                   Error)
          << "mode " << int{other};
    }
  }
  // A frame flag of 2 is corrupt (flag context 3 seeded with a 2).
  IntEncoder bad(4);
  bad.put(2, 3);
  std::vector<uint8_t> b = bad.finish();
  b.insert(b.begin(), 2);
  EXPECT_THROW(decode_c3d_words(b.data(), b.size(), valid.data(), points, points, scale,
                                back.data(), cb.data(), "t"),
               Error);
}

TEST(Container, GivenBoundWhenRoundTrippedThenEveryCoordinateWithinBoundAndMaskExact) {
  Take t = synthetic(700, 12, 0.01, 1);
  for (double bound : {0.1, 1.0}) {
    CompressOptions o;
    o.max_error = bound;
    o.window_frames = 256;
    CompressStats st;
    auto bytes = compress(t, o, &st);
    Take b = decompress(bytes.data(), bytes.size(), "mem");
    ASSERT_EQ(b.frames, t.frames);
    expect_same_mask(t, b);
    ErrorStats e = compare(t, b);
    EXPECT_LE(e.max_abs, bound);
    EXPECT_GT(e.max_abs, bound * 0.5);
    EXPECT_NEAR(e.kg_error, st.error.kg_error, 1e-9);
    EXPECT_EQ(st.bytes, bytes.size());
    EXPECT_EQ(b.labels, t.labels);
    EXPECT_EQ(b.units, "mm");
    EXPECT_EQ(b.rate, 100);
    for (size_t i = 0; i < b.valid.size(); ++i)
      if (!b.valid[i]) {
        EXPECT_EQ(b.xyz[i * 3], 0.0);
      }
  }
}

// The default window (window_frames = 0): 1024 frames, more for takes of few points with codec
// none (about 2^16 samples a window, at most 8192 frames), 1024 with a transform codec; an
// explicit size is kept.
TEST(Container, GivenDefaultWindowThenSizedByPointCount) {
  EXPECT_EQ(auto_window_frames(2), 8192u);
  EXPECT_EQ(auto_window_frames(40), 2048u);
  EXPECT_EQ(auto_window_frames(64), 1024u);
  EXPECT_EQ(auto_window_frames(8000), 1024u);
  Take t = synthetic(3000, 3, 0.01, 8);
  auto window_of = [&](const std::string& codec, size_t w) {
    CompressOptions o;
    o.max_error = 0.5;
    o.codec = codec;
    o.window_frames = w;
    auto bytes = compress(t, o);
    Take b = decompress(bytes.data(), bytes.size(), "mem");
    EXPECT_LE(compare(t, b).max_abs, 0.5);
    return describe(bytes.data(), bytes.size(), "mem").window_frames;
  };
  EXPECT_EQ(window_of("none", 0), 8192u);  // 3 points: one window of the whole take
  EXPECT_EQ(window_of("", 0), 8192u);
  EXPECT_EQ(window_of("none", 500), 500u);
  EXPECT_EQ(window_of("ts", 0), 1024u);
}

// The progress callback runs from inside the decode, after decompress() set it up: what it
// reports must outlive that set-up (a stack-use-after-scope under ASan when it did not).
TEST(Container, GivenProgressThenEachWindowReportsTheFramesDoneOfThoseAsked) {
  Take t = synthetic(1000, 4, 0, 9);
  CompressOptions o;
  o.max_error = 0.5;
  o.codec = "none";
  o.window_frames = 300;
  const auto bytes = compress(t, o);
  std::vector<std::pair<size_t, size_t>> calls;
  DecompressOptions d;
  d.progress = [&](size_t done, size_t of) { calls.emplace_back(done, of); };
  decompress(bytes.data(), bytes.size(), "mem", d);
  const std::vector<std::pair<size_t, size_t>> whole = {
      {300, 1000}, {600, 1000}, {900, 1000}, {1000, 1000}};
  EXPECT_EQ(calls, whole);
  calls.clear();
  const Take part = decompress_frames(bytes.data(), bytes.size(), 250, 500, "mem", d);
  EXPECT_EQ(part.frames, 500u);
  const std::vector<std::pair<size_t, size_t>> range = {{50, 500}, {350, 500}, {500, 500}};
  EXPECT_EQ(calls, range);
}

TEST(Container, GivenKgTargetThenAchievedAtOrJustUnder) {
  Take t = synthetic(400, 10, 0, 2);
  CompressOptions o;
  o.kg_error = 0.05;
  CompressStats st;
  auto bytes = compress(t, o, &st);
  Take b = decompress(bytes.data(), bytes.size());
  ErrorStats e = compare(t, b);
  EXPECT_LE(e.kg_error, 0.05);
  EXPECT_GT(e.kg_error, 0.04);
}

// The KG search finds the same grid whether it keeps the coordinates in memory or reads the
// source once per step (EncoderTuning::kg_cache_bytes 0, or a cache too small for the take),
// windows of 64 frames so the streamed sum crosses blocks; gaps included.
TEST(Container, GivenKgTargetWhenSearchCachedOrStreamedThenSameStream) {
  Take t = synthetic(500, 9, 0.05, 4);
  CompressOptions o;
  o.kg_error = 0.03;
  o.window_frames = 64;
  const std::vector<uint8_t> cached = compress(t, o);
  for (size_t cache : {size_t{0}, size_t{24}, size_t{1000} * 8}) {  // 0, 1 triple, 1000 values
    EncoderTuning tuning;
    tuning.kg_cache_bytes = cache;
    EXPECT_EQ(compress_tuned(t, o, tuning), cached) << "cache of " << cache << " bytes";
  }
}

// Frame numbers are coded with wrapping int64 sums (FORMAT.md 5.4): extreme values from the API
// round-trip exactly, listed and regular (a run that wraps past the largest int64), and under
// UBSan no sum overflows (fuzz corpus crash-frame-number-delta-overflow.capz: a crafted delta).
TEST(Container, GivenExtremeFrameNumbersThenTheyRoundTripWithoutOverflow) {
  constexpr int64_t kMax = std::numeric_limits<int64_t>::max();
  constexpr int64_t kMin = std::numeric_limits<int64_t>::min();
  const std::vector<std::vector<int64_t>> cases = {
      {kMax, kMin, 0, kMax, -1, kMin},                        // listed
      {kMax - 2, kMax - 1, kMax, kMin, kMin + 1, kMin + 2}};  // regular, wrapping
  for (const auto& numbers : cases) {
    Take t = synthetic(6, 3, 0, 5);
    t.trc = std::make_shared<TRCExtra>();
    t.trc->frame_numbers = numbers;
    CompressOptions o;
    o.lossless = true;
    auto bytes = compress(t, o);
    Take b = decompress(bytes.data(), bytes.size());
    ASSERT_TRUE(b.trc);
    EXPECT_EQ(b.trc->frame_numbers, numbers);
  }
}

TEST(Container, GivenDecimalDataWhenLosslessThenBitExact) {
  Take t = synthetic(300, 5, 0.02, 3);
  for (double& x : t.xyz) x = std::round(x * 1000) / 1000;  // as a TRC with 3 decimals reads
  CompressOptions o;
  o.lossless = true;
  CompressStats st;
  auto bytes = compress(t, o, &st);
  EXPECT_EQ(st.mode, "decimal-grid");
  Take b = decompress(bytes.data(), bytes.size());
  expect_same_mask(t, b);
  for (size_t i = 0; i < t.valid.size(); ++i)
    if (t.valid[i]) {
      ASSERT_EQ(std::memcmp(&t.xyz[i * 3], &b.xyz[i * 3], 24), 0);
    }
}

TEST(Container, GivenFloat32AndFloat64DataWhenLosslessThenBitExact) {
  Take t = synthetic(300, 5, 0.02, 4);
  for (double& x : t.xyz) x = static_cast<float>(x * 1.0000001);
  for (int pass = 0; pass < 2; ++pass) {
    CompressOptions o;
    o.lossless = true;
    CompressStats st;
    auto bytes = compress(t, o, &st);
    EXPECT_EQ(st.mode, pass == 0 ? "float32-bits" : "float64-bits");
    Take b = decompress(bytes.data(), bytes.size());
    for (size_t i = 0; i < t.valid.size(); ++i)
      if (t.valid[i]) {
        ASSERT_EQ(std::memcmp(&t.xyz[i * 3], &b.xyz[i * 3], 24), 0);
      }
    for (double& x : t.xyz) x += 1e-12;  // now not float32
  }
}

TEST(Container, GivenC3DInt16TakeThenStoredIntegersAndWordsComeBack) {
  Take t = synthetic(200, 6, 0.02, 5);
  t.format = Format::kC3D;
  t.c3d = std::make_shared<C3DExtra>();
  t.c3d->point_scale = 0.0833333;
  t.c3d->float_storage = false;
  t.c3d->residual.resize(t.frames * t.points);
  t.c3d->camera_mask.resize(t.frames * t.points);
  for (size_t i = 0; i < t.valid.size(); ++i) {
    for (int a = 0; a < 3; ++a)
      t.xyz[i * 3 + a] = std::round(t.xyz[i * 3 + a] / t.c3d->point_scale) * t.c3d->point_scale;
    t.c3d->residual[i] = t.valid[i] ? static_cast<float>((i % 5) * t.c3d->point_scale) : -1.0f;
    t.c3d->camera_mask[i] = static_cast<uint8_t>(t.valid[i] ? 0x3F : 0);
  }
  for (bool lossless : {true, false}) {
    CompressOptions o;
    o.lossless = lossless;
    o.max_error = 0.5;
    auto bytes = compress(t, o);
    Take b = decompress(bytes.data(), bytes.size());
    ASSERT_TRUE(b.c3d);
    EXPECT_EQ(b.c3d->camera_mask, t.c3d->camera_mask);
    EXPECT_EQ(std::memcmp(b.c3d->residual.data(), t.c3d->residual.data(), t.valid.size() * 4), 0);
    for (size_t i = 0; i < t.valid.size(); ++i)
      if (t.valid[i])
        for (int a = 0; a < 3; ++a) {
          double k = b.xyz[i * 3 + a] / t.c3d->point_scale;
          EXPECT_NEAR(k, std::round(k), 1e-6);  // still on the int16 grid
          if (lossless)
            ASSERT_EQ(b.xyz[i * 3 + a], t.xyz[i * 3 + a]);
          else
            ASSERT_LE(std::fabs(b.xyz[i * 3 + a] - t.xyz[i * 3 + a]), 0.5);
        }
  }
}

TEST(Container, GivenAnalogThenExactAndFrameRangeDecodesOnlyThatRange) {
  Take t = synthetic(1000, 4, 0.01, 6);
  t.analog.channels = 2;
  t.analog.samples_per_frame = 4;
  t.analog.rate = 400;
  t.analog.labels = {"A", "B"};
  t.analog.values.resize(1000 * 4 * 2);
  for (size_t i = 0; i < t.analog.values.size(); ++i)
    t.analog.values[i] = std::round(100 * std::sin(i * 0.01)) + (i % 2 ? 0.5 : 0);
  CompressOptions o;
  o.max_error = 0.1;
  o.window_frames = 128;
  auto bytes = compress(t, o);
  Take all = decompress(bytes.data(), bytes.size());
  EXPECT_EQ(
      std::memcmp(all.analog.values.data(), t.analog.values.data(), t.analog.values.size() * 8), 0);
  EXPECT_EQ(all.analog.labels, t.analog.labels);
  Take part = decompress_frames(bytes.data(), bytes.size(), 300, 250);
  ASSERT_EQ(part.frames, 250u);
  EXPECT_EQ(part.first_frame, t.first_frame + 300);
  for (size_t i = 0; i < 250 * 4 * 3; ++i) ASSERT_EQ(part.xyz[i], all.xyz[300 * 4 * 3 + i]);
  for (size_t i = 0; i < 250 * 4; ++i) ASSERT_EQ(part.valid[i], all.valid[300 * 4 + i]);
  for (size_t i = 0; i < 250 * 8; ++i)
    ASSERT_EQ(part.analog.values[i], all.analog.values[300 * 8 + i]);
  // A range needs only its windows: damage a window outside it and the range still decodes.
  auto damaged = bytes;
  StreamInfo si = describe(bytes.data(), bytes.size());
  EXPECT_EQ(si.windows, 8u);
  damaged[bytes.size() * 3 / 4] ^= 0x40;  // somewhere in a later window (INDX is small)
  EXPECT_THROW(decompress(damaged.data(), damaged.size()), Error);
  Take early = decompress_frames(damaged.data(), damaged.size(), 0, 100);
  EXPECT_EQ(early.frames, 100u);
}

TEST(Container, GivenEmptyAndAllGapTakesThenRoundTrip) {
  Take t = synthetic(50, 3, 0, 7);
  std::fill(t.valid.begin(), t.valid.end(), 0);
  std::fill(t.xyz.begin(), t.xyz.end(), 0.0);
  CompressOptions o;
  o.max_error = 0.1;
  auto bytes = compress(t, o);
  Take b = decompress(bytes.data(), bytes.size());
  EXPECT_EQ(b.gap_samples(), 150u);
  Take e;
  e.units = "m";
  auto eb = compress(e, o);
  Take be = decompress(eb.data(), eb.size());
  EXPECT_EQ(be.frames, 0u);
}

TEST(Container, GivenNoTargetOrTooFineBoundThenInvalidParameter) {
  Take t = synthetic(20, 2, 0, 8);
  CompressOptions o;
  try {
    compress(t, o);
    FAIL();
  } catch (const Error& e) {
    EXPECT_EQ(e.code(), ErrorCode::kInvalidParameter);
  }
  o.max_error = 1e-300;
  EXPECT_THROW(compress(t, o), Error);
  o.max_error = 0.1;
  o.codec = "no-such-codec";
  EXPECT_THROW(compress(t, o), Error);
}

}  // namespace
}  // namespace capz

namespace capz {
namespace {

TEST(Container, GivenFloatC3DOnItsScaleGridWhenLosslessThenFloat32GridModeAndBitExact) {
  Take t;
  t.format = Format::kC3D;
  t.resize(100, 4);
  t.units = "mm";
  t.c3d = std::make_shared<C3DExtra>();
  t.c3d->float_storage = true;
  t.c3d->point_scale = static_cast<double>(0.0833333358f);
  for (size_t i = 0; i < t.valid.size(); ++i) {
    t.valid[i] = i % 11 != 0;
    for (int a = 0; a < 3; ++a)
      t.xyz[i * 3 + a] = t.valid[i]
                             ? static_cast<double>(static_cast<float>(
                                   static_cast<double>(static_cast<int>(i * 7 + a * 1000) - 3000) *
                                   t.c3d->point_scale))
                             : 0.0;
  }
  CompressOptions o;
  o.lossless = true;
  CompressStats st;
  auto bytes = compress(t, o, &st);
  EXPECT_EQ(st.mode, "float32-grid");
  Take b = decompress(bytes.data(), bytes.size());
  for (size_t i = 0; i < t.valid.size(); ++i)
    if (t.valid[i]) {
      ASSERT_EQ(std::memcmp(&t.xyz[i * 3], &b.xyz[i * 3], 24), 0);
    }
}

}  // namespace
}  // namespace capz
