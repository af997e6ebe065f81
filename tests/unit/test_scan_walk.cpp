// The scan payload's ring walk frames (docs/FORMAT.md "Scan geometry payload", "Ring walk
// frames", flags_f bit 3): points in firing order code their ring and column in fewer bits than
// against the ring's successor, the encoder chooses the walk only where it pays, every order
// round-trips exactly, and damaged walk frames are corrupt.
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

// One sweep of a 32-ring sensor on a 1 mm grid in firing order (column after column, the rings
// of a column ascending, as --point-order any sorts them): the upper rings see no return over
// half the turn (sky), ring 5 returns twice in every firing (dual returns, the second farther),
// and 3 % of the other returns are missing at random. `order` permutes the rings within a
// firing (empty: ascending).
ScanGeometry firing_order(const std::vector<uint32_t>& order, ScanHints* h) {
  std::mt19937 rng(21);
  std::uniform_real_distribution<double> u(0, 1);
  ScanGeometry g;
  const int rings = 32, firings = 1000;
  uint32_t n = 0;
  for (int c = 0; c < firings; ++c) {
    const double az = 6.283185307179586 * c / firings;
    for (int i = 0; i < rings; ++i) {
      const int k = order.empty() ? i : static_cast<int>(order[static_cast<size_t>(i)]);
      if (k >= 20 && c < firings / 2) continue;  // sky
      if (k != 5 && u(rng) < 0.03) continue;
      for (int ret = 0; ret < (k == 5 ? 2 : 1); ++ret) {
        const double el = -0.3 + 0.5 * k / rings;
        const double range = 7 + 2 * std::sin(2 * az) + std::cos(5 * az + k) + 0.02 * u(rng) + ret;
        const double rho = range * std::cos(el);
        const double p[3] = {rho * std::cos(az), rho * std::sin(az), range * std::sin(el)};
        push_point(&g, h, p, static_cast<uint32_t>(k));
        ++n;
      }
    }
  }
  g.counts.push_back(n);
  return g;
}

// g's one frame coded spherically, with or without the ring walk: the payload, and the ring and
// column bytes.
std::vector<uint8_t> payload(const ScanGeometry& g, const ScanHints& h, bool walk,
                             size_t* ring_column) {
  return one_frame_payload(
      g, h, static_cast<uint8_t>(scan::kAllValid | scan::kSpherical | (walk ? scan::kRingWalk : 0)),
      ring_column);
}

uint8_t frame_flags(const std::vector<uint8_t>& p) {
  return scan::read_header(p.data(), p.size(), "walk", 1u << 20).flags.at(0);
}

TEST(ScanWalk, GivenFiringOrderWithSkyAndDualReturnsThenTheWalkCodesRingsInFarFewerBits) {
  // Against the successor the ring pays at every gap and every second return (a residual of
  // K - 1 or a skip); the walk knows which rings returned in the previous firing and which
  // returned twice. Measured: ring and column 0.32 bits a point with the walk against 0.89.
  ScanHints h;
  const ScanGeometry g = firing_order({}, &h);
  size_t walk = 0, successor = 0;
  const std::vector<uint8_t> pw = payload(g, h, true, &walk);
  const std::vector<uint8_t> ps = payload(g, h, false, &successor);
  expect_same(g, decode_scan_geometry(pw.data(), pw.size(), "walk"));
  expect_same(g, decode_scan_geometry(ps.data(), ps.size(), "successor"));
  EXPECT_LT(2 * walk, successor) << "ring and column bytes: walk " << walk << ", successor "
                                 << successor;
  EXPECT_LT(pw.size(), ps.size());

  // The encoder finds it too.
  const std::vector<uint8_t> p = encode_scan_geometry(g, h);
  EXPECT_EQ(frame_flags(p) & scan::kRingWalk, scan::kRingWalk);
  EXPECT_LE(p.size(), pw.size());
  expect_same(g, decode_scan_geometry(p.data(), p.size(), "encoded"));
}

TEST(ScanWalk, GivenRingsFiredOutOfAscendingOrderThenTheEncoderKeepsTheSuccessor) {
  // Rings fired 0, 16, 1, 17, ... (a VLP-16's lasers by elevation): the walk passes half the
  // rings at each step, the successor learns the order.
  std::vector<uint32_t> order;
  for (uint32_t i = 0; i < 16; ++i) order.insert(order.end(), {i, i + 16});
  ScanHints h;
  const ScanGeometry g = firing_order(order, &h);
  const std::vector<uint8_t> p = encode_scan_geometry(g, h);
  EXPECT_EQ(frame_flags(p) & scan::kRingWalk, 0);
  expect_same(g, decode_scan_geometry(p.data(), p.size(), "encoded"));
}

TEST(ScanWalk, GivenRingsFiredFromTheTopDownThenTheTableIsNumberedDownAndWalked) {
  // Each firing's rings from the highest down, as most Hesai drivers write them: the encoder
  // numbers its table's rings from the top (scan::flip_rings), so the walk runs up them, and the
  // sweep costs what the same points fired from the bottom up cost (within 1 %). Before, the
  // walk was not tried on them: 22,957 B against 20,941 here.
  std::vector<uint32_t> down;
  for (uint32_t i = 0; i < 32; ++i) down.push_back(31 - i);
  for (bool field : {true, false}) {  // rings from a ring field, and from the elevations
    ScanHints hu, hd;
    const ScanGeometry up_g = firing_order({}, &hu), down_g = firing_order(down, &hd);
    if (!field) hu.ring.clear(), hd.ring.clear();
    const std::vector<uint8_t> pu = encode_scan_geometry(up_g, hu);
    const std::vector<uint8_t> pd = encode_scan_geometry(down_g, hd);
    EXPECT_EQ(frame_flags(pd) & scan::kRingWalk, scan::kRingWalk) << field;
    EXPECT_LT(static_cast<double>(pd.size()), 1.01 * static_cast<double>(pu.size()))
        << field << ": from the top down " << pd.size() << " B, from the bottom up " << pu.size();
    expect_same(down_g, decode_scan_geometry(pd.data(), pd.size(), "down"));
  }
}

TEST(ScanWalk, GivenAnyOrderWhenCodedWithTheWalkThenExact) {
  // Shuffled points (rings repeated in new firings, walks round the whole table) and a
  // one-ring table still round-trip exactly.
  ScanHints h;
  ScanGeometry g = firing_order({}, &h);
  std::mt19937 rng(4);
  for (size_t i = g.total() - 1; i > 0; --i) {
    const size_t j = rng() % (i + 1);
    for (int a = 0; a < 3; ++a) std::swap(g.q[3 * i + a], g.q[3 * j + a]);
    std::swap(h.ring[i], h.ring[j]);
    for (int a = 0; a < 3; ++a) std::swap(h.xyz[3 * i + a], h.xyz[3 * j + a]);
  }
  size_t rc = 0;
  std::vector<uint8_t> p = payload(g, h, true, &rc);
  expect_same(g, decode_scan_geometry(p.data(), p.size(), "shuffled"));
  std::fill(h.ring.begin(), h.ring.end(), 0u);
  p = payload(g, h, true, &rc);
  expect_same(g, decode_scan_geometry(p.data(), p.size(), "one ring"));
}

TEST(ScanWalk, GivenDamagedWalkFramesWhenDecodedThenCorrupt) {
  ScanHints h;
  const ScanGeometry g = firing_order({}, &h);
  size_t rc = 0;
  const std::vector<uint8_t> p = payload(g, h, true, &rc);
  const scan::Header hd = scan::read_header(p.data(), p.size(), "walk", 1u << 20);
  // The flags byte: varint F (1 byte), varint n (3 bytes for 28k points), then the flags.
  size_t at = 1;
  while (p[at] & 0x80) ++at;
  ++at;
  ASSERT_LT(at, hd.body);
  ASSERT_EQ(p[at], scan::kSpherical | scan::kRingWalk);
  for (uint8_t bad : {uint8_t{scan::kRingWalk}, uint8_t{scan::kRingWalk | scan::kRaster},
                      uint8_t{scan::kRingWalk | 16}}) {
    std::vector<uint8_t> d = p;
    d[at] = bad;
    expect_scan_corrupt(d);
  }
  // Every cut of the block, and flips in it, either decode or are corrupt, never more.
  size_t errors = 0;
  for (size_t n = hd.body; n < p.size(); n += 61) {
    try {
      decode_scan_geometry(p.data(), n, "cut", 1 << 20);
    } catch (const Error& e) {
      EXPECT_EQ(e.code(), ErrorCode::kCorrupt);
      ++errors;
    }
  }
  EXPECT_EQ(errors, (p.size() - hd.body + 60) / 61);
  std::mt19937 rng(9);
  for (int t = 0; t < 60; ++t) {
    std::vector<uint8_t> d = p;
    d[hd.body + rng() % (d.size() - hd.body)] ^= static_cast<uint8_t>(1 + rng() % 255);
    try {
      const ScanGeometry r = decode_scan_geometry(d.data(), d.size(), "flipped", 1 << 20);
      EXPECT_EQ(r.valid.size(), r.total());
    } catch (const Error& e) {
      EXPECT_EQ(e.code(), ErrorCode::kCorrupt);
    }
  }
}

}  // namespace
}  // namespace capz
