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

constexpr double kQuantum = kQuantum001;

// One sweep (quantum_sweep) of a 32-ring sensor as a Velodyne driver writes it: each laser's
// azimuth the firing's plus a fixed offset and its share of the turn (its firing time),
// rounded to the quantum.
ScanGeometry sweep(ScanHints* h) {
  const int rings = 32;
  const auto none = [](int, int, const auto&) { return 0; };
  const auto slot = [&](int k, int64_t a, int turn, int) {
    const int64_t quanta = a + (k * 37) % 300 - 150 + std::lround(turn * k / 40.0);
    const double az = static_cast<double>(quanta) * kQuantum;
    return SweepLaser{static_cast<uint32_t>(k), quanta, -0.4 + 0.5 * k / rings,
                      12 + 3 * std::sin(2 * az) + std::cos(7 * az + k)};
  };
  return quantum_sweep(h, 5, rings, 0.03, none, slot);
}

std::vector<uint8_t> coded(const ScanGeometry& g, const ScanHints& h) {
  return coded_exact(g, h, "turn");
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
  expect_decoded_otherwise(p, g);
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
