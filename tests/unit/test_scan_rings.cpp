// Which rings the scan encoder codes with (src/coding/scan_encode.cpp): a ring field, or the
// rings it finds from the points' elevations when those code smaller; and the range's fourth
// candidate (FORMAT.md "Scan geometry payload", units bit 7), the ring's range before its last,
// for a sensor in dual-return mode. The RoboSense Helios 16P's
// near points, seen from the origin 35 mm off its optical centre, leave their laser's cone by
// their range, and the rings from the elevations (a laser split by range) code its sweeps in
// about 0.78x the bytes (docs/lab/2026-11-29-helios-at128.md).
#include <gtest/gtest.h>

#include <cmath>
#include <cstring>
#include <random>

#include "capz/error.h"
#include "coding/scan_geometry.h"
#include "scan_geometry_expect.h"

namespace capz {
namespace {

// Four sweeps of a still 16-laser sensor in dual-return mode, on a 1 mm grid, as the Helios
// 16P's driver writes them: each firing (0.2 degree apart) as two blocks, the first returns (a
// near surface, 0.25 to 0.45 m) then the last ones (a far wall, 1.5 to 2.5 m) at 0.1 degree on,
// so that a laser's points alternate between the two. With `offset` each point is its distance
// (on 2.5 mm, the distance field) along its laser from a centre `offset` metres off the axis that
// turns with the sweep: seen from the origin a near point then leaves its laser's cone.
ScanGeometry dual_returns(double offset, ScanHints* h, int firings = 1800) {
  std::mt19937 rng(5);
  std::uniform_real_distribution<double> u(0, 1);
  const int rings = 16;
  ScanGeometry g;
  for (int f = 0; f < 4; ++f) {
    uint32_t n = 0;
    for (int c = 0; c < 2 * firings; ++c) {
      const double hb = 3.141592653589793 * c / firings;  // the block's azimuth
      const bool last = c % 2 == 1;
      for (int k = 0; k < rings; ++k) {
        const double el = -0.26 + 0.45 * k / rings;
        const double at = 0.35 + 0.1 * std::sin(3 * hb + 0.3 * k), far = 2 + 0.5 * std::sin(2 * hb);
        const double d =
            0.0025 * std::floor(((last ? far : at) + 0.004 * (u(rng) - 0.5)) / 0.0025 + 0.5);
        const double p[3] = {d * std::cos(el) * std::cos(hb) + offset * std::cos(hb - 0.07),
                             d * std::cos(el) * std::sin(hb) + offset * std::sin(hb - 0.07),
                             d * std::sin(el)};
        push_point(&g, h, p, static_cast<uint32_t>(k));
        h->distance.push_back(static_cast<float>(d));
        ++n;
      }
    }
    g.counts.push_back(n);
  }
  h->grid_per_unit = 500;
  return g;
}

void expect_exact(const ScanGeometry& g, const std::vector<uint8_t>& p) {
  expect_same(g, decode_scan_geometry(p.data(), p.size(), "rings"));
}

TEST(ScanRings, GivenDualReturnsOffTheOriginThenTheElevationsRings) {
  ScanHints h;
  const ScanGeometry g = dual_returns(0.035, &h);
  EXPECT_TRUE(scan_rings_differ(g, h));
  const std::vector<uint8_t> field = encode_scan_geometry(g, h);
  expect_exact(g, field);
  ScanHints none = h;
  none.ring.clear();
  const std::vector<uint8_t> elevations = encode_scan_geometry(g, none);
  expect_exact(g, elevations);
  // The ring field's own rings (16) would cost more here: the payload is the elevations' one.
  EXPECT_EQ(field, elevations);
  EXPECT_GT(scan::read_header(field.data(), field.size(), "rings", 1u << 22).table.rings(), 16u);
}

// A sequence's windows (ScanWorkspace::remember) keep the second rings' payload over the first's;
// after a window where the elevations' rings lost by more than 2 %, up to 7 windows in a row code
// the ring field's alone, then both again.
TEST(ScanRings, GivenASequenceWhereTheElevationsRingsLostThenTheyAreSkippedAWhile) {
  ScanHints h;
  const ScanGeometry g = dual_returns(0.035, &h, 300);
  ScanWorkspace ws;
  ws.remember = true;
  const std::vector<uint8_t> both = encode_scan_geometry(g, h, &ws);
  ASSERT_GT(ws.second_ratio, 0.0);
  EXPECT_LT(ws.second_ratio, 1.0);  // the elevations' rings won here
  EXPECT_EQ(encode_scan_geometry(g, h, &ws).size(), both.size());
  EXPECT_EQ(ws.second_skipped, 0u);
  ws.second_ratio = 1.05;  // as if they had lost by 5 %
  size_t skipped = 0;
  for (int w = 0; w < 10 && ws.second_skipped == skipped; ++w) {
    const size_t coded = ws.tables_coded;
    const std::vector<uint8_t> p = encode_scan_geometry(g, h, &ws);
    expect_exact(g, p);
    if (ws.second_skipped == 0) break;  // both coded again
    ++skipped;
    EXPECT_GT(p.size(), both.size());  // the ring field's rings alone
    EXPECT_EQ(ws.tables_coded, coded + 1);
  }
  EXPECT_EQ(skipped, 7u);
  EXPECT_EQ(ws.second_skipped, 0u);
  EXPECT_LT(ws.second_ratio, 1.0);
}

TEST(ScanRings, GivenLasersOnTheOriginThenTheRingFieldsRingsKept) {
  ScanHints h;
  const ScanGeometry g = dual_returns(0, &h);
  EXPECT_FALSE(scan_rings_differ(g, h));  // the elevations find the same 16 lasers
  const std::vector<uint8_t> field = encode_scan_geometry(g, h);
  expect_exact(g, field);
  EXPECT_EQ(scan::read_header(field.data(), field.size(), "rings", 1u << 22).table.rings(), 16u);
}

// Its alternating returns: each laser's range one firing back is the same return's. The encoder
// sets units bit 7, the payload decodes exactly, and without the bit it decodes to other points
// (the decoder reads it).
TEST(ScanRings, GivenDualReturnsThenTheRangeBeforeTheLastIsACandidate) {
  ScanHints h;
  const ScanGeometry g = dual_returns(0, &h);
  const std::vector<uint8_t> p = encode_scan_geometry(g, h);
  expect_exact(g, p);
  const scan::Header hd = scan::read_header(p.data(), p.size(), "rings", 1u << 22);
  EXPECT_TRUE(hd.table.before);
  const size_t at = units_offset(p);
  ASSERT_NE(p[at] & scan::kBeforeBit, 0);
  std::vector<uint8_t> d = p;
  d[at] = static_cast<uint8_t>(d[at] & ~scan::kBeforeBit);
  try {
    const ScanGeometry back = decode_scan_geometry(d.data(), d.size(), "damaged");
    EXPECT_NE(back.q, g.q);
  } catch (const Error& e) {
    EXPECT_EQ(e.code(), ErrorCode::kCorrupt);
  }
  // A payload cut anywhere is corrupt.
  for (size_t n : {at + 1, hd.body, hd.body + 16, p.size() / 2, p.size() - 1})
    expect_scan_corrupt(
        std::vector<uint8_t>(p.begin(), p.begin() + static_cast<std::ptrdiff_t>(n)));
}

}  // namespace
}  // namespace capz
