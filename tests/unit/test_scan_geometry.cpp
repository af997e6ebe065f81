// The scan geometry coder (src/coding/scan_geometry.h): exact round trips on synthetic sweeps and
// clean failures (capz::Error, never a crash) on damaged payloads.
#include <gtest/gtest.h>

#include <cmath>
#include <random>

#include "capz/error.h"
#include "coding/scan_geometry.h"
#include "coding/scan_shared.h"
#include "scan_geometry_expect.h"

namespace capz {
namespace {

// A spinning LiDAR's sweeps on a 1 mm grid: `rings` lasers on cones (elevation and z offset per
// ring), firing together every `step` radians, ranges from a room-like scene, some returns
// missing (dropped, so every frame has its own count) and some NaN (kept as gaps).
// wobble: the firings' azimuths off the step by up to that share of it (a sensor whose azimuth
// step is not its firing interval: finer tables' columns fit them better). lift: each laser's
// height above the one below (m; at 0 the elevations' rings are the ring field's).
ScanGeometry spinning(int frames, int rings, int firings, uint32_t seed, ScanHints* hints,
                      double wobble = 0, double lift = 0.002) {
  std::mt19937 rng(seed);
  std::uniform_real_distribution<double> u(0, 1);
  ScanGeometry g;
  const double step = 6.283185307179586 / firings;
  for (int f = 0; f < frames; ++f) {
    uint32_t n = 0;
    for (int c = 0; c < firings; ++c) {
      const double az = (c + wobble * std::sin(0.37 * c)) * step + 0.001 * f;
      for (int k = 0; k < rings; ++k) {
        if (u(rng) < 0.05) continue;  // no return
        const double el = -0.26 + 0.4 * k / rings, z0 = lift * k;
        const double range = 8 + 3 * std::sin(3 * az) + 0.5 * std::cos(7 * az + k) + 0.01 * u(rng);
        const double rho = range * std::cos(el);
        const bool nan = u(rng) < 0.01;
        g.valid.push_back(!nan);
        const double p[3] = {rho * std::cos(az), rho * std::sin(az), z0 + rho * std::tan(el)};
        for (int a = 0; a < 3; ++a) {
          g.q.push_back(nan ? 0 : static_cast<int32_t>(std::floor(p[a] / 0.002 + 0.5)));
          if (hints) hints->xyz.push_back(nan ? NAN : static_cast<float>(p[a]));
        }
        if (hints) hints->ring.push_back(static_cast<uint32_t>(k));
        ++n;
      }
    }
    g.counts.push_back(n);
  }
  return g;
}

ScanGeometry round_trip(const ScanGeometry& g, const ScanHints& h = {}, size_t* bytes = nullptr) {
  const std::vector<uint8_t> p = encode_scan_geometry(g, h);
  if (bytes) *bytes = p.size();
  return decode_scan_geometry(p.data(), p.size(), "test");
}

TEST(ScanGeometry, GivenSpinningSweepsWithRingHintsWhenRoundTrippedThenExactAndSmall) {
  ScanHints h;
  const ScanGeometry g = spinning(3, 16, 900, 1, &h);
  size_t bytes = 0;
  expect_same(g, round_trip(g, h, &bytes));
  // The cones and the azimuth step make it far cheaper than 3 raw int32 (96 bits) a point.
  EXPECT_LT(8.0 * bytes / g.total(), 20.0);
}

// A still sensor's sweeps on a 1 mm grid: the same firings every sweep, each range the scene's
// plus Gaussian noise of `noise` metres.
ScanGeometry still_sweeps(int frames, double noise, ScanHints* hints) {
  std::mt19937 rng(7);
  std::normal_distribution<double> e(0, noise);
  ScanGeometry g;
  const int rings = 16, firings = 900;
  const double step = 6.283185307179586 / firings;
  for (int f = 0; f < frames; ++f) {
    for (int c = 0; c < firings; ++c) {
      const double az = c * step;
      for (int k = 0; k < rings; ++k) {
        const double el = -0.26 + 0.4 * k / rings;
        const double rho =
            (8 + 3 * std::sin(3 * az) + 0.5 * std::cos(7 * az + k) + e(rng)) * std::cos(el);
        const double p[3] = {rho * std::cos(az), rho * std::sin(az), rho * std::tan(el)};
        g.valid.push_back(1);
        for (int a = 0; a < 3; ++a) {
          g.q.push_back(static_cast<int32_t>(std::floor(p[a] / 0.002 + 0.5)));
          hints->xyz.push_back(static_cast<float>(p[a]));
        }
        hints->ring.push_back(static_cast<uint32_t>(k));
      }
    }
    g.counts.push_back(rings * firings);
  }
  return g;
}

// The first `frames` frames of g (and of its hints).
ScanGeometry first_frames(const ScanGeometry& g, const ScanHints& h, size_t frames,
                          ScanHints* out) {
  ScanGeometry s;
  s.counts.assign(g.counts.begin(), g.counts.begin() + static_cast<std::ptrdiff_t>(frames));
  size_t n = 0;
  for (uint32_t c : s.counts) n += c;
  s.valid.assign(g.valid.begin(), g.valid.begin() + static_cast<std::ptrdiff_t>(n));
  s.q.assign(g.q.begin(), g.q.begin() + static_cast<std::ptrdiff_t>(3 * n));
  out->ring.assign(h.ring.begin(), h.ring.begin() + static_cast<std::ptrdiff_t>(n));
  out->xyz.assign(h.xyz.begin(), h.xyz.begin() + static_cast<std::ptrdiff_t>(3 * n));
  return s;
}

TEST(ScanGeometry, GivenAStillSensorsNoisySweepsThenLaterSweepsCostLessThanTheSecond) {
  // The previous sweep's cell predicts a running mean of the cell's ranges (FORMAT "Scan
  // geometry payload", step 5): against the last range alone the residual's spread is the
  // noise's times sqrt(2), against a mean of 8 about sqrt(1.125): 0.4 bits a point less once the
  // means settle (measured: 4.84 bits a point for the second sweep, 4.57 for the next ten; 4.85
  // without).
  ScanHints h;
  const ScanGeometry g = still_sweeps(12, 0.006, &h);
  size_t b1 = 0, b2 = 0, b12 = 0;
  for (auto [frames, bytes] : {std::pair<size_t, size_t*>{1, &b1}, {2, &b2}, {12, &b12}}) {
    ScanHints hs;
    const ScanGeometry s = first_frames(g, h, frames, &hs);
    expect_same(s, round_trip(s, hs, bytes));
  }
  const double n = g.counts[0];
  const double second = 8.0 * (double(b2) - double(b1)) / n;
  const double later = 8.0 * (double(b12) - double(b2)) / (10 * n);
  EXPECT_LT(later, second - 0.15) << "second sweep " << second << ", later " << later;
}

TEST(ScanGeometry, GivenSpinningSweepsWithoutHintsWhenRoundTrippedThenExact) {
  const ScanGeometry g = spinning(2, 32, 500, 2, nullptr);
  size_t inferred = 0, ignored = 0;
  expect_same(g, round_trip(g, {}, &inferred));
  ScanHints none;
  none.ring.assign(1, 0);  // wrong size: ignored, the rings come from the elevations
  expect_same(g, round_trip(g, none, &ignored));
  EXPECT_EQ(inferred, ignored);
}

TEST(ScanGeometry, GivenRandomCloudsWhenRoundTrippedThenExact) {
  std::mt19937 rng(3);
  ScanGeometry g;
  for (uint32_t n : {1000u, 1u, 0u, 517u}) {
    g.counts.push_back(n);
    for (uint32_t i = 0; i < n; ++i) {
      g.valid.push_back(rng() % 7 != 0);
      for (int a = 0; a < 3; ++a)
        g.q.push_back(g.valid.back() ? static_cast<int32_t>(rng() % 200001) - 100000 : 0);
    }
  }
  expect_same(g, round_trip(g));
}

TEST(ScanGeometry, GivenEmptyAndAllNaNFramesWhenRoundTrippedThenKept) {
  ScanGeometry g;
  g.counts = {0, 3, 0, 2};
  g.valid = {0, 0, 0, 1, 0};
  g.q.assign(15, 0);
  g.q[9] = 5, g.q[10] = -7, g.q[11] = 1 << 20;
  expect_same(g, round_trip(g));
  ScanGeometry none;
  expect_same(none, round_trip(none));
  none.counts = {0, 0};
  expect_same(none, round_trip(none));
}

TEST(ScanGeometry, GivenSinglePointsAndHugeCoordinatesWhenRoundTrippedThenExact) {
  ScanGeometry g;
  const int32_t big[] = {INT32_MIN, INT32_MAX, 0, -1, 1 << 30, -(1 << 30), 123456789};
  for (int f = 0; f < 7; ++f) {
    g.counts.push_back(1);
    g.valid.push_back(1);
    for (int a = 0; a < 3; ++a) g.q.push_back(big[(f + a) % 7]);
  }
  expect_same(g, round_trip(g));
  // Spinning sweeps with a few far outliers: spherical frames must give way where needed.
  ScanHints h;
  ScanGeometry s = spinning(2, 8, 200, 4, &h);
  s.q[30] = INT32_MAX;
  s.q[31] = INT32_MIN;
  expect_same(s, round_trip(s, h));
}

TEST(ScanGeometry, GivenMismatchedShapesWhenEncodedThenError) {
  ScanGeometry g;
  g.counts = {2};
  g.valid = {1};
  g.q = {0, 0, 0};
  EXPECT_THROW(encode_scan_geometry(g), Error);
}

TEST(ScanGeometry, GivenDeterministicTrigonometryThenCloseToLibm) {
  for (double a = -20; a < 20; a += 0.0137) {
    double s, c;
    scan::det_sincos(a, &s, &c);
    EXPECT_NEAR(s, std::sin(a), 1e-14);
    EXPECT_NEAR(c, std::cos(a), 1e-14);
  }
}

// FORMAT.md step 4: a spherical point's azimuth cosine and sine are the sum of its ring's angle
// and its column's, each by det_sincos; the tables give those bits for columns inside and
// outside 0 .. C-1 (negative and past the turn), close to libm's of the whole angle.
TEST(ScanGeometry, GivenAnglesOfAzimuthsThenTheSumOfTwoAnglesAsFormatSays) {
  const std::vector<float> a0 = {0.0f, 0.0123f, -3.1f, 2.5f};
  const uint32_t columns = 1800;
  for (double step : {6.283185307179586 / columns, -0.000785398}) {
    const scan::Angles angles(a0, step, columns);
    for (uint32_t k = 0; k < a0.size(); ++k)
      for (int32_t col : {0, 1, 17, 899, 1799, 1800, 2500, -1, -450, 123457}) {
        double sa, ca, sb, cb, s, c;
        scan::det_sincos(static_cast<double>(a0[k]), &sa, &ca);
        scan::det_sincos(static_cast<double>(col) * step, &sb, &cb);
        angles.of(k, col, &s, &c);
        EXPECT_EQ(c, ca * cb - sa * sb) << k << " " << col;
        EXPECT_EQ(s, sa * cb + ca * sb) << k << " " << col;
        const double phi = static_cast<double>(a0[k]) + static_cast<double>(col) * step;
        EXPECT_NEAR(c, std::cos(phi), 1e-13);
        EXPECT_NEAR(s, std::sin(phi), 1e-13);
      }
  }
}

// Every truncation and many byte flips of a payload either decode or throw capz::Error.
TEST(ScanGeometry, GivenDamagedPayloadsWhenDecodedThenErrorOrValues) {
  ScanHints h;
  const ScanGeometry g = spinning(2, 8, 120, 5, &h);
  const std::vector<uint8_t> p = encode_scan_geometry(g, h);
  size_t errors = 0;
  for (size_t n = 0; n < p.size(); ++n) {
    try {
      decode_scan_geometry(p.data(), n, "cut", 1 << 20);
    } catch (const Error& e) {
      EXPECT_EQ(e.code(), ErrorCode::kCorrupt);
      ++errors;
    }
  }
  EXPECT_EQ(errors, p.size());  // a block cut short never ends where a valid one does
  std::mt19937 rng(6);
  for (int t = 0; t < 1500; ++t) {
    std::vector<uint8_t> d = p;
    for (int k = 0; k < 1 + t % 3; ++k)
      d[rng() % d.size()] ^= static_cast<uint8_t>(1 + rng() % 255);
    try {
      const ScanGeometry r = decode_scan_geometry(d.data(), d.size(), "flipped", 1 << 20);
      size_t total = 0;
      for (uint32_t c : r.counts) total += c;
      EXPECT_EQ(r.valid.size(), total);
    } catch (const Error& e) {
      EXPECT_EQ(e.code(), ErrorCode::kCorrupt);
    }
  }
}

TEST(ScanGeometry, GivenCountsBeyondTheLimitWhenDecodedThenError) {
  ScanGeometry g;
  g.counts = {1000};
  g.valid.assign(1000, 0);
  g.q.assign(3000, 0);
  const std::vector<uint8_t> p = encode_scan_geometry(g);
  EXPECT_THROW(decode_scan_geometry(p.data(), p.size(), "limit", 999), Error);
  EXPECT_EQ(decode_scan_geometry(p.data(), p.size(), "limit", 1000).total(), 1000u);
}

// The laser table chosen on a trial sample (scan_encode.cpp, sampled_choice): a sweep larger
// than its sample (the first quarter of its points) codes fewer tables whole than every_table's
// one a table, and its payload stays within 1.5 % of the smallest of theirs.
TEST(ScanTrial, GivenALargeSweepWhenEncodedThenTheTablesAreTriedOnASample) {
  ScanHints h;
  const ScanGeometry g = spinning(1, 32, 2400, 5, &h, 0.45);
  ASSERT_GT(g.total(), 4u * 16384);
  ScanWorkspace sampled, every;
  every.every_table = true;
  const std::vector<uint8_t> a = encode_scan_geometry(g, h, &sampled);
  const std::vector<uint8_t> b = encode_scan_geometry(g, h, &every);
  EXPECT_EQ(every.sample_codings, 0u);
  EXPECT_GE(every.tables_coded, 3u);
  EXPECT_GE(sampled.sample_codings, every.tables_coded);
  EXPECT_LT(sampled.tables_coded, every.tables_coded);
  EXPECT_LE(static_cast<double>(a.size()), 1.015 * static_cast<double>(b.size()));
  expect_same(g, decode_scan_geometry(a.data(), a.size(), "test"));
}

// A sequence's windows (ScanWorkspace::remember): the next window codes its sample under the
// table the window before chose, and under no other while that costs at most 5 % more bits a
// point than in the trial that chose it; else every table is tried again.
TEST(ScanTrial, GivenASequenceWhenTheChoiceIsRememberedThenTheNextWindowTriesItAlone) {
  ScanHints h1, h2;
  const ScanGeometry g1 = spinning(3, 32, 2400, 6, &h1), g2 = spinning(3, 32, 2400, 7, &h2);
  ScanWorkspace ws;
  ws.remember = true;
  encode_scan_geometry(g1, h1, &ws);
  const size_t tried = ws.sample_codings;
  ASSERT_GE(tried, 3u);
  ASSERT_GT(ws.choice.bits, 0.0);
  const std::vector<uint8_t> p = encode_scan_geometry(g2, h2, &ws);
  // Each set of rings coded (the ring field's, and the elevations' where they differ) tries the
  // remembered table alone.
  const size_t fits = scan_rings_differ(g2, h2) ? 2 : 1;
  EXPECT_EQ(ws.sample_codings, tried + fits);
  expect_same(g2, decode_scan_geometry(p.data(), p.size(), "test"));
  ScanWorkspace fresh;
  const size_t alone = encode_scan_geometry(g2, h2, &fresh).size();
  EXPECT_LE(static_cast<double>(p.size()), 1.015 * static_cast<double>(alone));
  // The remembered sample cost far below this window's: every table again.
  ws.choice.bits *= 0.5;
  const size_t before = ws.sample_codings;
  encode_scan_geometry(g2, h2, &ws);
  EXPECT_GE(ws.sample_codings, before + tried);
}

// What a sequence keeps beside its table choice: a spinning sensor's window leaves `moving` set
// (its second frame did not repeat its first's directions) and its elevation peaks (its ring
// field's rings); the next window's ring check on every 16th point and on those peaks, and its
// raster test skipped, give the bytes the full check and the test give.
TEST(ScanTrial, GivenASequenceWhenItsRingsAndMotionAreKeptThenTheNextWindowCodesTheSame) {
  ScanHints h1, h2;
  const ScanGeometry g1 = spinning(3, 16, 2400, 8, &h1, 0, 0),
                     g2 = spinning(3, 16, 2400, 9, &h2, 0, 0);
  ScanWorkspace ws;
  ws.remember = true;
  encode_scan_geometry(g1, h1, &ws);
  EXPECT_TRUE(ws.moving);
  EXPECT_FALSE(scan_rings_differ(g1, h1));
  ASSERT_EQ(ws.ring_peaks.size(), 16u);
  ASSERT_FALSE(scan_rings_differ(g2, h2));
  ScanWorkspace full = ws;
  full.ring_peaks.clear();
  full.moving = false;
  const std::vector<uint8_t> quick = encode_scan_geometry(g2, h2, &ws);
  EXPECT_EQ(quick, encode_scan_geometry(g2, h2, &full));
  EXPECT_EQ(ws.ring_peaks.size(), 16u);
  expect_same(g2, decode_scan_geometry(quick.data(), quick.size(), "test"));
}

}  // namespace
}  // namespace capz
