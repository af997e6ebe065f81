// The lossless rotation-window coder (src/coding/rotations.h, docs/FORMAT.md 12):
// exact round trips of every float32 bit pattern that matters, and corrupt input refused with
// Error(kCorrupt), never a crash.
#include <gtest/gtest.h>

#include <cmath>
#include <cstring>
#include <random>

#include "capz/error.h"
#include "coding/quantiser.h"
#include "coding/rotations.h"

using namespace capz;

namespace {

struct Window {
  size_t samples = 0, segments = 0;
  std::vector<float> matrices, reliability;
};

// Segments turning about z and moving smoothly, bottom row 0 0 0 1, reliability mostly 1.
Window smooth(size_t samples, size_t segments, uint32_t seed) {
  Window w;
  w.samples = samples;
  w.segments = segments;
  std::mt19937 rng(seed);
  std::normal_distribution<float> noise(0, 1e-4f);
  for (size_t s = 0; s < samples; ++s)
    for (size_t g = 0; g < segments; ++g) {
      const float a = 0.01f * float(s) + 0.7f * float(g);
      const float m[16] = {std::cos(a),
                           std::sin(a),
                           0,
                           0,
                           -std::sin(a),
                           std::cos(a),
                           0,
                           0,
                           0,
                           0,
                           1,
                           0,
                           100 + float(s) + noise(rng),
                           200 - 0.5f * float(s),
                           900,
                           1};
      w.matrices.insert(w.matrices.end(), m, m + 16);
      w.reliability.push_back(s % 50 == 7 ? 0.5f : 1.0f);
    }
  return w;
}

std::vector<uint8_t> encode(const Window& w) {
  return encode_rotations(w.matrices.data(), w.reliability.data(), w.samples, w.segments);
}

void expect_round_trip(const Window& w) {
  const std::vector<uint8_t> bytes = encode(w);
  const RotationWindow back = decode_rotations(bytes.data(), bytes.size(), w.samples, w.segments);
  ASSERT_EQ(back.matrices.size(), w.matrices.size());
  ASSERT_EQ(back.reliability.size(), w.reliability.size());
  for (size_t i = 0; i < w.matrices.size(); ++i)
    ASSERT_EQ(float_bits(back.matrices[i]), float_bits(w.matrices[i])) << "matrix value " << i;
  for (size_t i = 0; i < w.reliability.size(); ++i)
    ASSERT_EQ(float_bits(back.reliability[i]), float_bits(w.reliability[i])) << "reliability " << i;
}

// Every special float32 worth a test, in turn.
const uint32_t kSpecial[] = {
    0x00000000u, 0x80000000u,                                         // +0, -0
    0x00000001u, 0x80000001u, 0x007fffffu, 0x807fffffu, 0x00400000u,  // denormals
    0x00800000u, 0x7f7fffffu, 0xff7fffffu,                            // smallest normal, +-max
    0x7f800000u, 0xff800000u,                                         // +-inf
    0x7fc00000u, 0xffc00000u, 0x7fc00123u, 0x7f800001u, 0xff800abcu, 0x7fffffffu,  // NaNs
    0x3f800000u, 0xbf800000u,
};

}  // namespace

TEST(RotationCoder, ElementClasses) {
  EXPECT_EQ(rotation_class(0), RotationClass::kRotation);
  EXPECT_EQ(rotation_class(10), RotationClass::kRotation);
  for (int k : {12, 13, 14}) EXPECT_EQ(rotation_class(k), RotationClass::kTranslation) << k;
  for (int k : {3, 7, 11, 15}) EXPECT_EQ(rotation_class(k), RotationClass::kBottomRow) << k;
  EXPECT_EQ(rotation_class(16), RotationClass::kReliability);
}

TEST(RotationCoder, SmoothWindowRoundTripsExactlyAndCompresses) {
  const Window w = smooth(300, 4, 1);
  expect_round_trip(w);
  const size_t raw = (w.matrices.size() + w.reliability.size()) * 4;
  EXPECT_LT(encode(w).size(), raw / 2) << "raw " << raw;
}

TEST(RotationCoder, SpecialValuesInEveryPositionOfTheSeries) {
  // Each special value preceded and followed by each other one, in every element class, so
  // the linear predictor meets infinities, NaNs, overflow (max, -max) and denormals.
  Window w;
  w.segments = 1;
  for (uint32_t a : kSpecial)
    for (uint32_t b : kSpecial) {
      for (int k = 0; k < 16; ++k) w.matrices.push_back(bits_float(k % 2 ? a : b));
      w.reliability.push_back(bits_float(a));
      ++w.samples;
    }
  expect_round_trip(w);
}

TEST(RotationCoder, RandomBitPatternsRoundTrip) {
  std::mt19937 rng(5);
  Window w;
  w.samples = 97;
  w.segments = 3;
  for (size_t i = 0; i < w.samples * w.segments * 16; ++i) w.matrices.push_back(bits_float(rng()));
  for (size_t i = 0; i < w.samples * w.segments; ++i) w.reliability.push_back(bits_float(rng()));
  expect_round_trip(w);
}

TEST(RotationCoder, AlternatingExtremesOverflowTheLinearPrediction) {
  Window w;
  w.segments = 1;
  for (size_t s = 0; s < 40; ++s) {
    const float v = s % 3 == 0 ? 3.0e38f : (s % 3 == 1 ? -3.0e38f : 1e-40f);
    for (int k = 0; k < 16; ++k) w.matrices.push_back(k % 2 ? v : -v);
    w.reliability.push_back(v);
    ++w.samples;
  }
  expect_round_trip(w);
}

TEST(RotationCoder, EmptyWindows) {
  expect_round_trip(Window{});
  Window w;
  w.samples = 5;  // samples without segments
  expect_round_trip(w);
}

TEST(RotationCoder, CorruptInputThrowsCorruptNeverCrashes) {
  const Window w = smooth(60, 2, 3);
  const std::vector<uint8_t> good = encode(w);
  size_t thrown = 0;
  auto attempt = [&](const std::vector<uint8_t>& b, size_t samples, size_t segments) {
    try {
      decode_rotations(b.data(), b.size(), samples, segments, "test");
    } catch (const Error& e) {
      ASSERT_EQ(e.code(), ErrorCode::kCorrupt) << e.what();
      ++thrown;
    }
  };
  for (size_t n = 0; n < good.size(); ++n)  // every truncation
    attempt(std::vector<uint8_t>(good.begin(), good.begin() + static_cast<long>(n)), 60, 2);
  EXPECT_EQ(thrown, good.size());
  for (size_t i = 0; i < good.size(); ++i)  // every byte flipped
    for (uint8_t x : {0x01, 0x80, 0xff}) {
      std::vector<uint8_t> b = good;
      b[i] ^= x;
      attempt(b, 60, 2);
    }
  std::vector<uint8_t> extra = good;
  extra.push_back(0);
  thrown = 0;
  attempt(extra, 60, 2);
  EXPECT_EQ(thrown, 1u) << "a byte past the end";
  std::vector<uint8_t> bad_pred = good;
  bad_pred[2] = 3;
  thrown = 0;
  attempt(bad_pred, 60, 2);
  EXPECT_EQ(thrown, 1u) << "predictor 3";
  // Counts the block cannot hold, refused before allocating (and without overflow).
  thrown = 0;
  attempt(good, size_t{1} << 40, 2);
  attempt(good, 60, SIZE_MAX / 4);
  attempt(good, SIZE_MAX, SIZE_MAX);
  EXPECT_EQ(thrown, 3u);
}
