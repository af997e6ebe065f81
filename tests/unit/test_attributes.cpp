// The ATTR coder (coding/attributes.h, FORMAT.md 13): every field type and size, COUNT above 1,
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
  return capz_test::field_spec(name, type, size, count);
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
                                             size_t* bytes = nullptr,
                                             const uint8_t* valid = nullptr) {
  const std::vector<uint8_t> enc =
      capz::encode_attributes(specs, data, valid, frames, points, width);
  if (bytes) *bytes = enc.size();
  std::vector<std::vector<uint8_t>> back;
  capz::decode_attributes(enc.data(), enc.size(), specs, valid, frames, points, width, &back,
                          "test");
  return back;
}

void put_f32(std::vector<uint8_t>* b, size_t i, float v) {
  std::memcpy(b->data() + i * 4, &v, 4);
}

// Noisy unit normals of an organized W-wide surface over F frames (signs of z mixed, as normals
// of a noisy depth image have), with NaN normals at a few valid points and at the gaps, and
// corner cases (+-0, infinities, a NaN payload, |(x, y)| > 1) in the first frame.
std::vector<std::vector<uint8_t>> noisy_normals(size_t F, size_t N, const uint8_t* valid) {
  std::vector<std::vector<uint8_t>> d(3, std::vector<uint8_t>(F * N * 4));
  std::mt19937 rng(11);
  std::normal_distribution<double> g(0, 0.4);
  const float nan = std::nanf("");
  for (size_t i = 0; i < F * N; ++i) {
    double v[3] = {g(rng), g(rng), -1 + g(rng)};
    const double n = std::sqrt(v[0] * v[0] + v[1] * v[1] + v[2] * v[2]);
    for (int k = 0; k < 3; ++k) put_f32(&d[k], i, static_cast<float>(v[k] / n));
    if ((valid && !valid[i]) || i % 17 == 5)
      for (int k = 0; k < 3; ++k) put_f32(&d[k], i, nan);
  }
  const float odd[][3] = {{0.0f, -0.0f, -1.0f}, {-0.0f, 0.0f, 0.0f},     {INFINITY, 0.5f, 0.25f},
                          {0.9f, 0.9f, -0.0f},  {1.0f, 0.0f, -0.0f},     {0.6f, -INFINITY, nan},
                          {0.6f, 0.8f, 1e-30f}, {-1e-40f, 2e-45f, -1.0f}};
  for (size_t j = 0; j < 8 && j < F * N; ++j)
    for (int k = 0; k < 3; ++k) put_f32(&d[k], j, odd[j][k]);
  uint32_t payload = 0x7FC0BEEFu;  // a NaN with a payload in z only
  if (F * N > 9) std::memcpy(d[2].data() + 9 * 4, &payload, 4);
  return d;
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
  // Field 0: counts that walk by -1, 0 or +1 a frame from random starts (the temporal predictor
  // takes them to about 1.5 bits a value, which LZMA cannot); field 1: random colours.
  const size_t F = 16, N = 50;
  std::vector<AttrSpec> specs = {spec("count", 'U', 4), spec("rgb", 'U', 4)};
  std::vector<std::vector<uint8_t>> data = {std::vector<uint8_t>(F * N * 4),
                                            random_bytes(specs[1], F * N, 1)};
  std::mt19937 rng(4);
  std::vector<uint32_t> v(N);
  for (auto& x : v) x = static_cast<uint32_t>(rng());
  for (size_t f = 0; f < F; ++f)
    for (size_t p = 0; p < N; ++p) {
      v[p] += static_cast<uint32_t>(static_cast<int>(rng() % 3) - 1);
      std::memcpy(&data[0][(f * N + p) * 4], &v[p], 4);
    }
  const std::vector<uint8_t> enc = capz::encode_attributes(specs, data, nullptr, F, N, N);
  std::vector<std::vector<uint8_t>> back;
  auto decode = [&](const std::vector<uint8_t>& e, size_t frames) {
    return capz_test::error_of([&] {
      capz::decode_attributes(e.data(), e.size(), specs, nullptr, frames, N, N, &back, "test");
    });
  };
  // A bad transform, a bad predictor (the first field, smooth, is coded predictively).
  ASSERT_EQ(enc[0], 0);
  std::vector<uint8_t> e = enc;
  e[0] = 3;
  EXPECT_EQ(decode(e, F), ErrorCode::kCorrupt);
  e = enc;
  e[1] = 9;  // predictor of its one lane
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
  // An LZMA field whose stream is damaged or claims more than it can hold.
  std::vector<AttrSpec> one = {spec("label", 'U', 2)};
  std::vector<uint8_t> flat(F * N * 2, 7);
  const std::vector<uint8_t> z = capz::encode_attributes(one, {flat}, nullptr, F, N, N);
  ASSERT_EQ(z[0], 2);
  auto decode_one = [&](const std::vector<uint8_t>& b, size_t frames) {
    return capz_test::error_of([&] {
      capz::decode_attributes(b.data(), b.size(), one, nullptr, frames, N, N, &back, "test");
    });
  };
  EXPECT_EQ(decode_one(z, F + 1), ErrorCode::kCorrupt);  // decodes to too few bytes
  e = z;
  e[e.size() / 2] ^= 0x55;
  EXPECT_EQ(decode_one(e, F), ErrorCode::kCorrupt);
  EXPECT_EQ(decode_one(z, size_t{1} << 40), ErrorCode::kCorrupt);
}

TEST(AttrCoder, GapMaskAwarePredictorsAndLzmaRoundTrip) {
  // A depth-camera-like window: an organized 40 x 30 image whose background (a gap in x y z) is
  // NaN in every field; the foreground smooth. Predictors 5..8 (gap-aware) or LZMA must do far
  // better than without the mask, and everything comes back bit for bit.
  const size_t F = 6, W = 40, N = 40 * 30;
  std::vector<uint8_t> valid(F * N);
  for (size_t f = 0; f < F; ++f)
    for (size_t p = 0; p < N; ++p) {
      const double dx = static_cast<double>(p % W) - 20.0 - static_cast<double>(f);
      const double dy = static_cast<double>(p / W) - 15.0;
      valid[f * N + p] = dx * dx + dy * dy < 80;
    }
  std::vector<AttrSpec> specs = {spec("intensity", 'F', 4), spec("label", 'U', 2)};
  std::vector<std::vector<uint8_t>> data = {smooth_bytes(specs[0], F, N),
                                            smooth_bytes(specs[1], F, N)};
  const float nan = std::nanf("");
  for (size_t i = 0; i < F * N; ++i)
    if (!valid[i]) {
      std::memcpy(&data[0][i * 4], &nan, 4);
      data[1][i * 2] = data[1][i * 2 + 1] = 0;
    }
  size_t masked = 0, unmasked = 0;
  EXPECT_EQ(round_trip(specs, data, F, N, W, &masked, valid.data()), data);
  EXPECT_EQ(round_trip(specs, data, F, N, W, &unmasked), data);
  EXPECT_LT(masked, unmasked);
  // Random bytes and a random mask: still exact.
  std::mt19937 rng(9);
  for (auto& v : valid) v = rng() % 3 != 0;
  std::vector<std::vector<uint8_t>> noise = {random_bytes(specs[0], F * N, 5),
                                             random_bytes(specs[1], F * N, 6)};
  EXPECT_EQ(round_trip(specs, noise, F, N, W, nullptr, valid.data()), noise);
  // Exact repeats at moving places (a textured surface seen by a camera): LZMA's case.
  std::vector<AttrSpec> colour = {spec("rgb", 'U', 4)};
  std::vector<uint8_t> tex(F * N * 4);
  for (size_t f = 0; f < F; ++f)
    for (size_t p = 0; p < N; ++p) {
      const uint32_t c = static_cast<uint32_t>(((p + 3 * f) / 2 * 2654435761u) >> 8);
      std::memcpy(&tex[(f * N + p) * 4], &c, 4);
    }
  size_t bytes = 0;
  EXPECT_EQ(round_trip(colour, {tex}, F, N, W, &bytes), std::vector<std::vector<uint8_t>>{tex});
  EXPECT_LT(bytes, F * N * 4 / 4) << bytes;
}

// The same fields under names no unit vector completes (predictor 9 is then no candidate).
std::vector<AttrSpec> renamed(std::vector<AttrSpec> specs) {
  for (AttrSpec& s : specs) s.name = "f_" + s.name;
  return specs;
}

TEST(AttrCoder, UnitCompletionOfNormalZIsExactAndSmaller) {
  // FORMAT.md 6.1: normal_z predicted from normal_x and normal_y (predictor 9); the triple comes
  // back bit for bit (NaN payloads, -0.0, infinities, |(x, y)| > 1), and z costs far less than
  // under names predictor 9 does not complete.
  const size_t F = 6, W = 40, N = 40 * 30;
  std::vector<uint8_t> valid(F * N);
  for (size_t i = 0; i < valid.size(); ++i) valid[i] = (i / 13) % 4 != 0;
  const std::vector<AttrSpec> specs = {spec("normal_x", 'F', 4), spec("intensity", 'F', 4),
                                       spec("normal_y", 'F', 4), spec("normal_z", 'F', 4)};
  ASSERT_TRUE(capz::has_unit_candidate(specs));
  ASSERT_FALSE(capz::has_unit_candidate({specs[0], specs[1], specs[3]}));
  ASSERT_FALSE(capz::has_unit_candidate({spec("normal_x", 'F', 8), specs[2], specs[3]}));
  const std::vector<std::vector<uint8_t>> n = noisy_normals(F, N, valid.data());
  const std::vector<std::vector<uint8_t>> data = {n[0], smooth_bytes(specs[1], F, N), n[1], n[2]};
  size_t v5 = 0, v6 = 0, xy = 0;
  EXPECT_EQ(round_trip(renamed(specs), data, F, N, W, &v5, valid.data()), data);
  EXPECT_EQ(round_trip(specs, data, F, N, W, &v6, valid.data()), data);
  round_trip({specs[0], specs[1], specs[2]}, {data[0], data[1], data[2]}, F, N, W, &xy,
             valid.data());
  // z alone cost about as much as x (noise); completed, a few bits a value.
  EXPECT_LT(v6 - xy, (v5 - xy) / 3) << v5 << " " << v6 << " " << xy;
  EXPECT_LT(v6 - xy, F * N / 2);
  // Without the mask too.
  EXPECT_EQ(round_trip(specs, data, F, N, W, nullptr, nullptr), data);
}

TEST(AttrCoder, UnitCompletionOfACountThreeNormalField) {
  const size_t F = 4, N = 300;
  const std::vector<AttrSpec> specs = {spec("normals", 'F', 4, 3), spec("curvature", 'F', 4)};
  ASSERT_TRUE(capz::has_unit_candidate(specs));
  ASSERT_FALSE(capz::has_unit_candidate({spec("descriptor", 'F', 4, 3)}));
  const std::vector<std::vector<uint8_t>> n = noisy_normals(F, N, nullptr);
  std::vector<uint8_t> packed(F * N * 12);
  for (size_t i = 0; i < F * N; ++i)
    for (size_t k = 0; k < 3; ++k) std::memcpy(&packed[(i * 3 + k) * 4], &n[k][i * 4], 4);
  const std::vector<std::vector<uint8_t>> data = {packed, smooth_bytes(specs[1], F, N)};
  size_t v5 = 0, v6 = 0;
  EXPECT_EQ(round_trip(renamed(specs), data, F, N, N, &v5, nullptr), data);
  EXPECT_EQ(round_trip(specs, data, F, N, N, &v6, nullptr), data);
  EXPECT_LT(v6 + F * N, v5) << v5 << " " << v6;
}

TEST(AttrCoder, DamagedUnitReferencesAreCorrupt) {
  // normal_z (attribute 2) coded with predictor 9: its lane's predictor byte is followed by the
  // references (0, 0) and (1, 0). Each reference that names something predictor 9 cannot use
  // is refused, naming the field.
  const size_t F = 3, N = 200;
  const std::vector<AttrSpec> specs = {spec("normal_x", 'F', 4), spec("normal_y", 'F', 4),
                                       spec("normal_z", 'F', 4), spec("label", 'U', 2)};
  const std::vector<std::vector<uint8_t>> n = noisy_normals(F, N, nullptr);
  const std::vector<std::vector<uint8_t>> data = {n[0], n[1], n[2], smooth_bytes(specs[3], F, N)};
  const std::vector<uint8_t> enc = capz::encode_attributes(specs, data, nullptr, F, N, N);
  // Find attribute 2's header: walk attributes 0 and 1 (transform, [predictor], size, data).
  size_t at = 0;
  for (int a = 0; a < 2; ++a) {
    const uint8_t t = enc[at++];
    if (t < 2) ++at;  // one lane
    uint64_t m = 0;
    for (int sh = 0;; sh += 7) {
      m |= static_cast<uint64_t>(enc[at] & 0x7F) << sh;
      if (!(enc[at++] & 0x80)) break;
    }
    at += static_cast<size_t>(m);
  }
  ASSERT_EQ(enc[at], 0);      // plain
  ASSERT_EQ(enc[at + 1], 9);  // predictor 9
  ASSERT_EQ(enc[at + 2], 0);
  ASSERT_EQ(enc[at + 3], 0);
  ASSERT_EQ(enc[at + 4], 1);
  ASSERT_EQ(enc[at + 5], 0);
  std::vector<std::vector<uint8_t>> back;
  auto decode = [&](const std::vector<uint8_t>& e) {
    return capz_test::error_of([&] {
      capz::decode_attributes(e.data(), e.size(), specs, nullptr, F, N, N, &back, "test");
    });
  };
  ASSERT_NO_THROW(
      capz::decode_attributes(enc.data(), enc.size(), specs, nullptr, F, N, N, &back, "test"));
  EXPECT_EQ(back, data);
  const std::pair<size_t, uint8_t> bad[] = {
      {at + 2, 3},  // a later attribute
      {at + 2, 2},  // itself (count 1: no earlier element)
      {at + 3, 1},  // element 1 of a count-1 field
      {at + 4, 0},  // the same element twice
      {at + 2, 9},  // past the last attribute
  };
  for (const auto& b : bad) {
    std::vector<uint8_t> e = enc;
    e[b.first] = b.second;
    EXPECT_EQ(decode(e), ErrorCode::kCorrupt) << b.first << " " << int(b.second);
  }
  // Predictor 9 on a field that is not float32.
  std::vector<AttrSpec> other = specs;
  other[2] = spec("normal_z", 'I', 4);
  std::string msg;
  EXPECT_EQ(capz_test::error_of(
                [&] {
                  capz::decode_attributes(enc.data(), enc.size(), other, nullptr, F, N, N, &back,
                                          "test");
                },
                &msg),
            ErrorCode::kCorrupt);
  EXPECT_NE(msg.find("predictor 9"), std::string::npos) << msg;
}

namespace {

// A camera-like window's mask: F frames of W x (N / W) pixels, a disc of radius^2 r2 centred at
// (cx + step f, cy) valid, the rest gaps.
std::vector<uint8_t> moving_disc(size_t F, size_t W, size_t N, double cx, double cy, double step,
                                 double r2) {
  std::vector<uint8_t> valid(F * N);
  for (size_t f = 0; f < F; ++f)
    for (size_t p = 0; p < N; ++p) {
      const double dx = static_cast<double>(p % W) - cx - step * static_cast<double>(f);
      const double dy = static_cast<double>(p / W) - cy;
      valid[f * N + p] = dx * dx + dy * dy < r2;
    }
  return valid;
}

}  // namespace

TEST(AttrCoder, ValidAndGapValuesApart) {
  // FORMAT.md 6.2: a camera-like window (a moving disc of texture colours and labels on a NaN /
  // zero background): LZMA of the valid points' values apart from the gap points' (transforms 4
  // and 5) is chosen, and everything comes back bit for bit.
  const size_t F = 6, W = 40, N = 40 * 30;
  std::vector<uint8_t> valid = moving_disc(F, W, N, 18.0, 15.0, 1.5, 90);
  const std::vector<AttrSpec> specs = {spec("rgb", 'F', 4), spec("label", 'U', 2)};
  std::vector<std::vector<uint8_t>> data = {std::vector<uint8_t>(F * N * 4),
                                            std::vector<uint8_t>(F * N * 2)};
  const uint32_t nan = 0x7FC00000u;
  for (size_t f = 0; f < F; ++f)
    for (size_t p = 0; p < N; ++p) {
      const size_t i = f * N + p;
      const uint32_t c =
          valid[i] ? 0xFF000000u | (static_cast<uint32_t>(((p + f) / 3) * 2654435761u) >> 8) : nan;
      std::memcpy(&data[0][i * 4], &c, 4);
      const uint16_t l = valid[i] ? static_cast<uint16_t>(1 + (p % W + f) / 4) : 0;
      std::memcpy(&data[1][i * 2], &l, 2);
    }
  EXPECT_EQ(round_trip(specs, data, F, N, W, nullptr, valid.data()), data);
  const std::vector<uint8_t> enc = capz::encode_attributes(specs, data, valid.data(), F, N, W);
  ASSERT_TRUE(enc[0] == 4 || enc[0] == 5) << int(enc[0]);
  // Random values at random valid points, with gap values that are not all the same: exact.
  std::mt19937 rng(21);
  for (auto& v : valid) v = rng() % 4 != 0;
  std::vector<std::vector<uint8_t>> noise = {random_bytes(specs[0], F * N, 8),
                                             random_bytes(specs[1], F * N, 9)};
  EXPECT_EQ(round_trip(specs, noise, F, N, W, nullptr, valid.data()), noise);
}

// estimate_split (a trial's size: EncoderTuning::attr_estimate): in a window with gaps the LZMA
// transforms are estimated on a sample before one is coded in full. On a camera-like window
// large enough to be sampled (fields of 256 KiB and more), the valid points' transform is still
// the one kept, the bytes decode to the fields, and the size is within 1 % of every transform's
// full trial.
TEST(AttrCoder, EstimatedSplitTransformsKeepTheValidPointsTransform) {
  const size_t F = 4, W = 160, N = 160 * 120;
  const std::vector<uint8_t> valid = moving_disc(F, W, N, 70.0, 60.0, 3.0, 2500);
  const std::vector<AttrSpec> specs = {spec("rgb", 'F', 4)};
  std::vector<std::vector<uint8_t>> data = {std::vector<uint8_t>(F * N * 4)};
  for (size_t i = 0; i < F * N; ++i) {
    const size_t p = i % N, f = i / N;
    const uint32_t c = valid[i]
                           ? 0xFF000000u | (static_cast<uint32_t>(((p + f) / 3) * 2654435761u) >> 8)
                           : 0x7FC00000u;
    std::memcpy(&data[0][i * 4], &c, 4);
  }
  ASSERT_GE(data[0].size(), size_t{1} << 18);
  const std::vector<uint8_t> full = capz::encode_attributes(specs, data, valid.data(), F, N, W);
  const std::vector<uint8_t> est =
      capz::encode_attributes(specs, data, valid.data(), F, N, W, nullptr, false, nullptr, true);
  ASSERT_TRUE(full[0] == 4 || full[0] == 5) << int(full[0]);
  EXPECT_EQ(est[0], full[0]);
  EXPECT_LE(static_cast<double>(est.size()), 1.01 * static_cast<double>(full.size()));
  std::vector<std::vector<uint8_t>> back;
  capz::decode_attributes(est.data(), est.size(), specs, valid.data(), F, N, W, &back, "test");
  EXPECT_EQ(back, data);
}

TEST(AttrCoder, DamagedValidGapSplitIsCorrupt) {
  const size_t F = 4, W = 20, N = 20 * 10;
  std::vector<uint8_t> valid(F * N);
  for (size_t i = 0; i < valid.size(); ++i) {
    const size_t col = i % W, f = i / N;
    valid[i] = col > 3 + f && col < 12 + f;
  }
  const std::vector<AttrSpec> one = {spec("rgb", 'U', 4)};
  std::vector<uint8_t> b(F * N * 4, 0);
  for (size_t i = 0; i < F * N; ++i)
    if (valid[i]) {
      const size_t p = i % N, f = i / N;
      const uint32_t c = static_cast<uint32_t>(((p - f) / 2) * 2654435761u) >> 8;
      std::memcpy(&b[i * 4], &c, 4);
    }
  const std::vector<uint8_t> enc = capz::encode_attributes(one, {b}, valid.data(), F, N, W);
  ASSERT_TRUE(enc[0] == 4 || enc[0] == 5) << int(enc[0]);
  std::vector<std::vector<uint8_t>> back;
  auto decode = [&](const std::vector<uint8_t>& e, const uint8_t* mask) {
    return capz_test::error_of(
        [&] { capz::decode_attributes(e.data(), e.size(), one, mask, F, N, W, &back, "t"); });
  };
  ASSERT_NO_THROW(
      capz::decode_attributes(enc.data(), enc.size(), one, valid.data(), F, N, W, &back, "t"));
  EXPECT_EQ(back, std::vector<std::vector<uint8_t>>{b});
  EXPECT_EQ(decode(enc, nullptr), ErrorCode::kCorrupt);  // no gap mask
  // Another mask (more valid points): the parts decode to other lengths.
  std::vector<uint8_t> other(valid.size(), 1);
  other[0] = 0;
  EXPECT_EQ(decode(enc, other.data()), ErrorCode::kCorrupt);
  // valid_size (the varint after the size varint) past the end, 0, or one short: rewritten in
  // the same number of bytes, so only the split is wrong.
  size_t at = 1;
  while (enc[at] & 0x80) ++at;
  ++at;
  ASSERT_EQ(enc[at] & 0x80, 0x80);  // two bytes here
  ASSERT_EQ(enc[at + 1] & 0x80, 0);
  const unsigned vs = (enc[at] & 0x7Fu) | (static_cast<unsigned>(enc[at + 1]) << 7);
  for (unsigned v : {16383u, 0u, vs - 1, vs + 1}) {
    std::vector<uint8_t> e = enc;
    e[at] = static_cast<uint8_t>(0x80 | (v & 0x7F));
    e[at + 1] = static_cast<uint8_t>(v >> 7);
    EXPECT_EQ(decode(e, valid.data()), ErrorCode::kCorrupt) << v;
  }
  std::vector<uint8_t> e = enc;
  // A transform above 5.
  e[0] = 6;
  EXPECT_EQ(decode(e, valid.data()), ErrorCode::kCorrupt);
}
