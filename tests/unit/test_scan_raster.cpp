// Raster frames of the scan geometry payload (src/coding/scan_raster.h, FORMAT.md "Raster
// frames"): a payload built by hand decodes to the integers the format text gives, a synthetic
// flash LiDAR's sweeps round-trip exactly as raster frames, at a coarse bound they come back on
// their rays within the bound (the fine shift), points off their rays too, and damaged raster
// payloads fail cleanly.
#include <gtest/gtest.h>

#include <algorithm>
#include <cmath>
#include <filesystem>
#include <random>

#include "capz/codec.h"
#include "capz/error.h"
#include "capz/io.h"
#include "capz/tool/verify.h"
#include "coding/bytes.h"
#include "coding/scan_geometry.h"
#include "coding/scan_raster.h"
#include "coding/scan_shared.h"
#include "scan_geometry_expect.h"
#include "test_util.h"

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

// A depth camera: a cols x rows pinhole (focal length 0.8 cols, principal point at the centre)
// looking along axis `axis` (sign `side`) at a tilted wall and a bump, depth on a 1 mm quantum with
// noise of a few quanta, the other two coordinates (u - c) depth / f in float32, a 2 mm grid;
// each frame drops some pixels (no depth), and the frames keep the camera's pixel order.
ScanGeometry pinhole(int frames, int rows, int cols, uint32_t seed, int axis, int side,
                     ScanHints* hints) {
  std::mt19937 rng(seed);
  std::uniform_real_distribution<double> u(0, 1);
  const double f = 0.8 * cols, cu = 0.5 * cols, cv = 0.5 * rows;
  ScanGeometry g;
  for (int k = 0; k < frames; ++k) {
    uint32_t n = 0;
    for (int r = 0; r < rows; ++r) {
      for (int c = 0; c < cols; ++c) {
        if (u(rng) < 0.05) continue;  // no depth
        const double x = (c - cu) / f, y = (r - cv) / f;
        const double scene = 2.5 + 0.8 * x + 0.3 * std::exp(-20 * (x * x + y * y));
        const double z = 0.001 * std::floor(scene / 0.001 + 6 * (u(rng) - 0.5));
        float p[3];
        p[axis] = static_cast<float>(side * z);
        p[(axis + 1) % 3] = static_cast<float>((c - cu) * z / f);
        p[(axis + 2) % 3] = static_cast<float>((r - cv) * z / f);
        g.valid.push_back(1);
        for (int a = 0; a < 3; ++a) {
          g.q.push_back(static_cast<int32_t>(std::floor(p[a] / 0.002 + 0.5)));
          hints->xyz.push_back(p[a]);
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
std::vector<uint8_t> two_point_payload(int32_t pixel1, uint8_t flags = scan::kRaster,
                                       uint8_t fine = 0) {
  ByteWriter w;
  w.varint(1);  // F
  w.varint(2);  // n_0
  w.u8(flags);
  w.varint(0);  // K
  w.varint(2);  // P
  w.f64(1.0);   // delta
  w.u8(0);      // e
  w.u8(fine);   // k
  IntEncoder enc(scan::kContexts);
  enc.add_bit_models();
  const int t = scan::raster::kCtxTable;  // the pixel table: plain tokens (FORMAT "Zero first")
  enc.put_signed(1, t), enc.put_signed(0, t + 1), enc.put_signed(0, t + 2);   // V[0] - 0
  enc.put_signed(-2, t), enc.put_signed(1, t + 1), enc.put_signed(0, t + 2);  // V[1] - 2 V[0]
  const int p = scan::raster::kCtxPixel, r = scan::raster::kCtxRange, x = scan::raster::kCtxXyz;
  // The pixel residuals and x y z zero first, the ranges plain.
  const auto z = [&enc](int32_t v, int ctx) { enc.put_zero_first(zigzag(v), ctx); };
  z(0, p + 1);                                  // point 0: pixel 0 (s' = 1 at the frame's start)
  enc.put_signed(5, r + 0);                     // rho 5 against L = 0, scores 0
  for (int a = 0; a < 3; ++a) z(0, x + 2 * a);  // (5, 0, 0) as predicted
  z(pixel1, p + 0);                             // point 1
  enc.put_signed(2, r + 2);                     // rho 7 against L = 5; score 5: bits(5 >> 1) = 2
  z(0, x), z(1, x + 2), z(0, x + 4);            // (0, 7 + 1, 0)
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
  EXPECT_EQ(g.fine, 0);
  // A fine shift changes nothing but what the integers count (the caller scales them).
  const std::vector<uint8_t> f = two_point_payload(0, scan::kRaster, 3);
  const ScanGeometry gf = decode_scan_geometry(f.data(), f.size(), "test");
  EXPECT_EQ(gf.q, g.q);
  EXPECT_EQ(gf.fine, 3);
  EXPECT_EQ(scan_fine_shift(f.data(), f.size(), "test"), 3);
  EXPECT_EQ(scan_fine_shift(p.data(), p.size(), "test"), 0);
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
  // Header bytes: F, n_0, flags, K, P (offset 4), delta (5..12), e (13), k (14).
  std::vector<uint8_t> zero_p = good, nan_delta = good, big_e = good, big_k = good;
  zero_p[4] = 0;
  nan_delta[12] = 0x7f, nan_delta[11] = 0xf8;  // NaN
  big_e[13] = 31;
  big_k[14] = scan::kMaxFine + 1;
  for (const auto* p : {&zero_p, &nan_delta, &big_e, &big_k}) {
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

// A depth camera's frames without their empty pixels: the depth, not the range, lies on a
// quantum, along z or another axis, either way round. Coded as raster frames (the depth the
// range), exactly, in under half the payload of the other coding.
TEST(ScanRaster, GivenDepthCameraFramesWhenRoundTrippedThenRasterFramesAlongTheDepthAxis) {
  for (int axis : {2, 0}) {
    for (int side : {1, -1}) {
      SCOPED_TRACE(std::to_string(axis) + " " + std::to_string(side));
      ScanHints h;
      const ScanGeometry g = pinhole(4, 30, 40, 3, axis, side, &h);
      const std::vector<uint8_t> raster = encode_scan_geometry(g, h);
      const scan::Header head = scan::read_header(raster.data(), raster.size(), "test", 1u << 20);
      for (uint8_t fl : head.flags) EXPECT_TRUE(fl & scan::kRaster) << int{fl};
      EXPECT_GE(head.pixels, 30u * 40u * 9u / 10u);
      EXPECT_LE(head.pixels, 30u * 40u + 16u);
      expect_same(g, decode_scan_geometry(raster.data(), raster.size(), "test"));
      const std::vector<uint8_t> plain = encode_scan_geometry(g, {});
      EXPECT_LT(raster.size() * 2, plain.size()) << raster.size() << " against " << plain.size();
    }
  }
  // Points on both sides of every axis' zero (no camera's depth) are no depth camera's.
  ScanHints h;
  ScanGeometry g = pinhole(3, 20, 20, 4, 2, 1, &h);
  for (size_t i = 0; i < g.total(); i += 2) {
    h.xyz[3 * i + 2] = -h.xyz[3 * i + 2];
    g.q[3 * i + 2] = -g.q[3 * i + 2];
  }
  const std::vector<uint8_t> p = encode_scan_geometry(g, h);
  EXPECT_FALSE(scan::read_header(p.data(), p.size(), "test", 1u << 20).flags[0] & scan::kRaster);
  expect_same(g, decode_scan_geometry(p.data(), p.size(), "test"));
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

// The largest error of g's decoded points (integers times step 2^-fine, also as float32) from
// the source coordinates xyz (valid points only).
double max_error(const ScanGeometry& g, const std::vector<float>& xyz, double step) {
  double worst = 0;
  for (size_t i = 0; i < g.total(); ++i)
    for (size_t a = 0; g.valid[i] && a < 3; ++a) {
      const double y = std::ldexp(static_cast<double>(g.q[3 * i + a]) * step, -g.fine);
      const double x = xyz[3 * i + a];
      worst = std::max(
          {worst, std::fabs(y - x), std::fabs(static_cast<double>(static_cast<float>(y)) - x)});
    }
  return worst;
}

// g's integers on the grid of `step` from the source coordinates (the nearest grid points).
void on_grid(const ScanHints& h, double step, ScanGeometry* g) {
  for (size_t i = 0; i < g->total(); ++i)
    for (size_t a = 0; g->valid[i] && a < 3; ++a)
      g->q[3 * i + a] = static_cast<int32_t>(std::floor(h.xyz[3 * i + a] / step + 0.5));
}

// A flash sweep at a coarse bound: the step of the grid (2 bound) leaves no room, so the encoder
// puts the points on their rays on a finer grid, ranges in steps of about 2 bound. The bound
// holds on every decoded (and float32) coordinate, and the payload is under 0.9 of the exact one
// (about 0.85, 0.7 and 0.55 of it at 5 mm, 1 cm and 2 cm: the noise here is 4 quanta, 2 cm).
TEST(ScanRaster, GivenCoarseBoundWhenEncodedThenPointsOnRaysWithinBoundAndSmaller) {
  for (double bound : {0.005, 0.01, 0.02}) {
    ScanHints h;
    ScanGeometry g = flash(6, 24, 32, 11, &h);
    const double step = 2 * bound * (1 - std::ldexp(1.0, -30));
    on_grid(h, step, &g);
    const std::vector<uint8_t> exact = encode_scan_geometry(g, h);
    h.bound = bound, h.step = step;
    const std::vector<uint8_t> ray = encode_scan_geometry(g, h);
    const ScanGeometry back = decode_scan_geometry(ray.data(), ray.size(), "test");
    EXPECT_GT(back.fine, 0) << bound;
    EXPECT_EQ(back.counts, g.counts);
    EXPECT_EQ(back.valid, g.valid);
    EXPECT_LE(max_error(back, h.xyz, step), bound) << bound;
    EXPECT_LT(ray.size() * 10, exact.size() * 9)
        << bound << ": " << ray.size() << " against " << exact.size();
    // The same payload from the same input (the encoder's choices are deterministic).
    EXPECT_EQ(encode_scan_geometry(g, h), ray);
  }
}

// Points off their ray by more than the bound (a return the raster does not describe) fall back
// to the source's coordinates on the fine grid: the bound still holds on each.
// A depth camera's frames at a coarse bound: on their rays, within the bound, smaller.
TEST(ScanRaster, GivenDepthCameraFramesAtBoundWhenEncodedThenOnTheirRaysWithinTheBound) {
  for (double bound : {0.001, 0.01}) {
    ScanHints h;
    ScanGeometry g = pinhole(4, 30, 40, 8, 2, 1, &h);
    const double step = 2 * bound * (1 - std::ldexp(1.0, -30));
    on_grid(h, step, &g);
    const std::vector<uint8_t> plain = encode_scan_geometry(g, {});
    h.bound = bound, h.step = step;
    const std::vector<uint8_t> ray = encode_scan_geometry(g, h);
    const ScanGeometry back = decode_scan_geometry(ray.data(), ray.size(), "test");
    EXPECT_TRUE(scan::read_header(ray.data(), ray.size(), "test", 1u << 20).flags[0] &
                scan::kRaster);
    EXPECT_EQ(back.counts, g.counts);
    EXPECT_LE(max_error(back, h.xyz, step), bound) << bound;
    EXPECT_LT(ray.size() * 4, plain.size() * 3)
        << bound << ": " << ray.size() << " against " << plain.size();
  }
}

TEST(ScanRaster, GivenPointsOffTheirRaysWhenEncodedAtBoundThenBoundHolds) {
  ScanHints h;
  ScanGeometry g = flash(4, 20, 24, 5, &h);
  const double bound = 0.01, step = 2 * bound * (1 - std::ldexp(1.0, -30));
  std::mt19937 rng(9);
  size_t moved = 0;
  for (size_t i = 0; i < g.total(); ++i) {
    if (!g.valid[i] || rng() % 50 != 0) continue;
    h.xyz[3 * i + rng() % 3] += (rng() % 2 ? 0.05f : -0.04f);  // 4-5 bounds off one axis
    ++moved;
  }
  ASSERT_GT(moved, 20u);
  on_grid(h, step, &g);
  h.bound = bound, h.step = step;
  const std::vector<uint8_t> p = encode_scan_geometry(g, h);
  const ScanGeometry back = decode_scan_geometry(p.data(), p.size(), "test");
  ASSERT_GT(back.fine, 0);
  EXPECT_LE(max_error(back, h.xyz, step), bound);
}

// Cut or damaged raster payloads at a bound fail as corrupt, never crash.
TEST(ScanRaster, GivenDamagedBoundedPayloadWhenDecodedThenCorrupt) {
  ScanHints h;
  ScanGeometry g = flash(3, 12, 16, 2, &h);
  const double bound = 0.01, step = 2 * bound * (1 - std::ldexp(1.0, -30));
  on_grid(h, step, &g);
  h.bound = bound, h.step = step;
  const std::vector<uint8_t> p = encode_scan_geometry(g, h);
  ASSERT_GT(scan_fine_shift(p.data(), p.size(), "test"), 0);
  for (size_t cut : {p.size() - 1, p.size() / 2, size_t{20}}) {
    try {
      decode_scan_geometry(p.data(), cut, "test");
      FAIL() << "decoded " << cut << " bytes";
    } catch (const Error& e) {
      EXPECT_EQ(e.code(), ErrorCode::kCorrupt) << cut;
    }
  }
  size_t failed = 0;
  for (size_t at = p.size() / 3; at < p.size(); at += p.size() / 7) {
    std::vector<uint8_t> d = p;
    d[at] ^= 0x5a;
    try {
      const ScanGeometry back = decode_scan_geometry(d.data(), d.size(), "test");
      EXPECT_EQ(back.total(), g.total());
    } catch (const Error& e) {
      EXPECT_EQ(e.code(), ErrorCode::kCorrupt);
      ++failed;
    }
  }
  EXPECT_GT(failed, 0u);
}

// The RoboSense E1 (../shared) at 1 cm, its fields kept, in the file's order: its raster frames
// on their rays come back within the bound (and as float32), every field byte for byte; with
// --point-order any (octree frames since their window with its fields is smaller, FORMAT.md
// "Octree frames") each frame's points within the bound of their partners and its fields as a
// multiset; and frames decoded at random equal the whole decode.
// A reordered archive z of t decoded as d: the promise holds (each frame's points paired within
// the bound, capz/tool/verify.h) and each frame's fields are the same multiset of rows.
void expect_same_fields_per_frame(const Take& t, const Take& d, const std::vector<uint8_t>& z) {
  const PromiseResult r = check_promise(t, d, promise_of(describe(z.data(), z.size())));
  EXPECT_TRUE(r.holds) << r.why;
  ASSERT_EQ(d.attributes.size(), t.attributes.size());
  const auto rows = [](const Take& x, size_t f) {
    std::vector<std::vector<uint8_t>> out;
    for (size_t i = x.frame_begin(f); i < x.frame_begin(f) + x.frame_points(f); ++i) {
      std::vector<uint8_t> row;
      for (const PointAttribute& a : x.attributes) {
        const auto at = a.data.begin() + static_cast<std::ptrdiff_t>(i * a.bytes_per_point());
        row.insert(row.end(), at, at + static_cast<std::ptrdiff_t>(a.bytes_per_point()));
      }
      out.push_back(std::move(row));
    }
    std::sort(out.begin(), out.end());
    return out;
  };
  for (size_t f = 0; f < t.frames; ++f) EXPECT_EQ(rows(d, f), rows(t, f)) << "frame " << f;
}

TEST(ScanRaster, SharedE1AtOneCentimetreHoldsTheBoundWithItsFields) {
  const std::string root = capz_test::shared_data_or_skip("scan");
  if (root.empty()) return;
  const std::string dir = root + "/robosense-e1";
  if (!std::filesystem::is_directory(dir)) GTEST_SKIP() << "no " << dir;
  const Take t = read_take(dir);
  ASSERT_TRUE(t.ragged());
  for (bool any : {false, true}) {
    CompressOptions o;
    o.max_error = 0.01;
    o.any_point_order = any;
    const std::vector<uint8_t> z = compress(t, o);
    const Take d = decompress(z.data(), z.size());
    ASSERT_EQ(d.total_points(), t.total_points());
    if (any) expect_same_fields_per_frame(t, d, z);
    double worst = 0;
    for (size_t i = 0; i < t.total_points() && !any; ++i) {
      ASSERT_EQ(d.valid[i], t.valid[i]);
      for (size_t a = 0; t.valid[i] && a < 3; ++a) {
        const double y = d.xyz[3 * i + a], x = t.xyz[3 * i + a];
        worst = std::max(
            {worst, std::fabs(y - x), std::fabs(static_cast<double>(static_cast<float>(y)) - x)});
      }
    }
    EXPECT_LE(worst, 0.01) << "any " << any;
    ASSERT_EQ(d.attributes.size(), t.attributes.size());
    for (size_t a = 0; a < t.attributes.size() && !any; ++a)
      EXPECT_EQ(d.attributes[a].data, t.attributes[a].data) << t.attributes[a].name;
    const Take part = decompress_frames(z.data(), z.size(), 5, 3);
    const size_t p0 = t.frame_begin(5);
    ASSERT_EQ(part.total_points(), t.frame_begin(8) - p0);
    for (size_t j = 0; j < 3 * part.total_points(); ++j)
      ASSERT_EQ(part.xyz[j], d.xyz[3 * p0 + j]) << j;
  }
}

// The integers a raster payload at a bound codes (fine shift above 0) as the encoder hands them
// out in its workspace (ScanWorkspace::fine_q, which the ATTR chunk's predictors take instead
// of decoding the payload again) are the decoder's, point for point; a payload of the integers
// given (no bound) hands out none. s: the source's coordinates (x y z per point), counts: per
// frame.
void expect_fine_q_decodes(const std::vector<uint32_t>& counts, const std::vector<float>& s,
                           double bound, const std::string& what) {
  ScanGeometry g;
  ScanHints h;
  g.counts = counts;
  h.xyz = s;
  for (size_t i = 0; i < s.size() / 3; ++i)
    g.valid.push_back(std::isfinite(s[3 * i]) && std::isfinite(s[3 * i + 1]) &&
                      std::isfinite(s[3 * i + 2]));
  g.q.assign(s.size(), 0);
  const double step = 2 * bound * (1 - std::ldexp(1.0, -30));
  on_grid(h, step, &g);
  ScanWorkspace ws;
  const std::vector<uint8_t> exact = encode_scan_geometry(g, h, &ws);
  EXPECT_TRUE(ws.fine_q.empty() && ws.fine_payload.empty()) << what;
  h.bound = bound, h.step = step;
  const std::vector<uint8_t> p = encode_scan_geometry(g, h, &ws);
  const ScanGeometry back = decode_scan_geometry(p.data(), p.size(), what);
  ASSERT_GT(back.fine, 0) << what;
  EXPECT_EQ(ws.fine_payload, p) << what;
  ASSERT_EQ(ws.fine_q.size(), back.q.size()) << what;
  size_t moved = 0;  // integers other than the grid's (the hand-out is not g.q)
  for (size_t j = 0; j < back.q.size(); ++j) {
    ASSERT_EQ(ws.fine_q[j], back.q[j]) << what << " integer " << j;
    moved += back.q[j] != g.q[j];
  }
  EXPECT_GT(moved, back.q.size() / 2) << what;
}

TEST(ScanRaster, GivenFlashSweepsAtBoundWhenEncodedThenHandedOutIntegersAreTheDecoders) {
  for (double bound : {0.005, 0.02}) {
    ScanHints h;
    const ScanGeometry g = flash(5, 20, 28, 3, &h);
    expect_fine_q_decodes(g.counts, h.xyz, bound, "flash " + std::to_string(bound));
  }
}

// The same on the RoboSense E1's first four sweeps (../shared) at 1 cm and 1 mm.
TEST(ScanRaster, SharedE1SweepsAtBoundHandOutTheDecodersIntegers) {
  const std::string dir = capz_test::shared_data_or_skip("scan/robosense-e1");
  if (dir.empty()) return;
  const Take t = read_take(dir);
  ASSERT_TRUE(t.ragged() && t.frames >= 4);
  std::vector<uint32_t> counts;
  for (size_t f = 0; f < 4; ++f) counts.push_back(static_cast<uint32_t>(t.frame_points(f)));
  std::vector<float> s(3 * t.frame_begin(4));
  for (size_t i = 0; i < s.size() / 3; ++i)
    for (size_t a = 0; a < 3; ++a)
      s[3 * i + a] = t.valid[i] ? static_cast<float>(t.xyz[3 * i + a]) : NAN;
  for (double bound : {0.01, 0.001})
    expect_fine_q_decodes(counts, s, bound, "e1 " + std::to_string(bound));
}

}  // namespace
}  // namespace capz
