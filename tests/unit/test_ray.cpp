// POSW predictor 10, "ray" (docs/FORMAT.md 8.3): the rule, the coder with it, the decoder's
// refusal where a stream may not hold it, and the encoder's choice of format 7.0.
#include <gtest/gtest.h>

#include <algorithm>
#include <cmath>
#include <random>
#include <vector>

#include "../support/positions_round_trip.h"
#include "capz/codec.h"
#include "capz/error.h"
#include "coding/positions.h"
#include "coding/predict.h"
#include "coding/quantiser.h"
#include "relabel.h"

namespace capz {
namespace {

TEST(RayRule, GivenProportionalIntegersThenOtherAxesScaleWithTheLead) {
  const int32_t c[3] = {100, -50, 10};
  EXPECT_EQ(ray_lead(RayKind::kLinear, c), 0);
  // The lead went 100 -> 200: the other two double.
  EXPECT_EQ(ray_predict(RayKind::kLinear, c[1], c[0], 200), -100);
  EXPECT_EQ(ray_predict(RayKind::kLinear, c[2], c[0], 200), 20);
  // Halves round away from zero: 7 * 150 / 100 = 10.5 -> 11, -10.5 -> -11.
  EXPECT_EQ(ray_predict(RayKind::kLinear, 7, 100, 150), 11);
  EXPECT_EQ(ray_predict(RayKind::kLinear, -7, 100, 150), -11);
  // An undefined ratio, or one leaving int32, keeps the previous value.
  EXPECT_EQ(ray_predict(RayKind::kLinear, 5, 0, 9), 5);
  EXPECT_EQ(ray_predict(RayKind::kLinear, 2000000000, 1, 2), 2000000000);
}

TEST(RayRule, GivenTiesOrUnusableValuesThenTheLeadIsTheLowestLargestUsableAxis) {
  const int32_t tie[3] = {-40, 40, 7};
  EXPECT_EQ(ray_lead(RayKind::kLinear, tie), 0);
  const int32_t z[3] = {1, -2, -3};
  EXPECT_EQ(ray_lead(RayKind::kLinear, z), 2);
  const int32_t f[3] = {float_to_ordered(std::nanf("")), float_to_ordered(-2.5f),
                        float_to_ordered(1.0f)};
  EXPECT_EQ(ray_lead(RayKind::kFloat32, f), 1);  // NaN counts as 0
  const int32_t inf[3] = {float_to_ordered(INFINITY), float_to_ordered(0.5f), 0};
  EXPECT_EQ(ray_lead(RayKind::kFloat32, inf), 1);
}

TEST(RayRule, GivenFloat32PointsOnOneRayThenThePredictionIsTheRoundedRatio) {
  const float ya = 1.25f, xl1 = 3.0f, xl = 4.5f;
  const int32_t p = ray_predict(RayKind::kFloat32, float_to_ordered(ya), float_to_ordered(xl1),
                                float_to_ordered(xl));
  EXPECT_EQ(ordered_to_float(p), 1.875f);
  // Negative values order below zero; the rule works on the values, not on the integers.
  const int32_t n = ray_predict(RayKind::kFloat32, float_to_ordered(-1.25f), float_to_ordered(3.0f),
                                float_to_ordered(4.5f));
  EXPECT_EQ(ordered_to_float(n), -1.875f);
  // A zero or non-finite lead, or an overflowing ratio, keeps the previous value.
  const int32_t ca = float_to_ordered(2.0f);
  EXPECT_EQ(ray_predict(RayKind::kFloat32, ca, float_to_ordered(0.0f), float_to_ordered(1.0f)), ca);
  EXPECT_EQ(ray_predict(RayKind::kFloat32, ca, float_to_ordered(1.0f), float_to_ordered(NAN)), ca);
  EXPECT_EQ(ray_predict(RayKind::kFloat32, float_to_ordered(3e38f), float_to_ordered(1e-30f),
                        float_to_ordered(1.0f)),
            float_to_ordered(3e38f));
}

TEST(RayRule, GivenAVersionAndModeThenTheKindOfTheRule) {
  EXPECT_EQ(ray_kind(6, PosMode::kFloat32), RayKind::kNone);
  EXPECT_EQ(ray_kind(7, PosMode::kFloat64), RayKind::kNone);
  EXPECT_EQ(ray_kind(7, PosMode::kFloat32), RayKind::kFloat32);
  EXPECT_EQ(ray_kind(7, PosMode::kGrid), RayKind::kLinear);
  EXPECT_EQ(ray_kind(7, PosMode::kDecimal), RayKind::kLinear);
  EXPECT_EQ(ray_kind(7, PosMode::kFloat32Grid), RayKind::kLinear);
}

// A LiDAR-like window: each point a fixed direction times a range with noise, some points
// missing in some frames; as float32 ordered integers or on a grid of step `step`.
WindowInts ray_window(size_t frames, size_t points, bool float32, double step, unsigned seed) {
  std::mt19937 rng(seed);
  std::normal_distribution<double> noise(0, 0.01);
  std::uniform_real_distribution<double> u(-1, 1), r0(2, 30);
  WindowInts w;
  w.frames = frames;
  w.points = points;
  w.q.assign(frames * points * 3, 0);
  w.valid.assign(frames * points, 1);
  std::vector<double> dir(points * 3), range(points);
  for (size_t p = 0; p < points; ++p) {
    double n = 0;
    for (int a = 0; a < 3; ++a) n += (dir[p * 3 + a] = u(rng)) * dir[p * 3 + a];
    for (int a = 0; a < 3; ++a) dir[p * 3 + a] /= std::sqrt(n);
    range[p] = r0(rng);
  }
  for (size_t f = 0; f < frames; ++f)
    for (size_t p = 0; p < points; ++p) {
      if ((p * 7 + f * 3) % 23 == 0) {
        w.valid[f * points + p] = 0;
        continue;
      }
      const double r = range[p] + noise(rng);
      for (int a = 0; a < 3; ++a) {
        const double x = dir[p * 3 + a] * r;
        w.q[(f * points + p) * 3 + a] = float32 ? float_to_ordered(static_cast<float>(x))
                                                : static_cast<int32_t>(std::lround(x / step));
      }
    }
  return w;
}

// Encodes with predictor 10 allowed as `ray`, decodes, expects every valid integer back; returns
// the payload's size and the points' predictors.
size_t ray_round_trip(const WindowInts& w, RayKind ray, std::vector<uint8_t>* modes) {
  const std::vector<uint8_t> pos = encode_positions(w, {}, {}, false, kPositionScheme, ray);
  const PositionsPayload pp = split_positions(pos.data(), pos.size(), "test");
  WindowInts back;
  back.frames = w.frames;
  back.points = w.points;
  back.valid = w.valid;
  decode_positions(pp, {}, false, kPositionScheme, &back, "test", ray);
  size_t diff = 0;
  for (size_t i = 0; i < w.frames * w.points; ++i)
    if (w.valid[i])
      for (size_t k = i * 3; k < i * 3 + 3; ++k) diff += back.q[k] != w.q[k];
  EXPECT_EQ(diff, 0u);
  *modes = decode_modes(pp, w.points, kPositionScheme, "test", ray);
  return pos.size();
}

TEST(RayCoder, GivenPointsOnRaysThenPredictor10IsChosenAndTheWindowIsSmallerAndExact) {
  for (const bool float32 : {true, false}) {
    SCOPED_TRACE(float32 ? "float32 bits" : "grid 1e-4");
    const WindowInts w = ray_window(40, 300, float32, 1e-4, 11);
    std::vector<uint8_t> modes, plain;
    const size_t with = ray_round_trip(w, float32 ? RayKind::kFloat32 : RayKind::kLinear, &modes);
    const size_t without = ray_round_trip(w, RayKind::kNone, &plain);
    size_t rays = 0;
    for (uint8_t m : modes) rays += m == kPredRay;
    EXPECT_GT(rays, 250u);
    EXPECT_LT(static_cast<double>(with), 0.8 * static_cast<double>(without));
    for (uint8_t m : plain) EXPECT_NE(m, kPredRay);
  }
}

TEST(RayCoder, GivenPointsOffRaysThenStillExactWithTheRuleAllowed) {
  // Random walks: the ray rule may win a few points or none; every integer still comes back.
  std::mt19937 rng(5);
  std::uniform_int_distribution<int32_t> step(-40, 40);
  WindowInts w;
  w.frames = 30;
  w.points = 64;
  w.q.assign(w.frames * w.points * 3, 0);
  w.valid.assign(w.frames * w.points, 1);
  for (size_t f = 0; f < w.frames; ++f)
    for (size_t k = 0; k < w.points * 3; ++k)
      w.q[f * w.points * 3 + k] =
          (f ? w.q[(f - 1) * w.points * 3 + k] : static_cast<int32_t>(k * 1000)) + step(rng);
  w.valid[5 * w.points + 3] = 0;
  std::vector<uint8_t> modes;
  ray_round_trip(w, RayKind::kLinear, &modes);
  ray_round_trip(w, RayKind::kFloat32, &modes);
}

TEST(RayCoder, GivenPredictor10WhereTheStreamMayNotHoldItThenCorrupt) {
  const WindowInts w = ray_window(20, 50, true, 0, 3);
  const std::vector<uint8_t> pos =
      encode_positions(w, {}, {}, false, kPositionScheme, RayKind::kFloat32);
  const PositionsPayload pp = split_positions(pos.data(), pos.size(), "POSW");
  std::vector<uint8_t> modes =
      decode_modes(pp, w.points, kPositionScheme, "POSW", RayKind::kFloat32);
  ASSERT_NE(std::find(modes.begin(), modes.end(), kPredRay), modes.end());
  WindowInts back;
  back.frames = w.frames;
  back.points = w.points;
  back.valid = w.valid;
  // A stream of major 6 or lower (kNone), or mode 3 (float64 bits, whatever the major).
  for (const bool float64 : {false, true}) {
    try {
      decode_positions(pp, {}, float64, kPositionScheme, &back, "POSW",
                       float64 ? RayKind::kFloat32 : RayKind::kNone);
      ADD_FAILURE() << "predictor 10 accepted";
    } catch (const Error& e) {
      EXPECT_EQ(e.code(), ErrorCode::kCorrupt);
      EXPECT_NE(std::string(e.what()).find("unknown predictor 10"), std::string::npos) << e.what();
    }
  }
}

// A PCD take of `frames` x `points`, each point on a fixed ray with a noisy range (on_rays), or
// the same points moved by a common offset (off the rays from the origin).
Take scan_take(bool on_rays) {
  const WindowInts w = ray_window(12, 200, true, 0, 9);
  Take t;
  t.format = Format::kPCDFolder;
  t.resize(w.frames, w.points);
  for (size_t i = 0; i < w.frames * w.points; ++i) {
    t.valid[i] = w.valid[i];
    for (int a = 0; a < 3; ++a)
      t.xyz[i * 3 + a] = w.valid[i]
                             ? static_cast<double>(static_cast<float>(
                                   ordered_to_float(w.q[i * 3 + a]) + (on_rays ? 0.0f : 5.0f + a)))
                             : 0.0;
  }
  return t;
}

TEST(RayScan, GivenAPcdTakeOnRaysThenFormat7AndExactElseFormat5) {
  for (const bool rays : {true, false}) {
    SCOPED_TRACE(rays ? "on rays" : "off rays");
    const Take t = scan_take(rays);
    CompressOptions o;
    o.lossless = true;
    const std::vector<uint8_t> b = compress(t, o);
    ASSERT_GT(b.size(), 10u);
    EXPECT_EQ(b[9], rays ? 7 : 5);  // the major version byte after the 9-byte magic
    const Take back = decompress(b.data(), b.size());
    EXPECT_EQ(back.xyz, t.xyz);
    EXPECT_EQ(back.valid, t.valid);
  }
}

TEST(RayScan, GivenATransformCodecOnRaysThenBothPredictionsDecodeWithinTheBound) {
  for (const char* codec : {"pdct", "ts"}) {
    SCOPED_TRACE(codec);
    const Take t = scan_take(true);
    CompressOptions o;
    o.codec = codec;
    o.max_error = 0.01;
    const std::vector<uint8_t> b = compress(t, o);
    ASSERT_GT(b.size(), 10u);
    EXPECT_EQ(b[9], 7);
    const Take back = decompress(b.data(), b.size());
    ASSERT_EQ(back.valid, t.valid);
    double worst = 0;
    for (size_t i = 0; i < t.xyz.size(); ++i)
      worst = std::max(worst, std::fabs(back.xyz[i] - t.xyz[i]));
    EXPECT_LE(worst, 0.01);
  }
}

TEST(RayScan, GivenAC3DTakeThenNeverScannedForRays) {
  Take t = scan_take(true);
  t.format = Format::kC3D;
  CompressOptions o;
  o.lossless = true;
  const std::vector<uint8_t> b = compress(t, o);
  ASSERT_GT(b.size(), 10u);
  EXPECT_EQ(b[9], 5);
}

TEST(RayScan, GivenA7StreamRelabelledAs6ThenCorruptNotMisread) {
  const std::vector<uint8_t> b = capz_test::golden_bytes("lidar_small.lossless.v7.0.capz");
  ASSERT_EQ(b[9], 7);
  EXPECT_NO_THROW(decompress(b.data(), b.size()));
  // major 6, with a header CRC that matches it: predictor 10 is then unknown
  capz_test::expect_corrupt_naming(capz_test::relabelled(b, 6, 0), {"POSW"});
}

}  // namespace
}  // namespace capz
