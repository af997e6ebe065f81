// The ATTR coder (coding/attributes.h, FORMAT.md 5.3): every field type and size, COUNT above 1,
// packed colour in both spellings, NaN payloads and -0.0, organized layouts; the predictors
// actually help on smooth data; damaged payloads are refused.
#include <gtest/gtest.h>

#include <cmath>
#include <cstring>
#include <random>
#include <string>
#include <vector>

#include "capz/error.h"
#include "coding/attributes.h"
#include "test_util.h"

using capz::AttrSpec;
using capz::ErrorCode;

namespace {

AttrSpec spec(const std::string& name, char type, int size, int count = 1) {
  AttrSpec s;
  s.name = name;
  s.type = type;
  s.size = size;
  s.count = count;
  return s;
}

// Random bytes for frames x points x count elements.
std::vector<uint8_t> random_bytes(const AttrSpec& s, size_t n, uint32_t seed) {
  std::mt19937 rng(seed);
  std::vector<uint8_t> b(n * static_cast<size_t>(s.size * s.count));
  for (auto& x : b) x = static_cast<uint8_t>(rng());
  return b;
}

// Smooth values of a field over frames x points (slowly changing in time and along the row).
std::vector<uint8_t> smooth_bytes(const AttrSpec& s, size_t frames, size_t points) {
  std::vector<uint8_t> b(frames * points * static_cast<size_t>(s.size * s.count));
  size_t o = 0;
  for (size_t f = 0; f < frames; ++f)
    for (size_t p = 0; p < points; ++p)
      for (int k = 0; k < s.count; ++k) {
        const double v =
            40 + 30 * std::sin(0.05 * static_cast<double>(p) + 0.1 * static_cast<double>(f) + k);
        uint64_t bits = 0;
        if (s.type == 'F' && s.size == 4) {
          const float x = static_cast<float>(v);
          uint32_t u;
          std::memcpy(&u, &x, 4);
          bits = u;
        } else if (s.type == 'F') {
          std::memcpy(&bits, &v, 8);
        } else {
          bits = static_cast<uint64_t>(static_cast<int64_t>(std::lround(v)));
        }
        for (int i = 0; i < s.size; ++i) b[o++] = static_cast<uint8_t>(bits >> (8 * i));
      }
  return b;
}

std::vector<std::vector<uint8_t>> round_trip(const std::vector<AttrSpec>& specs,
                                             const std::vector<std::vector<uint8_t>>& data,
                                             size_t frames, size_t points, size_t width,
                                             size_t* bytes = nullptr) {
  const std::vector<uint8_t> enc = capz::encode_attributes(specs, data, frames, points, width);
  if (bytes) *bytes = enc.size();
  std::vector<std::vector<uint8_t>> back;
  capz::decode_attributes(enc.data(), enc.size(), specs, frames, points, width, &back, "test");
  return back;
}

}  // namespace

TEST(AttrCoder, EveryTypeAndSizeComesBackBitForBit) {
  const size_t F = 5, N = 37;
  std::vector<AttrSpec> specs = {spec("u1", 'U', 1), spec("i1", 'I', 1), spec("u2", 'U', 2),
                                 spec("i2", 'I', 2), spec("u4", 'U', 4), spec("i4", 'I', 4),
                                 spec("u8", 'U', 8), spec("i8", 'I', 8), spec("f4", 'F', 4),
                                 spec("f8", 'F', 8)};
  std::vector<std::vector<uint8_t>> random, smooth;
  for (size_t i = 0; i < specs.size(); ++i) {
    random.push_back(random_bytes(specs[i], F * N, static_cast<uint32_t>(i + 1)));
    smooth.push_back(smooth_bytes(specs[i], F, N));
  }
  EXPECT_EQ(round_trip(specs, random, F, N, N), random);
  EXPECT_EQ(round_trip(specs, smooth, F, N, N), smooth);
}

TEST(AttrCoder, CountAboveOneAndPaddingFields) {
  const size_t F = 3, N = 20;
  std::vector<AttrSpec> specs = {spec("fpfh", 'F', 4, 33), spec("_", 'U', 1, 3),
                                 spec("ring", 'U', 2)};
  std::vector<std::vector<uint8_t>> data = {
      smooth_bytes(specs[0], F, N), random_bytes(specs[1], F * N, 7), smooth_bytes(specs[2], F, N)};
  EXPECT_EQ(round_trip(specs, data, F, N, N), data);
}

TEST(AttrCoder, PackedColourInBothSpellingsThroughYCoCgR) {
  const size_t F = 4, N = 64;
  for (char type : {'F', 'U'}) {
    for (const char* name : {"rgb", "rgba"}) {
      std::vector<AttrSpec> specs = {spec(name, type, 4)};
      ASSERT_TRUE(capz::is_colour_field(specs[0]));
      // Every byte value in every channel position, including alpha 0 and 255 (packed floats
      // that are NaN or denormal).
      std::vector<uint8_t> b(F * N * 4);
      for (size_t i = 0; i < b.size(); ++i) b[i] = static_cast<uint8_t>((i * 37 + i / 4) & 255);
      b[3] = 0xFF;
      b[7] = 0x7F;  // with the next bytes: float NaN pattern
      EXPECT_EQ(round_trip(specs, {b}, F, N, 8), std::vector<std::vector<uint8_t>>{b})
          << name << " " << type;
    }
  }
  // Exhaustive over the transform: every (R, G, B) of a coarse lattice and its extremes.
  std::vector<uint8_t> all;
  for (int r = 0; r < 256; r += 15)
    for (int g = 0; g < 256; g += 15)
      for (int bl = 0; bl < 256; bl += 15) {
        all.push_back(static_cast<uint8_t>(bl));
        all.push_back(static_cast<uint8_t>(g));
        all.push_back(static_cast<uint8_t>(r));
        all.push_back(static_cast<uint8_t>(255 - r));
      }
  const size_t n = all.size() / 4;
  EXPECT_EQ(round_trip({spec("rgba", 'U', 4)}, {all}, 1, n, n),
            std::vector<std::vector<uint8_t>>{all});
}

TEST(AttrCoder, NaNPayloadsNegativeZeroAndInfinitiesStay) {
  const size_t F = 2, N = 6;
  const uint32_t f4[] = {0x7FC00001u, 0xFFC12345u, 0x80000000u,
                         0x7F800000u, 0xFF800000u, 0x00000001u};
  std::vector<uint8_t> b4(F * N * 4), b8(F * N * 8);
  for (size_t i = 0; i < F * N; ++i) {
    std::memcpy(&b4[i * 4], &f4[i % 6], 4);
    const uint64_t v = (static_cast<uint64_t>(f4[(i + 1) % 6]) << 32) | f4[i % 6];
    std::memcpy(&b8[i * 8], &v, 8);
  }
  std::vector<AttrSpec> specs = {spec("intensity", 'F', 4), spec("curvature", 'F', 8)};
  EXPECT_EQ(round_trip(specs, {b4, b8}, F, N, 3), (std::vector<std::vector<uint8_t>>{b4, b8}));
}

TEST(AttrCoder, SmoothFieldsCostFarLessThanTheirRawBytes) {
  // A smooth organized 32 x 24 intensity image over 8 frames: the spatial and temporal
  // predictors must take it well below its raw size (random bytes would not shrink).
  const size_t F = 8, W = 32, N = 32 * 24;
  std::vector<AttrSpec> specs = {spec("label", 'U', 2), spec("intensity", 'F', 4)};
  std::vector<std::vector<uint8_t>> data = {smooth_bytes(specs[0], F, N),
                                            smooth_bytes(specs[1], F, N)};
  size_t bytes = 0;
  EXPECT_EQ(round_trip(specs, data, F, N, W, &bytes), data);
  const size_t raw = F * N * 6;
  // Integer labels that change by a unit or so between neighbours: a few bits a value.
  size_t label_bytes = 0;
  round_trip({specs[0]}, {data[0]}, F, N, W, &label_bytes);
  EXPECT_LT(label_bytes, F * N * 2 / 4) << label_bytes;
  // Float32 values carry ~23 bits of mantissa that no predictor sees through; the sign,
  // exponent and top mantissa bits are predicted away.
  EXPECT_LT(bytes - label_bytes, F * N * 4 * 3 / 4) << bytes;
  // Random values do not shrink, and still come back.
  std::vector<std::vector<uint8_t>> noise = {random_bytes(specs[0], F * N, 3),
                                             random_bytes(specs[1], F * N, 4)};
  EXPECT_EQ(round_trip(specs, noise, F, N, W, &bytes), noise);
  EXPECT_GT(bytes, raw * 9 / 10);
}

TEST(AttrCoder, NoFramesOrNoPoints) {
  std::vector<AttrSpec> specs = {spec("rgb", 'F', 4), spec("i", 'I', 2)};
  EXPECT_EQ(round_trip(specs, {{}, {}}, 0, 10, 10), (std::vector<std::vector<uint8_t>>{{}, {}}));
  EXPECT_EQ(round_trip(specs, {{}, {}}, 3, 0, 0), (std::vector<std::vector<uint8_t>>{{}, {}}));
}

TEST(AttrCoder, DamagedPayloadsAreCorrupt) {
  const size_t F = 4, N = 50;
  std::vector<AttrSpec> specs = {spec("rgb", 'U', 4), spec("intensity", 'F', 4)};
  std::vector<std::vector<uint8_t>> data = {random_bytes(specs[0], F * N, 1),
                                            smooth_bytes(specs[1], F, N)};
  const std::vector<uint8_t> enc = capz::encode_attributes(specs, data, F, N, N);
  std::vector<std::vector<uint8_t>> back;
  auto decode = [&](const std::vector<uint8_t>& e, size_t frames) {
    return capz_test::error_of(
        [&] { capz::decode_attributes(e.data(), e.size(), specs, frames, N, N, &back, "test"); });
  };
  // A bad transform, a bad predictor.
  std::vector<uint8_t> e = enc;
  e[0] = 2;
  EXPECT_EQ(decode(e, F), ErrorCode::kCorrupt);
  e = enc;
  e[2] = 9;  // predictor of lane 0
  EXPECT_EQ(decode(e, F), ErrorCode::kCorrupt);
  // Truncated, and with a byte added.
  for (size_t cut : {size_t{1}, size_t{3}, enc.size() / 2, enc.size() - 1}) {
    e.assign(enc.begin(), enc.begin() + static_cast<long>(cut));
    EXPECT_EQ(decode(e, F), ErrorCode::kCorrupt) << cut;
  }
  e = enc;
  e.push_back(0);
  EXPECT_EQ(decode(e, F), ErrorCode::kCorrupt);
  // More values than the payload can hold: refused before anything is allocated.
  EXPECT_EQ(decode(enc, size_t{1} << 40), ErrorCode::kCorrupt);
}
