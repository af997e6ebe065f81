// Columns on the sensor's azimuth quantum and the column's third candidate, the firing's turn
// (docs/FORMAT.md "Scan geometry payload", `units` bit 4): a sweep whose azimuths sit on
// 0.01 degree is coded under that quantum's table, exactly and smaller than when the encoder
// cannot see the quantum; damaged tables are corrupt.
#include <gtest/gtest.h>

#include <cmath>
#include <random>

#include "capz/error.h"
#include "coding/scan_geometry.h"
#include "coding/scan_shared.h"
#include "scan_geometry_expect.h"

namespace capz {
namespace {

constexpr double kQuantum = 0.01 * 3.141592653589793 / 180;  // 0.01 degree in radians

// One sweep of a spinning sensor on a 1 mm grid (step 0.002 m) in firing order, ranges on a
// 4 mm step, as a Velodyne driver writes it: a firing's azimuth on the quantum, turning 19 to 21
// quanta a firing, and each laser's azimuth that plus a fixed offset and its share of the turn
// (its firing time), rounded to the quantum; the ranges also as a distance field.
ScanGeometry sweep(ScanHints* h) {
  std::mt19937 rng(5);
  std::uniform_real_distribution<double> u(0, 1);
  ScanGeometry g;
  const int rings = 32;
  uint32_t n = 0;
  int64_t a = 0;
  for (int f = 0; a < 36000; ++f) {
    const int turn = 19 + static_cast<int>(u(rng) * 3);
    a += turn;
    for (int k = 0; k < rings; ++k) {
      if (u(rng) < 0.03) continue;
      const int64_t quanta = a + (k * 37) % 300 - 150 + std::lround(turn * k / 40.0);
      const double az = static_cast<double>(quanta) * kQuantum;
      const double el = -0.4 + 0.5 * k / rings;
      push_polar(&g, h, az, el, 12 + 3 * std::sin(2 * az) + std::cos(7 * az + k) + 0.004 * u(rng),
                 static_cast<uint32_t>(k));
      ++n;
    }
  }
  g.counts.push_back(n);
  h->grid_per_unit = 500;
  return g;
}

std::vector<uint8_t> coded(const ScanGeometry& g, const ScanHints& h) {
  const std::vector<uint8_t> p = encode_scan_geometry(g, h);
  expect_same(g, decode_scan_geometry(p.data(), p.size(), "turn"));
  return p;
}

// The offset of the laser table's `units` byte.
size_t units_at(const std::vector<uint8_t>& p) {
  return units_offset(p);
}

TEST(ScanTurn, GivenAzimuthsOnTheQuantumThenItsTableWithTheTurnExactAndSmaller) {
  ScanHints h;
  const ScanGeometry g = sweep(&h);
  // The same integers, the source's azimuths (which the encoder's inference reads) turned off
  // the quantum by up to 0.3 of it, their ranges kept.
  ScanHints without = h;
  std::mt19937 rng(7);
  std::uniform_real_distribution<double> u(-0.3, 0.3);
  for (size_t i = 0; i < g.total(); ++i) {
    const double x = h.xyz[3 * i], y = h.xyz[3 * i + 1], t = u(rng) * kQuantum;
    without.xyz[3 * i] = static_cast<float>(x * std::cos(t) - y * std::sin(t));
    without.xyz[3 * i + 1] = static_cast<float>(x * std::sin(t) + y * std::cos(t));
  }
  const std::vector<uint8_t> on = coded(g, h), plain = coded(g, without);
  const scan::Header hd = scan::read_header(on.data(), on.size(), "turn", 1u << 22);
  EXPECT_TRUE(hd.table.turn);
  EXPECT_NEAR(hd.table.step, kQuantum, 1e-9);
  EXPECT_EQ(on[units_at(on)] & ~scan::kPackBit, 1 | scan::kTurnBit);
  EXPECT_FALSE(scan::read_header(plain.data(), plain.size(), "off", 1u << 22).table.turn);
  EXPECT_EQ(scan::read_header(plain.data(), plain.size(), "off", 1u << 22).table.unit.size(),
            hd.table.rings());  // both count the range's 4 mm steps
  EXPECT_LT(static_cast<double>(on.size()), 0.85 * static_cast<double>(plain.size()));
}

TEST(ScanTurn, GivenTheTurnBitClearedThenTheDecoderPredictsOtherwise) {
  ScanHints h;
  const ScanGeometry g = sweep(&h);
  std::vector<uint8_t> p = coded(g, h);
  p[units_at(p)] &= static_cast<uint8_t>(~scan::kTurnBit);
  try {
    const ScanGeometry back = decode_scan_geometry(p.data(), p.size(), "damaged");
    EXPECT_NE(back.q, g.q);
  } catch (const Error& e) {
    EXPECT_EQ(e.code(), ErrorCode::kCorrupt);
  }
}

TEST(ScanTurn, GivenDamagedUnitsOrBlockThenCorrupt) {
  ScanHints h;
  const ScanGeometry g = sweep(&h);
  const std::vector<uint8_t> p = coded(g, h);
  const size_t at = units_at(p);
  for (uint8_t bit : {64, 128}) {  // (bit 3: test_scan_shares.cpp; 5: test_scan_pack.cpp)
    std::vector<uint8_t> d = p;
    d[at] = static_cast<uint8_t>(d[at] | bit);
    expect_scan_corrupt(d);
  }
  expect_scan_corrupt(std::vector<uint8_t>(p.begin(), p.end() - 40));  // the block cut short
}

}  // namespace
}  // namespace capz
