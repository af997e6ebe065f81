// The laser table's bow (docs/FORMAT.md "Scan geometry payload", `units` bit 2): a sensor that
// scans with a mirror (the Hesai AT128) has lasers whose elevations curve away from the middle of
// its field of view; the encoder finds the bow and every laser, codes exactly, and a damaged bow
// is corrupt. A spinning sensor's table has none.
#include <gtest/gtest.h>

#include <cmath>
#include <cstring>
#include <random>

#include "capz/error.h"
#include "coding/scan_geometry.h"
#include "coding/scan_shared.h"

namespace capz {
namespace {

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

scan::Header coded(const ScanGeometry& g, const ScanHints& h, std::vector<uint8_t>* p) {
  *p = encode_scan_geometry(g, h);
  const ScanGeometry back = decode_scan_geometry(p->data(), p->size(), "bow");
  EXPECT_EQ(back.counts, g.counts);
  EXPECT_EQ(back.valid, g.valid);
  EXPECT_EQ(back.q, g.q);
  return scan::read_header(p->data(), p->size(), "bow", 1u << 20);
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
  const size_t per_ring = hd.table.unit.empty() ? 0 : hd.table.offset[0] != 0 ? 16 : 8;
  const size_t bow_at = hd.body - 4, units_at = bow_at - per_ring * hd.table.rings() - 1;
  ASSERT_EQ(p[units_at] & scan::kBowBit, scan::kBowBit);
  const auto expect_corrupt = [](const std::vector<uint8_t>& d) {
    try {
      decode_scan_geometry(d.data(), d.size(), "damaged");
      ADD_FAILURE() << "decoded";
    } catch (const Error& e) {
      EXPECT_EQ(e.code(), ErrorCode::kCorrupt);
      EXPECT_NE(std::string(e.what()).find("damaged"), std::string::npos);
    }
  };
  for (uint8_t bit : {8, 16, 128}) {
    std::vector<uint8_t> d = p;
    d[units_at] = static_cast<uint8_t>(d[units_at] | bit);
    expect_corrupt(d);
  }
  for (float bad : {std::nanf(""), 1.5f, -2.0f, INFINITY}) {
    std::vector<uint8_t> d = p;
    std::memcpy(&d[bow_at], &bad, 4);  // little-endian hosts, as the library's tests
    expect_corrupt(d);
  }
}

}  // namespace
}  // namespace capz
