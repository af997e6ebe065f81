// Range units of the scan geometry payload (docs/FORMAT.md "Scan geometry payload"): a sensor
// whose ranges count whole steps is coded in those steps, exactly, and smaller; damaged units
// are corrupt.
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

// A spinning sensor's sweeps on a 1 mm grid (step 0.002 m), ranges in whole steps of
// `range_step` metres (0: any range) measured from the origin, or with `offset` from a centre
// that far off the axis (the RoboSense Helios 16P's optics), given as a distance field.
ScanGeometry sweeps(double range_step, ScanHints* h, double offset = 0) {
  std::mt19937 rng(11);
  std::uniform_real_distribution<double> u(0, 1);
  ScanGeometry g;
  const int rings = 16, firings = 1200;
  for (int f = 0; f < 2; ++f) {
    uint32_t n = 0;
    for (int c = 0; c < firings; ++c) {
      const double az = 6.283185307179586 * c / firings;
      for (int k = 0; k < rings; ++k) {
        if (u(rng) < 0.05) continue;
        const double el = -0.26 + 0.4 * k / rings;
        double range = 6 + 3 * std::sin(3 * az) + std::cos(5 * az + k) + 0.05 * u(rng);
        if (range_step > 0) range = range_step * std::floor(range / range_step + 0.5);
        const double rho = range * std::cos(el) + offset;
        const double p[3] = {rho * std::cos(az), rho * std::sin(az), range * std::sin(el)};
        if (offset != 0) h->distance.push_back(static_cast<float>(range));
        push_point(&g, h, p, static_cast<uint32_t>(k));
        ++n;
      }
    }
    g.counts.push_back(n);
  }
  h->grid_per_unit = 500;
  return g;
}

void expect_exact(const ScanGeometry& g, const std::vector<uint8_t>& p) {
  const ScanGeometry back = decode_scan_geometry(p.data(), p.size(), "units");
  ASSERT_EQ(back.counts, g.counts);
  ASSERT_EQ(back.valid, g.valid);
  ASSERT_EQ(back.q, g.q);
}

TEST(ScanUnits, GivenRangesInWholeStepsWhenCodedThenInStepsExactAndSmaller) {
  ScanHints h;
  const ScanGeometry g = sweeps(0.004, &h);
  const std::vector<uint8_t> with = encode_scan_geometry(g, h);
  expect_exact(g, with);
  const scan::Header hd = scan::read_header(with.data(), with.size(), "units", 1u << 20);
  ASSERT_EQ(hd.table.unit.size(), hd.table.rings());
  ASSERT_GT(hd.table.rings(), 0u);
  for (double u : hd.table.unit) EXPECT_NEAR(u, 2.0, 0.3);  // 4 mm in 2 mm grid units, cos(el)
  ScanHints without = h;
  without.grid_per_unit = 0;  // the encoder cannot look for a step
  const std::vector<uint8_t> plain = encode_scan_geometry(g, without);
  expect_exact(g, plain);
  EXPECT_TRUE(scan::read_header(plain.data(), plain.size(), "plain", 1u << 20).table.unit.empty());
  EXPECT_LT(static_cast<double>(with.size()), 0.9 * static_cast<double>(plain.size()));
}

TEST(ScanUnits, GivenADistanceFieldFromAnOffsetCentreThenUnitsWithOffsets) {
  ScanHints h;
  const ScanGeometry g = sweeps(0.0025, &h, 0.035);
  const std::vector<uint8_t> with = encode_scan_geometry(g, h);
  expect_exact(g, with);
  const scan::Header hd = scan::read_header(with.data(), with.size(), "offsets", 1u << 20);
  ASSERT_EQ(hd.table.offset.size(), hd.table.rings());
  ASSERT_GT(hd.table.rings(), 0u);
  EXPECT_EQ(with[units_offset(with)] & 3, 2);                  // units 2: u_k and v_k
  for (double v : hd.table.offset) EXPECT_NEAR(v, 17.5, 0.5);  // 35 mm in 2 mm grid units
  ScanHints without = h;
  without.grid_per_unit = 0;  // the encoder cannot look for a step
  const std::vector<uint8_t> plain = encode_scan_geometry(g, without);
  expect_exact(g, plain);
  EXPECT_TRUE(scan::read_header(plain.data(), plain.size(), "plain", 1u << 20).table.unit.empty());
  EXPECT_LT(with.size(), plain.size());
}

// Without the distance field (a .bin or PLY of the same sweeps) the distances from the origin sit
// on the steps only less each ring's own offset (about 35 mm cos(el)): the encoder finds the step
// and the rings' offsets all the same (units 2), nearly as small as with the field.
TEST(ScanUnits, GivenNoDistanceFieldFromAnOffsetCentreThenUnitsWithRingOffsets) {
  ScanHints h;
  const ScanGeometry g = sweeps(0.0025, &h, 0.035);
  const std::vector<uint8_t> field = encode_scan_geometry(g, h);
  h.distance.clear();
  const std::vector<uint8_t> with = encode_scan_geometry(g, h);
  expect_exact(g, with);
  const scan::Header hd = scan::read_header(with.data(), with.size(), "rings", 1u << 20);
  ASSERT_EQ(hd.table.offset.size(), hd.table.rings());
  ASSERT_GT(hd.table.rings(), 0u);
  EXPECT_EQ(with[units_offset(with)] & 3, 2);                // units 2: u_k and v_k
  for (double u : hd.table.unit) EXPECT_NEAR(u, 1.25, 0.1);  // 2.5 mm in 2 mm grid units, cos(el)
  ScanHints without = h;
  without.grid_per_unit = 0;
  const std::vector<uint8_t> plain = encode_scan_geometry(g, without);
  expect_exact(g, plain);
  EXPECT_LT(static_cast<double>(with.size()), 0.9 * static_cast<double>(plain.size()));
  EXPECT_LT(static_cast<double>(with.size()), 1.02 * static_cast<double>(field.size()));
}

TEST(ScanUnits, GivenRangesOffAnyStepThenGridUnits) {
  ScanHints h;
  const ScanGeometry g = sweeps(0, &h);
  const std::vector<uint8_t> p = encode_scan_geometry(g, h);
  expect_exact(g, p);
  EXPECT_TRUE(scan::read_header(p.data(), p.size(), "off", 1u << 20).table.unit.empty());
}

TEST(ScanUnits, GivenDamagedUnitsWhenDecodedThenCorrupt) {
  ScanHints h;
  const ScanGeometry g = sweeps(0.004, &h);
  const std::vector<uint8_t> p = unpacked(encode_scan_geometry(g, h));  // the plain table
  expect_exact(g, p);
  const scan::Header hd = scan::read_header(p.data(), p.size(), "units", 1u << 20);
  const size_t units_at = units_offset(p);
  ASSERT_EQ(p[units_at], 1);  // through the origin: u_k alone
  std::vector<uint8_t> d = p;
  d[units_at] = 3;
  expect_scan_corrupt(d);
  for (double bad : {0.0, -1.0, 0x1p-21, 0x1p21, std::nan("")}) {
    d = p;
    std::memcpy(&d[units_at + 1 + 12 * hd.table.rings()], &bad, 8);  // little-endian hosts
    expect_scan_corrupt(d);
  }
}

}  // namespace
}  // namespace capz
