// The scan payload's ring pair frames (docs/FORMAT.md "Scan geometry payload", "Ring pair
// frames", flags_f bit 7): a sweep written in a driver's own ring order, its rings' columns
// apart by ring, codes its rings and columns in fewer bits with them; the encoder finds them
// there and not on a sweep in firing order; any order round-trips; damaged flags are corrupt.
#include <gtest/gtest.h>

#include <algorithm>
#include <cmath>
#include <random>

#include "capz/error.h"
#include "coding/scan_geometry.h"
#include "coding/scan_shared.h"
#include "coding/scan_table.h"
#include "scan_geometry_expect.h"

namespace capz {
namespace {

constexpr int kRings = 16;

// One sweep of a 16-ring sensor on the 2 mm grid: each firing's rings written in `order`, ring
// k's azimuth off the firing's by offset[k] columns (odd rings 40 columns behind, as the
// RoboSense Helios' two banks), the firings 1 or 2 columns apart at random, 2 % of the returns
// missing.
ScanGeometry driver_order(const std::vector<uint32_t>& order, ScanHints* h, bool apart = true) {
  std::mt19937 rng(37);
  std::uniform_real_distribution<double> u(0, 1);
  const double step = 0.0035;
  ScanGeometry g;
  uint32_t n = 0;
  int column = 0;
  for (int c = 0; c < 900; ++c) {
    column += u(rng) < 0.3 ? 2 : 1;
    for (uint32_t k : order) {
      if (u(rng) < 0.02) continue;
      const int offset = apart ? (k % 2 ? -40 : 0) + 3 * static_cast<int>(k % 3) : 0;
      const double az = step * (column + offset) + 0.0002 * k;
      const double el = -0.25 + 0.03 * k;
      const double range = 9 + 2 * std::sin(2 * az) + std::cos(3 * az + k) + 0.01 * u(rng);
      const double rho = range * std::cos(el);
      const double p[3] = {rho * std::cos(az), rho * std::sin(az), range * std::sin(el)};
      push_point(&g, h, p, k);
      ++n;
    }
  }
  g.counts.push_back(n);
  return g;
}

// The rings of a firing descending, as the Helios writes them.
std::vector<uint32_t> descending() {
  std::vector<uint32_t> o;
  for (int k = kRings - 1; k >= 0; --k) o.push_back(static_cast<uint32_t>(k));
  return o;
}

// g's one frame coded spherically, with or without ring pairs: the payload, and (*ring_column)
// the ring and column bytes.
std::vector<uint8_t> payload(const ScanGeometry& g, const ScanHints& h, bool pairs,
                             size_t* ring_column = nullptr) {
  size_t rc = 0;
  const std::vector<uint8_t> p = one_frame_payload(
      g, h,
      static_cast<uint8_t>(scan::kSomeValid | scan::kSpherical | (pairs ? scan::kRingPairs : 0)),
      &rc);
  if (ring_column) *ring_column = rc;
  return p;
}

uint8_t frame_flags(const std::vector<uint8_t>& p) {
  return scan::read_header(p.data(), p.size(), "pairs", 1u << 20).flags.at(0);
}

TEST(ScanPairs, GivenRingsInADriversOrderWithColumnsApartByRingThenPairsCodeFewerBits) {
  // Against the previous point's column every point pays its ring's offset; against the ring's
  // last column plus its step every firing 2 columns on pays; the pair's step is exact within
  // a firing. Measured (2026-12-01): ring and column 1218 bytes with pairs against 3296, the
  // payload 14049 against 16128.
  ScanHints h;
  const ScanGeometry g = driver_order(descending(), &h);
  size_t rp = 0, rs = 0;
  const std::vector<uint8_t> pp = payload(g, h, true, &rp), ps = payload(g, h, false, &rs);
  expect_same(g, decode_scan_geometry(pp.data(), pp.size(), "pairs"));
  expect_same(g, decode_scan_geometry(ps.data(), ps.size(), "successor"));
  EXPECT_LT(pp.size() * 100, ps.size() * 95) << "pairs " << pp.size() << ", without " << ps.size();
  EXPECT_LT(rp * 2, rs) << "ring and column bytes: pairs " << rp << ", without " << rs;
  // The encoder codes it as small: these rings run from the top down, one firing after another,
  // so it numbers its table from the top and walks the rings (scan::flip_rings): 13314 bytes
  // against 14049 with pairs.
  const std::vector<uint8_t> p = encode_scan_geometry(g, h);
  EXPECT_EQ(frame_flags(p) & scan::kRingWalk, scan::kRingWalk);
  EXPECT_LE(p.size(), pp.size()) << "encoded " << p.size() << ", pairs " << pp.size();
  expect_same(g, decode_scan_geometry(p.data(), p.size(), "encoded"));
  // Rings fired in an order of their own (0, 8, 1, 9, ...: neither up nor down the table): the
  // encoder finds the pairs.
  std::vector<uint32_t> own;
  for (uint32_t k = 0; k < kRings / 2; ++k) own.insert(own.end(), {k, k + kRings / 2});
  ScanHints ho;
  const ScanGeometry go = driver_order(own, &ho);
  const std::vector<uint8_t> po = encode_scan_geometry(go, ho);
  EXPECT_EQ(frame_flags(po) & scan::kRingPairs, scan::kRingPairs);
  EXPECT_LE(po.size(), payload(go, ho, true).size());
  expect_same(go, decode_scan_geometry(po.data(), po.size(), "own order"));
}

TEST(ScanPairs, GivenFiringOrderWithOneColumnAFiringThenTheEncoderKeepsTheSuccessor) {
  // The previous point's column is exact within a firing: no trial, no bit 7.
  std::vector<uint32_t> order = descending();
  std::reverse(order.begin(), order.end());
  ScanHints h;
  const ScanGeometry g = driver_order(order, &h, false);
  const std::vector<uint8_t> p = encode_scan_geometry(g, h);
  EXPECT_EQ(frame_flags(p) & scan::kRingPairs, 0);
  expect_same(g, decode_scan_geometry(p.data(), p.size(), "encoded"));
}

TEST(ScanPairs, GivenAShuffledSweepWhenCodedWithPairsThenExact) {
  ScanHints h;
  ScanGeometry g = driver_order(descending(), &h);
  std::mt19937 rng(5);
  for (size_t i = g.total() - 1; i > 0; --i) {
    const size_t j = rng() % (i + 1);
    for (int a = 0; a < 3; ++a) std::swap(g.q[3 * i + a], g.q[3 * j + a]);
    std::swap(h.ring[i], h.ring[j]);
    for (int a = 0; a < 3; ++a) std::swap(h.xyz[3 * i + a], h.xyz[3 * j + a]);
  }
  const std::vector<uint8_t> p = payload(g, h, true);
  expect_same(g, decode_scan_geometry(p.data(), p.size(), "shuffled"));
}

TEST(ScanPairs, GivenDamagedPairFramesWhenDecodedThenCorrupt) {
  ScanHints h;
  const ScanGeometry g = driver_order(descending(), &h);
  const std::vector<uint8_t> p = payload(g, h, true);
  const scan::Header hd = scan::read_header(p.data(), p.size(), "pairs", 1u << 20);
  size_t at = 1;  // the flags byte, after varints F and n
  while (p[at] & 0x80) ++at;
  ++at;
  ASSERT_LT(at, hd.body);
  ASSERT_EQ(p[at], scan::kSomeValid | scan::kSpherical | scan::kRingPairs);
  for (uint8_t bad :
       {uint8_t{scan::kSomeValid | scan::kRingPairs},
        uint8_t{scan::kSomeValid | scan::kSpherical | scan::kRingPairs | scan::kRingWalk},
        uint8_t{scan::kSomeValid | scan::kRaster | scan::kRingPairs}}) {
    std::vector<uint8_t> d = p;
    d[at] = bad;
    expect_scan_corrupt(d);
  }
  // Cuts and flips of the block decode or are corrupt, never more.
  std::mt19937 rng(11);
  for (int t = 0; t < 60; ++t) {
    std::vector<uint8_t> d = p;
    if (t % 2)
      d.resize(hd.body + rng() % (d.size() - hd.body));
    else
      d[hd.body + rng() % (d.size() - hd.body)] ^= static_cast<uint8_t>(1 + rng() % 255);
    try {
      const ScanGeometry r = decode_scan_geometry(d.data(), d.size(), "damaged", 1 << 20);
      EXPECT_EQ(r.valid.size(), r.total());
    } catch (const Error& e) {
      EXPECT_EQ(e.code(), ErrorCode::kCorrupt);
    }
  }
}

}  // namespace
}  // namespace capz
