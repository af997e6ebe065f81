#include <gtest/gtest.h>

#include <cmath>
#include <cstring>

#include "capz/error.h"
#include "capz/metrics.h"
#include "codec/pdct/pdct_encoder.h"
#include "synthetic.h"

using capz::PdctCodec;
using capz::TransformParams;

namespace {

void expect_bit_identical(const std::vector<double>& a, const std::vector<double>& b) {
  ASSERT_EQ(a.size(), b.size());
  EXPECT_EQ(std::memcmp(a.data(), b.data(), a.size() * sizeof(double)), 0);
}

}  // namespace

TEST(PdctCodec, GivenRigidBodiesWhenEncodedThenDecoderMatchesEncoderBitForBit) {
  const auto t = capz_test::rigid_bodies(3, 20, 40, 1, 0.05);
  PdctCodec codec;
  for (int clusters : {0, 1, 3, 10, -1}) {
    for (const char* order : {"1", "2"}) {
      TransformParams p;
      p.clusters = clusters;
      p.options["local_order"] = order;
      p.options["zero_share"] = "0.3";
      std::vector<uint8_t> bytes;
      std::vector<double> enc, dec;
      codec.encode(t.view(), p, &bytes, &enc);
      codec.decode(bytes.data(), bytes.size(), t.frames, t.points, &dec);
      expect_bit_identical(enc, dec);
    }
  }
}

TEST(PdctCodec, GivenNoTargetWhenEncodedThenPaperBitsGiveSmallError) {
  const auto t = capz_test::rigid_bodies(3, 30, 50, 2, 0.05);
  PdctCodec codec;
  TransformParams p;
  p.clusters = 3;
  std::vector<uint8_t> bytes;
  std::vector<double> rec;
  capz::PdctReport rep;
  capz::encode_pdct(t.view(), p, &bytes, &rec, &rep);
  const auto s = capz::compare(t.frames, t.points, t.xyz.data(), rec.data(), t.valid.data());
  EXPECT_EQ(rep.clusters, 3u);
  EXPECT_LT(s.kg_error, 0.5);  // 12-bit frame 0 and coefficients
  EXPECT_LT(s.max_error, 3.0);
  // The frame points sit on the 16-bit seed grid: error <= half a step per axis.
  EXPECT_GT(rep.frame_points, 0u);
}

TEST(PdctCodec, GivenMaxErrorInDctModeWhenEncodedThenStepsFollowTheBound) {
  const auto t = capz_test::rigid_bodies(2, 40, 60, 3, 0.2);
  TransformParams p;
  p.max_error = 0.5;
  p.options["mode"] = "dct";
  std::vector<uint8_t> bytes;
  std::vector<double> rec;
  capz::PdctReport rep;
  capz::encode_pdct(t.view(), p, &bytes, &rec, &rep);
  EXPECT_FALSE(rep.grid_mode);
  EXPECT_DOUBLE_EQ(rep.seed_step, 0.5);  // seed_factor 0.5 of the bound's grid 2 * 0.5
  const auto s = capz::compare(t.frames, t.points, t.xyz.data(), rec.data(), t.valid.data());
  // The DCT path alone does not guarantee the bound (the container's bound layer does), but
  // with steps at the bound's grid the RMS error stays well inside it.
  EXPECT_LT(s.rmse, 0.5);
}

TEST(PdctCodec, GivenMaxErrorWhenEncodedThenGridModeReconstructsTheBoundLayersGridExactly) {
  auto t = capz_test::rigid_bodies(3, 20, 50, 12, 0.3);
  for (size_t f = 5; f < 20; ++f) t.valid[f * t.points + 4] = 0;  // a gap (values left as they are)
  for (double grid_step : {0.0, 0.37}) {
    TransformParams p;
    p.max_error = 0.25;
    p.grid_step = grid_step;
    std::vector<uint8_t> bytes;
    std::vector<double> enc, dec;
    capz::PdctReport rep;
    capz::encode_pdct(t.view(), p, &bytes, &enc, &rep);
    EXPECT_TRUE(rep.grid_mode);
    PdctCodec().decode(bytes.data(), bytes.size(), t.frames, t.points, &dec);
    expect_bit_identical(enc, dec);
    const double g = grid_step > 0 ? grid_step : 2 * 0.25 * (1 - 0x1p-30);
    size_t checked = 0;
    for (size_t s = 0; s < t.frames * t.points; ++s) {
      if (!t.valid[s]) continue;
      for (int a = 0; a < 3; ++a) {
        // Exactly the bound layer's quantisation: round half away from zero, times the step.
        ASSERT_EQ(dec[3 * s + a], static_cast<double>(std::llround(t.xyz[3 * s + a] / g)) * g) << s;
        ++checked;
      }
    }
    EXPECT_EQ(checked, (t.frames * t.points - 15) * 3);
    size_t local = rep.predictors[1] + rep.predictors[2] + rep.predictors[3];
    EXPECT_GT(local, 0u);  // rigid bodies: local-frame predictors win for some points
  }
}

TEST(PdctCodec, GivenKgTargetWhenEncodedThenTargetMetAndCoarserIsSmaller) {
  const auto t = capz_test::rigid_bodies(3, 30, 60, 4, 0.3);
  std::vector<size_t> sizes;
  for (double kg : {0.05, 0.5}) {
    TransformParams p;
    p.kg_error = kg;
    p.clusters = 3;
    std::vector<uint8_t> bytes;
    std::vector<double> rec;
    PdctCodec().encode(t.view(), p, &bytes, &rec);
    const auto s = capz::compare(t.frames, t.points, t.xyz.data(), rec.data(), t.valid.data());
    EXPECT_LE(s.kg_error, kg);
    EXPECT_GT(s.kg_error, kg / 4);  // the search does not overshoot grossly
    sizes.push_back(bytes.size());
  }
  EXPECT_LT(sizes[1], sizes[0]);
}

TEST(PdctCodec, GivenGapsWhenEncodedThenValidSamplesCodedAndDecoderMatches) {
  auto t = capz_test::rigid_bodies(2, 25, 50, 6, 0.05);
  // Gaps: points 7 and 33 vanish for frames 10-29 (filled with their last value, as a
  // container would), point 12 is missing in frame 0.
  for (size_t f = 10; f < 30; ++f)
    for (size_t i : {7u, 33u}) {
      t.valid[f * t.points + i] = 0;
      for (int a = 0; a < 3; ++a)
        t.xyz[3 * (f * t.points + i) + a] = t.xyz[3 * (9 * t.points + i) + a];
    }
  t.valid[12] = 0;
  TransformParams p;
  p.kg_error = 0.1;
  std::vector<uint8_t> bytes;
  std::vector<double> enc, dec;
  PdctCodec codec;
  codec.encode(t.view(), p, &bytes, &enc);
  codec.decode(bytes.data(), bytes.size(), t.frames, t.points, &dec);
  expect_bit_identical(enc, dec);
  const auto s = capz::compare(t.frames, t.points, t.xyz.data(), dec.data(), t.valid.data());
  EXPECT_LE(s.kg_error, 0.1);
}

TEST(PdctCodec, GivenTinyWindowsWhenEncodedThenRoundTrip) {
  PdctCodec codec;
  for (size_t P : {1u, 2u, 3u, 5u})
    for (size_t F : {1u, 2u}) {
      const auto t = capz_test::rigid_bodies(1, P, F, 8);
      TransformParams p;
      std::vector<uint8_t> bytes;
      std::vector<double> enc, dec;
      codec.encode(t.view(), p, &bytes, &enc);
      codec.decode(bytes.data(), bytes.size(), F, P, &dec);
      expect_bit_identical(enc, dec);
      const auto s = capz::compare(F, P, t.xyz.data(), dec.data(), t.valid.data());
      EXPECT_LT(s.max_error, 0.1) << P << "x" << F;
    }
}

TEST(PdctCodec, GivenBadOptionsWhenEncodingThenInvalidParameter) {
  const auto t = capz_test::rigid_bodies(1, 10, 3, 8);
  std::vector<uint8_t> bytes;
  std::vector<double> rec;
  for (auto kv : std::vector<std::pair<std::string, std::string>>{
           {"nonsense", "1"},
           {"zero_share", "1.5"},
           {"coef_bits", "x"},
           {"local_order", "3"},
           {"mode", "grid"} /* grid needs a max error */,
           {"mode", "fast"}}) {
    TransformParams p;
    p.options[kv.first] = kv.second;
    try {
      PdctCodec().encode(t.view(), p, &bytes, &rec);
      ADD_FAILURE() << kv.first << "=" << kv.second << " accepted";
    } catch (const capz::Error& e) {
      EXPECT_EQ(e.code(), capz::ErrorCode::kInvalidParameter);
    }
  }
}

TEST(PdctCodec, GivenTruncatedOrFlippedPayloadWhenDecodingThenCleanErrorOrOutput) {
  const auto t = capz_test::rigid_bodies(2, 15, 12, 9, 0.05);
  PdctCodec codec;
  for (double max_error : {0.0, 0.05}) {  // dct mode, grid mode
    std::vector<uint8_t> bytes;
    std::vector<double> rec;
    TransformParams params;
    params.max_error = max_error;
    codec.encode(t.view(), params, &bytes, &rec);
    for (size_t n = 0; n < bytes.size(); n += 7) {
      EXPECT_THROW(codec.decode(bytes.data(), n, t.frames, t.points, &rec), capz::Error) << n;
    }
    // Bit flips: either a capz::Error or some output of the window's size, never a crash.
    for (size_t i = 0; i < bytes.size(); i += 3) {
      auto b = bytes;
      b[i] ^= 0x5a;
      try {
        codec.decode(b.data(), b.size(), t.frames, t.points, &rec);
        EXPECT_EQ(rec.size(), t.frames * t.points * 3);
      } catch (const capz::Error&) {
      }
    }
    // A window of another shape is rejected.
    EXPECT_THROW(codec.decode(bytes.data(), bytes.size(), t.frames, t.points + 1, &rec),
                 capz::Error);
  }
}
