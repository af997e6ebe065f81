// The second of x y of a spherical frame (docs/FORMAT.md "Scan geometry payload", step 4 and
// flags_f bit 6): from the azimuth where the columns' azimuths are exact, from the range's
// hypotenuse where they are not; the encoder chooses per frame, exactly; bit 6 without bit 2 is
// corrupt. And the laser table's bow (`units` bit 2): a sensor that scans with a mirror (the
// Hesai AT128) has lasers whose elevations curve away from the middle of its field of view; the
// encoder finds the bow and every laser, and a damaged bow is corrupt.
#include <gtest/gtest.h>

#include <cmath>
#include <cstring>
#include <random>

#include "capz/error.h"
#include "coding/scan_geometry.h"
#include "coding/scan_shared.h"
#include "scan_geometry_expect.h"

namespace capz {
namespace {

// Two sweeps of a spinning sensor on a 1 mm grid (step 0.002 m), ranges in whole 4 mm steps
// (the encoder finds them: range units). `jitter`: each firing's azimuth off its column by up to
// that many column steps either way (0: every azimuth on its column).
ScanGeometry sweeps(double jitter, ScanHints* h) {
  std::mt19937 rng(5);
  std::uniform_real_distribution<double> u(0, 1);
  ScanGeometry g;
  const int rings = 16, firings = 1000;
  const double column = 6.283185307179586 / firings;
  for (int f = 0; f < 2; ++f) {
    uint32_t n = 0;
    for (int c = 0; c < firings; ++c) {
      const double az = column * (c + jitter * (2 * u(rng) - 1));
      for (int k = 0; k < rings; ++k) {
        if (u(rng) < 0.05) continue;
        const double el = -0.26 + 0.4 * k / rings;
        double range = 30 + 4 * std::sin(3 * az) + std::cos(5 * az + k) + 0.05 * u(rng);
        range = 0.004 * std::floor(range / 0.004 + 0.5);
        const double rho = range * std::cos(el);
        const double p[3] = {rho * std::cos(az), rho * std::sin(az), range * std::sin(el)};
        push_point(&g, h, p, static_cast<uint32_t>(k));
        ++n;
      }
    }
    g.counts.push_back(n);
  }
  h->grid_per_unit = 500;
  return g;
}

// The payload, checked exact; its header.
scan::Header coded(const ScanGeometry& g, const ScanHints& h, std::vector<uint8_t>* p) {
  *p = encode_scan_geometry(g, h);
  const ScanGeometry back = decode_scan_geometry(p->data(), p->size(), "axis");
  EXPECT_EQ(back.counts, g.counts);
  EXPECT_EQ(back.valid, g.valid);
  EXPECT_EQ(back.q, g.q);
  return scan::read_header(p->data(), p->size(), "axis", 1u << 20);
}

TEST(ScanAxis, GivenAzimuthsOnTheirColumnsThenTheSecondAxisFromTheAzimuth) {
  ScanHints h;
  const ScanGeometry g = sweeps(0, &h);
  std::vector<uint8_t> p;
  const scan::Header hd = coded(g, h, &p);
  ASSERT_FALSE(hd.table.unit.empty());  // an exact range: the azimuth can win
  for (uint8_t fl : hd.flags) {
    EXPECT_NE(fl & scan::kSpherical, 0);
    EXPECT_EQ(fl & scan::kHypot, 0);
  }
}

TEST(ScanAxis, GivenAzimuthsOffTheirColumnsThenTheSecondAxisFromTheHypotenuse) {
  ScanHints h;
  const ScanGeometry g = sweeps(0.45, &h);
  std::vector<uint8_t> p;
  const scan::Header hd = coded(g, h, &p);
  ASSERT_FALSE(hd.table.unit.empty());
  for (uint8_t fl : hd.flags) {
    EXPECT_NE(fl & scan::kSpherical, 0);
    EXPECT_NE(fl & scan::kHypot, 0);
  }
}

// The offset of flags_f in a payload: after F and the counts (varints).
size_t flags_at(const scan::Header& hd) {
  size_t at = 1;  // F < 128 here
  for (uint32_t n : hd.counts)
    for (uint32_t v = n;; v >>= 7) {
      ++at;
      if (v < 128) break;
    }
  return at;
}

TEST(ScanAxis, GivenTheHypotenuseBitOnACartesianFrameWhenDecodedThenCorrupt) {
  ScanHints h;
  const ScanGeometry g = sweeps(0.45, &h);
  std::vector<uint8_t> p;
  const scan::Header hd = coded(g, h, &p);
  const size_t at = flags_at(hd);
  ASSERT_EQ(p[at], hd.flags[0]);
  ASSERT_NE(p[at] & scan::kHypot, 0);
  for (uint8_t bad : {static_cast<uint8_t>(p[at] & ~scan::kSpherical),     // bit 6 alone
                      static_cast<uint8_t>(scan::kHypot | scan::kRaster),  // on a raster frame
                      static_cast<uint8_t>(p[at] | 0x80)}) {               // bit 7
    std::vector<uint8_t> d = p;
    d[at] = bad;
    expect_scan_corrupt(d);
  }
}

constexpr double kPi = 3.141592653589793;

// One sweep of a mirror-scanned sensor on a 1 mm grid (step 0.002 m), no ring field: `lasers`
// lasers 0.2 degrees apart, azimuths -60 .. 60 degrees, each laser's cone slope
// tan(e_k) + w (1 - cos phi).
ScanGeometry mirror_sweep(int lasers, double w, ScanHints* h) {
  std::mt19937 rng(3);
  std::uniform_real_distribution<double> u(0, 1);
  ScanGeometry g;
  uint32_t n = 0;
  for (int c = 0; c <= 600; ++c) {
    const double phi = (-60 + 0.2 * c) * kPi / 180;
    for (int k = 0; k < lasers; ++k) {
      if (u(rng) < 0.1) continue;
      const double e = (-4 + 0.2 * k) * kPi / 180;
      const double rho = 4 + 2 * std::sin(2 * phi + 0.3 * k) + 0.5 * u(rng);
      const double p[3] = {rho * std::cos(phi), rho * std::sin(phi),
                           rho * (std::tan(e) + w * (1 - std::cos(phi)))};
      g.valid.push_back(1);
      for (int a = 0; a < 3; ++a) {
        g.q.push_back(static_cast<int32_t>(std::floor(p[a] / 0.002 + 0.5)));
        h->xyz.push_back(static_cast<float>(p[a]));
      }
      ++n;
    }
  }
  g.counts.push_back(n);
  h->grid_per_unit = 500;
  return g;
}

TEST(ScanBow, GivenAMirrorScannedSweepThenTheBowAndEveryLaserAreFound) {
  ScanHints h;
  const ScanGeometry g = mirror_sweep(40, 0.006, &h);
  std::vector<uint8_t> p;
  const scan::Header hd = coded(g, h, &p);
  ASSERT_NE(hd.flags[0] & scan::kSpherical, 0);
  EXPECT_NEAR(hd.table.bow, 0.006, 0.0005);
  EXPECT_EQ(hd.table.rings(), 40u);  // without the bow the lasers' curves run into each other
}

TEST(ScanBow, GivenAStraightSweepThenNoBow) {
  ScanHints h;
  const ScanGeometry g = mirror_sweep(40, 0, &h);
  std::vector<uint8_t> p;
  const scan::Header hd = coded(g, h, &p);
  EXPECT_EQ(hd.table.bow, 0.0f);
  EXPECT_EQ(hd.table.rings(), 40u);
}

TEST(ScanBow, GivenADamagedBowWhenDecodedThenCorrupt) {
  ScanHints h;
  const ScanGeometry g = mirror_sweep(40, 0.006, &h);
  std::vector<uint8_t> p;
  const scan::Header hd = coded(g, h, &p);
  ASSERT_NE(hd.table.bow, 0.0f);
  const size_t bow_at = hd.body - 1 - 4, units_at = units_offset(p);
  ASSERT_EQ(p[units_at] & scan::kBowBit, scan::kBowBit);
  for (uint8_t bit : {8, 16}) {  // (bit 7, the range's fourth candidate, is any table's)
    std::vector<uint8_t> d = p;
    d[units_at] = static_cast<uint8_t>(d[units_at] | bit);
    expect_scan_corrupt(d);
  }
  for (float bad : {std::nanf(""), 1.5f, -2.0f, INFINITY}) {
    std::vector<uint8_t> d = p;
    std::memcpy(&d[bow_at], &bad, 4);  // little-endian hosts, as the library's tests
    expect_scan_corrupt(d);
  }
}

}  // namespace
}  // namespace capz
