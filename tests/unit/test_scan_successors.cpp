// The previous sweep's successors (docs/FORMAT.md, the more byte's bit 1): in ring pair frames,
// the ring that followed the previous point's cell in the sweep before is the first candidate.
#include <gtest/gtest.h>

#include <cmath>
#include <cstdint>
#include <random>
#include <string>
#include <vector>

#include "coding/scan_geometry.h"
#include "coding/scan_shared.h"
#include "scan_geometry_expect.h"

namespace capz {
namespace {

// Laser s of a firing is ring kOrder[s]: a driver's order of its own (the Pandar64 writes its
// firings so), each a column apart by its ring's azimuth offset.
constexpr int kLasers = 16;
constexpr int kOrder[kLasers] = {7, 0, 8, 1, 9, 2, 10, 3, 11, 4, 12, 5, 13, 6, 14, 15};

// `frames` sweeps of that sensor, 1,800 firings a turn at fixed azimuths (0.2 degrees apart), 5 %
// of the returns missing at random in each sweep, ranges of a still scene with 1 mm of noise.
ScanGeometry shuffled_sweeps(int frames, ScanHints* h) {
  std::mt19937 rng(5);
  std::uniform_real_distribution<double> u(0, 1);
  ScanGeometry g;
  for (int f = 0; f < frames; ++f) {
    uint32_t n = 0;
    for (int c = 0; c < 1800; ++c)
      for (int s = 0; s < kLasers; ++s) {
        if (u(rng) < 0.05) continue;
        const int k = kOrder[s];
        const double az = (0.2 * c + 0.05 * k) * 3.141592653589793 / 180;
        const double range = 8 + 2 * std::sin(3 * az) + 0.5 * std::cos(7 * az + k) + 0.001 * u(rng);
        push_polar(&g, h, az, (-15.0 + 2.0 * k) * 3.141592653589793 / 180, range,
                   static_cast<uint32_t>(k));
        ++n;
      }
    g.counts.push_back(n);
  }
  h->grid_per_unit = 500;
  return g;
}

TEST(ScanSuccessors, GivenSweepsOfADriversOwnRingOrderThenThePreviousSweepsSuccessorsAreUsed) {
  ScanHints h;
  const ScanGeometry g = shuffled_sweeps(3, &h);
  const std::vector<uint8_t> p = coded_exact(g, h, "shuffled");
  const scan::Header hd = payload_header(p);
  ASSERT_GT(hd.table.rings(), 0u);
  EXPECT_TRUE(hd.table.successors);
  size_t pairs = 0;
  for (uint8_t f : hd.flags) pairs += (f & scan::kRingPairs) != 0;
  EXPECT_EQ(pairs, 3u);
  // The more byte ends the header here (no turns, raster or cells): without its bit 1 the
  // decoder takes other rings.
  ASSERT_EQ(p[hd.body - 1], scan::kMoreSuccessors);
  std::vector<uint8_t> d = p;
  d[hd.body - 1] = 0;
  expect_decoded_otherwise(d, g);
  // (The encoder keeps the bit only where it makes the payload smaller.) One sweep alone has no
  // sweep before it: the bit is not written.
  ScanHints h1;
  const ScanGeometry one = shuffled_sweeps(1, &h1);
  EXPECT_FALSE(payload_header(coded_exact(one, h1, "one sweep")).table.successors);
}

}  // namespace
}  // namespace capz
