// A turning sensor's turns (docs/FORMAT.md "Turns"): the encoder finds how far each sweep
// turned, in the table's columns, and both sides read the previous sweep's map that far on.
#include <gtest/gtest.h>

#include <cmath>
#include <cstdint>
#include <random>
#include <vector>

#include "capz/error.h"
#include "coding/bytes.h"
#include "coding/scan_geometry.h"
#include "coding/scan_shared.h"
#include "coding/scan_trial_gates.h"
#include "scan_geometry_expect.h"

namespace capz {
namespace {

constexpr int kRings = 16, kColumns = 1800;  // 0.2 degree columns
constexpr double kTwoPi = 6.283185307179586;

// `frames` sweeps of a still scene by a sensor that turns `turn` columns a sweep: column c of
// sweep f looks along the scene's azimuth of column c + f turn. Each ring's range is a function
// of that azimuth (walls at their distances, by ring), 5 % of the points missing.
ScanGeometry turning_sweeps(int frames, int turn, ScanHints* h) {
  std::mt19937 rng(7);
  std::uniform_real_distribution<double> u(0, 1);
  ScanGeometry g;
  for (int f = 0; f < frames; ++f) {
    uint32_t n = 0;
    for (int c = 0; c < kColumns; ++c) {
      const double world = kTwoPi * (c + f * turn) / kColumns;
      for (int k = 0; k < kRings; ++k) {
        if (u(rng) < 0.05) continue;
        const double el = (-15.0 + 2.0 * k) * kTwoPi / 360;
        const double range = 12 + 4 * std::sin(3 * world) + 2 * std::sin(11 * world + k) +
                             0.5 * std::floor(8 * std::sin(29 * world));
        push_polar(&g, h, kTwoPi * c / kColumns, el, range, static_cast<uint32_t>(k));
        ++n;
      }
    }
    g.counts.push_back(n);
  }
  h->grid_per_unit = 500;
  return g;
}

// The offset of the more byte of a payload whose header ends with its turns (no raster or cells).
size_t more_at(const scan::Header& hd) {
  ByteWriter w;
  for (int32_t t : hd.turns) w.svarint(t);
  return hd.body - 1 - w.buffer().size();
}

TEST(ScanTurns, GivenSweepsOfATurningSensorThenEachFindsItsTurnAndCostsWhatAStillOneDoes) {
  ScanHints ht, hs;
  const ScanGeometry turned = turning_sweeps(4, 10, &ht), still = turning_sweeps(4, 0, &hs);
  const std::vector<uint8_t> p = coded_exact(turned, ht, "turned");
  const std::vector<uint8_t> q = coded_exact(still, hs, "still");
  const scan::Header a = payload_header(p), b = payload_header(q);
  ASSERT_GT(a.table.rings(), 0u);
  ASSERT_EQ(a.table.columns % kColumns, 0u);  // the step found, or a divisor of it
  const auto per = static_cast<int32_t>(a.table.columns / kColumns);
  EXPECT_EQ(a.turns, (std::vector<int32_t>{0, 10 * per, 10 * per, 10 * per}));
  EXPECT_TRUE(b.turns.empty());  // a still sensor's payload has none (its more byte 0)
  EXPECT_EQ(q[b.body - 1], 0);
  // The turned sweeps cost about what the still ones do (the map read where the scene was).
  EXPECT_LT(static_cast<double>(p.size()), 1.03 * static_cast<double>(q.size()));
}

TEST(ScanTurns, GivenTheTurnsTakenAwayThenTheDecoderPredictsOtherwise) {
  ScanHints h;
  const ScanGeometry g = turning_sweeps(3, 10, &h);
  const std::vector<uint8_t> p = coded_exact(g, h, "turned");
  const scan::Header hd = payload_header(p);
  ASSERT_EQ(hd.turns.size(), 3u);
  const size_t more = more_at(hd);
  ASSERT_EQ(p[more], scan::kMoreTurns);
  std::vector<uint8_t> d(p.begin(), p.begin() + static_cast<std::ptrdiff_t>(more));
  d.push_back(0);
  d.insert(d.end(), p.begin() + static_cast<std::ptrdiff_t>(hd.body), p.end());
  expect_decoded_otherwise(d, g);
}

TEST(ScanTurns, GivenDamagedTurnsOrMoreBitsThenCorrupt) {
  ScanHints h;
  const ScanGeometry g = turning_sweeps(3, 10, &h);
  const std::vector<uint8_t> p = coded_exact(g, h, "turned");
  const scan::Header hd = payload_header(p);
  const size_t more = more_at(hd);
  ASSERT_EQ(p[more], scan::kMoreTurns);
  for (uint8_t bit : {4, 128}) {  // bits 2-7 are not known
    std::vector<uint8_t> d = p;
    d[more] = static_cast<uint8_t>(d[more] | bit);
    expect_scan_corrupt(d);
  }
  // A whole turn, |t_f| = C, in place of frame 2's turn.
  ByteWriter w;
  w.u8(scan::kMoreTurns);
  w.svarint(hd.turns[0]);
  w.svarint(hd.turns[1]);
  w.svarint(-static_cast<int64_t>(hd.table.columns));
  std::vector<uint8_t> d(p.begin(), p.begin() + static_cast<std::ptrdiff_t>(more));
  d.insert(d.end(), w.buffer().begin(), w.buffer().end());
  d.insert(d.end(), p.begin() + static_cast<std::ptrdiff_t>(hd.body), p.end());
  expect_scan_corrupt(d);
  d.assign(p.begin(), p.begin() + static_cast<std::ptrdiff_t>(more + 2));  // cut in the turns
  expect_scan_corrupt(d);
}

// The encoder's search for a turn scores a bounded number of shifts however many columns a
// fitted table has: a table of 2^22 columns whose step is tiny (points fitted by chance) reaches
// 2^21 columns either way, and a search of every column within one coarse step of the best
// scored 2^17 shifts of 1,024 points. A sensor's table (below) still has every shift near the
// coarse best scored.
TEST(ScanTurns, GivenAFittedTableOfManyTinyColumnsThenTheSearchScoresFewShifts) {
  ScanGeometry g;
  std::vector<scan::Polar> polar;
  for (uint32_t i = 0; i < 4096; ++i) {
    g.valid.push_back(1);
    polar.push_back({0, static_cast<int32_t>(i * 1000), 5000});
  }
  g.counts.push_back(4096);
  // The shifts scored (besides 0) under a one-ring table of `columns` columns of `step` radians.
  auto scored_under = [&](uint32_t columns, float step) {
    scan::Table t;
    t.azimuth0 = {0};
    t.slope = {0};
    t.z0 = {0};
    t.columns = columns;
    t.step = step;
    scan::State st(t);
    size_t scored = 0;
    EXPECT_EQ(find_turn(g, polar, st, 0, 4096, &scored), 0);  // (no previous sweep to match)
    return scored;
  };
  const size_t tiny = scored_under(1u << 22, 1e-8f);
  EXPECT_GT(tiny, 64u);
  EXPECT_LT(tiny, 600u);
  // 1,800 columns of 0.2 degrees: 6 degrees is 30 columns, one coarse step a column, so the
  // coarse search is all of them (60 shifts) and no finer level runs.
  EXPECT_EQ(scored_under(1800, static_cast<float>(kTwoPi / 1800)), 60u);
  // 36,000 columns: 600 columns, coarse steps of 19 (62 shifts), then the 36 around the best.
  EXPECT_EQ(scored_under(36000, static_cast<float>(kTwoPi / 36000)), 62u + 36u);
}

}  // namespace
}  // namespace capz
