// Raster frames of the scan geometry payload (src/coding/scan_raster.h, FORMAT.md "Raster
// frames"): a payload built by hand decodes to the integers the format text gives, a synthetic
// flash LiDAR's sweeps round-trip exactly as raster frames, and damaged raster payloads fail
// cleanly.
#include <gtest/gtest.h>

#include <cmath>
#include <random>

#include "capz/error.h"
#include "coding/bytes.h"
#include "coding/scan_geometry.h"
#include "coding/scan_raster.h"
#include "coding/scan_shared.h"
#include "scan_geometry_expect.h"

namespace capz {
namespace {

// A flash LiDAR: a fixed raster of rows x cols directions on a curved pattern, ranges on a 5 mm
// quantum (a static room with noise of a few quanta), x y z = range times the pixel's unit vector
// in float32, a 2 mm grid. Each frame loses some returns (dropped: its own count) and some points
// are NaN (gaps kept in place).
ScanGeometry flash(int frames, int rows, int cols, uint32_t seed, ScanHints* hints) {
  std::mt19937 rng(seed);
  std::uniform_real_distribution<double> u(0, 1);
  ScanGeometry g;
  for (int f = 0; f < frames; ++f) {
    uint32_t n = 0;
    for (int r = 0; r < rows; ++r) {
      for (int c = 0; c < cols; ++c) {
        if (u(rng) < 0.04) continue;  // no return
        const double az = -1.0 + 2.0 * c / cols, el = -0.7 + 1.4 * r / rows + 0.05 * az * az;
        const double ux = std::cos(el) * std::cos(az), uy = std::cos(el) * std::sin(az),
                     uz = std::sin(el);
        const double scene = 3 + 1.5 * std::sin(2 * az + r * 0.1) + 0.5 * std::cos(3 * el);
        const double d = 0.005 * std::floor(scene / 0.005 + 4 * (u(rng) - 0.5));
        const bool nan = u(rng) < 0.01;
        g.valid.push_back(!nan);
        const float p[3] = {static_cast<float>(d * ux), static_cast<float>(d * uy),
                            static_cast<float>(d * uz)};
        for (int a = 0; a < 3; ++a) {
          g.q.push_back(nan ? 0 : static_cast<int32_t>(std::floor(p[a] / 0.002 + 0.5)));
          hints->xyz.push_back(nan ? NAN : p[a]);
        }
        ++n;
      }
    }
    g.counts.push_back(n);
  }
  return g;
}

// One raster frame of two points, by FORMAT.md's rules: pixels (1, 0, 0) and (0, 1, 0) at e = 0,
// delta 1; ranges 5 and 7; the second point's y one above its prediction. `pixel1` is the second
// point's pixel residual (0: pixel 1, the one after pixel 0).
std::vector<uint8_t> two_point_payload(int32_t pixel1, uint8_t flags = scan::kRaster) {
  ByteWriter w;
  w.varint(1);  // F
  w.varint(2);  // n_0
  w.u8(flags);
  w.varint(0);  // K
  w.varint(2);  // P
  w.f64(1.0);   // delta
  w.u8(0);      // e
  IntEncoder enc(scan::kContexts);
  const int t = scan::raster::kCtxTable;
  enc.put_signed(1, t), enc.put_signed(0, t + 1), enc.put_signed(0, t + 2);   // V[0] - 0
  enc.put_signed(-2, t), enc.put_signed(1, t + 1), enc.put_signed(0, t + 2);  // V[1] - 2 V[0]
  const int p = scan::raster::kCtxPixel, r = scan::raster::kCtxRange, x = scan::raster::kCtxXyz;
  enc.put_signed(0, p + 1);  // point 0: pixel 0 (s' = 1 at the frame's start)
  enc.put_signed(5, r + 0);  // rho 5 against L = 0, scores 0
  for (int a = 0; a < 3; ++a) enc.put_signed(0, x + 2 * a);  // (5, 0, 0) as predicted
  enc.put_signed(pixel1, p + 0);                             // point 1
  enc.put_signed(2, r + 2);  // rho 7 against L = 5; score 5: bits(5 >> 1) = 2
  enc.put_signed(0, x), enc.put_signed(1, x + 2), enc.put_signed(0, x + 4);  // (0, 7 + 1, 0)
  std::vector<uint8_t> out = w.buffer();
  const std::vector<uint8_t> body = enc.finish();
  out.insert(out.end(), body.begin(), body.end());
  return out;
}

TEST(ScanRaster, GivenHandBuiltPayloadWhenDecodedThenTheFormatsIntegers) {
  const std::vector<uint8_t> p = two_point_payload(0);
  const ScanGeometry g = decode_scan_geometry(p.data(), p.size(), "test");
  ASSERT_EQ(g.counts, std::vector<uint32_t>{2});
  EXPECT_EQ(g.valid, (std::vector<uint8_t>{1, 1}));
  EXPECT_EQ(g.q, (std::vector<int32_t>{5, 0, 0, 0, 8, 0}));
}

TEST(ScanRaster, GivenPixelOutsideTheTableWhenDecodedThenCorrupt) {
  for (int32_t s : {1, -2}) {
    const std::vector<uint8_t> p = two_point_payload(s);
    try {
      decode_scan_geometry(p.data(), p.size(), "test");
      FAIL() << "pixel residual " << s << " decoded";
    } catch (const Error& e) {
      EXPECT_EQ(e.code(), ErrorCode::kCorrupt);
    }
  }
}

TEST(ScanRaster, GivenRasterAndSphericalFlagsWhenDecodedThenCorrupt) {
  const std::vector<uint8_t> p =
      two_point_payload(0, static_cast<uint8_t>(scan::kRaster | scan::kSpherical));
  EXPECT_THROW(decode_scan_geometry(p.data(), p.size(), "test"), Error);
}

TEST(ScanRaster, GivenBadPixelTableHeaderWhenDecodedThenCorrupt) {
  const std::vector<uint8_t> good = two_point_payload(0);
  // Header bytes: F, n_0, flags, K, P (offset 4), delta (5..12), e (13).
  std::vector<uint8_t> zero_p = good, nan_delta = good, big_e = good;
  zero_p[4] = 0;
  nan_delta[12] = 0x7f, nan_delta[11] = 0xf8;  // NaN
  big_e[13] = 31;
  for (const auto* p : {&zero_p, &nan_delta, &big_e}) {
    try {
      decode_scan_geometry(p->data(), p->size(), "test");
      FAIL() << "decoded";
    } catch (const Error& e) {
      EXPECT_EQ(e.code(), ErrorCode::kCorrupt);
    }
  }
}

TEST(ScanRaster, GivenFlashSweepsWhenRoundTrippedThenRasterFramesExactAndSmaller) {
  ScanHints h;
  const ScanGeometry g = flash(5, 24, 32, 7, &h);
  const std::vector<uint8_t> raster = encode_scan_geometry(g, h);
  const scan::Header head = scan::read_header(raster.data(), raster.size(), "test", 1u << 20);
  for (uint8_t fl : head.flags) EXPECT_TRUE(fl & scan::kRaster) << int{fl};
  // Every direction of the raster, some maybe twice (a direction that rounds to two keys, 2^-15
  // apart, from one frame to the next: a pixel of its own, which costs a few bits only).
  EXPECT_GE(head.pixels, 24u * 32u);
  EXPECT_LE(head.pixels, 24u * 32u + 8u);
  const ScanGeometry back = decode_scan_geometry(raster.data(), raster.size(), "test");
  expect_same(g, back);
  // Without the source coordinates the encoder cannot find the raster: its other coding, larger.
  const std::vector<uint8_t> plain = encode_scan_geometry(g, {});
  EXPECT_FALSE(scan::read_header(plain.data(), plain.size(), "test", 1u << 20).flags[0] &
               scan::kRaster);
  EXPECT_LT(raster.size() * 3, plain.size() * 2);
}

TEST(ScanRaster, GivenOneFrameOrNoQuantumWhenEncodedThenNoRasterFrames) {
  ScanHints h;
  ScanGeometry g = flash(1, 10, 12, 3, &h);
  std::vector<uint8_t> p = encode_scan_geometry(g, h);
  EXPECT_FALSE(scan::read_header(p.data(), p.size(), "test", 1u << 20).flags[0] & scan::kRaster);
  ScanHints h2;
  g = flash(3, 10, 12, 3, &h2);
  std::mt19937 rng(5);
  for (float& v : h2.xyz) v *= 1.0f + 1e-3f * static_cast<float>(rng() % 1000) / 1000.0f;
  p = encode_scan_geometry(g, h2);
  EXPECT_FALSE(scan::read_header(p.data(), p.size(), "test", 1u << 20).flags[0] & scan::kRaster);
  expect_same(g, decode_scan_geometry(p.data(), p.size(), "test"));
}

}  // namespace
}  // namespace capz
