// The column's fourth candidate, the firing's base (docs/FORMAT.md "Scan geometry payload",
// `units` bit 3), and the firing's slots (bit 6): a VLP-16-like sweep whose lasers' azimuths
// are the firing's plus the turn times their firing time, rounded to 0.01 degree, is coded with
// the firing's slots when the firing time is a 24th of half the firing's turn (the VLP-16's),
// else with the firing's turn and the rings' shares of it, exactly; without them the decoder
// predicts otherwise; damaged fields are corrupt.
#include <gtest/gtest.h>

#include <cmath>
#include <cstring>

#include "capz/error.h"
#include "coding/scan_geometry.h"
#include "coding/scan_shared.h"
#include "scan_geometry_expect.h"

namespace capz {
namespace {

constexpr double kQuantum = kQuantum001;

// One sweep (quantum_sweep) as the VLP-16's driver writes it: the 16 lasers (ring k, elevation
// -15 + 2k degrees) fire in slots `2k` below 8 and `2 (k - 8) + 1` from 8 on, each at the
// firing's azimuth plus D slot / `per` quanta, rounded, with D 39 to 41, or 0 in one firing of
// six (the driver's last block of a packet). The VLP-16's `per` is 48.
ScanGeometry sweep(ScanHints* h, double per) {
  const auto spread = [](int f, int, const auto& draw) {
    return f % 6 == 5 ? 0 : 39 + static_cast<int>(draw() * 3);
  };
  const auto slot = [per](int s, int64_t a, int, int d) {
    const int k = s % 2 ? 8 + s / 2 : s / 2;
    const int64_t quanta = a + static_cast<int64_t>(std::floor(d * s / per + 0.5));
    const double az = static_cast<double>(quanta) * kQuantum;
    return SweepLaser{static_cast<uint32_t>(k), quanta, (-15.0 + 2.0 * k) * 3.141592653589793 / 180,
                      9 + 2 * std::sin(2 * az) + std::cos(5 * az + k)};
  };
  return quantum_sweep(h, 11, 16, 0.05, spread, slot);
}

std::vector<uint8_t> coded(const ScanGeometry& g, const ScanHints& h) {
  return coded_exact(g, h, "shares");
}

// The offset of the laser table's `units` byte.
size_t units_at(const std::vector<uint8_t>& p) {
  return units_offset(p);
}

constexpr double kSlotShare = 48, kOtherShare = 44;  // the VLP-16's D slot / 48, and another

TEST(ScanShares, GivenLasersSpreadByTheirFiringTimeThenTheFiringsBaseExact) {
  ScanHints h;
  const ScanGeometry g = sweep(&h, kOtherShare);
  const std::vector<uint8_t> p = coded(g, h);
  const scan::Header hd = payload_header(p);
  EXPECT_TRUE(hd.table.turn);
  EXPECT_NEAR(hd.table.step, kQuantum, 1e-9);
  ASSERT_EQ(hd.table.share.size(), hd.table.rings());
  EXPECT_NEAR(hd.table.fire_turn, 20, 1);
  EXPECT_EQ(p[units_at(p)] & ~scan::kPackBit, 1 | scan::kShareBit | scan::kTurnBit);
  // The shares follow the slots: ring 8 (slot 1) after ring 0 (slot 0), ring 1 (slot 2) after
  // it, ring 15 (slot 15) last, about 5/6 of a quantum a slot.
  const std::vector<float>& s = hd.table.share;
  EXPECT_LT(s[0], s[8]);
  EXPECT_LT(s[8], s[1]);
  EXPECT_NEAR((s[15] - s[0]) * hd.table.fire_turn, 15 * 40 / kOtherShare, 1.5);
}

TEST(ScanSlots, GivenTheVlp16sFiringTimesThenTheSlotsExact) {
  ScanHints h;
  const ScanGeometry g = sweep(&h, kSlotShare);
  const std::vector<uint8_t> p = coded(g, h);
  const scan::Header hd = payload_header(p);
  EXPECT_TRUE(hd.table.share.empty());
  EXPECT_EQ(hd.table.slots, 24u);
  EXPECT_EQ(p[units_at(p)] & ~scan::kPackBit, 1 | scan::kSlotBit | scan::kTurnBit);
  ASSERT_EQ(hd.table.slot.size(), 16u);
  for (uint32_t k = 0; k < 16; ++k) EXPECT_EQ(hd.table.slot[k], k < 8 ? 2 * k : 2 * (k - 8) + 1);
  // Removing the slots (bit 6 cleared, N and m_k cut) makes the decoder predict otherwise.
  std::vector<uint8_t> d(p.begin(), p.begin() + static_cast<std::ptrdiff_t>(hd.body) - 1 - 17);
  d[units_at(p)] &= static_cast<uint8_t>(~scan::kSlotBit);
  d.insert(d.end(), p.begin() + static_cast<std::ptrdiff_t>(hd.body) - 1, p.end());  // more on
  expect_decoded_otherwise(d, g);
}

TEST(ScanSlots, GivenDamagedSlotsOrBitsThenCorrupt) {
  ScanHints h;
  const ScanGeometry g = sweep(&h, kSlotShare);
  const std::vector<uint8_t> p = coded(g, h);
  const size_t at = units_at(p), n = payload_header(p).body - 1 - 17;  // (the more byte last)
  std::vector<uint8_t> d = p;
  d[at] = static_cast<uint8_t>(d[at] & ~scan::kTurnBit);  // bit 6 without bit 4
  expect_scan_corrupt(d);
  d = p;
  d[at] = static_cast<uint8_t>(d[at] | scan::kShareBit);  // bits 3 and 6
  expect_scan_corrupt(d);
  for (uint8_t v : {0, 65, 255}) {  // N out of range
    d = p;
    d[n] = v;
    expect_scan_corrupt(d);
  }
  d = p;  // truncated in the slots
  d.resize(n + 5);
  expect_scan_corrupt(d);
}

TEST(ScanShares, GivenTheSharesRemovedThenTheDecoderPredictsOtherwise) {
  ScanHints h;
  const ScanGeometry g = sweep(&h, kOtherShare);
  const std::vector<uint8_t> p = coded(g, h);
  const scan::Header hd = payload_header(p);
  std::vector<uint8_t> d(p.begin(), p.begin() + static_cast<std::ptrdiff_t>(hd.body) - 1 - 4 -
                                        4 * static_cast<std::ptrdiff_t>(hd.table.rings()));
  d[units_at(p)] &= static_cast<uint8_t>(~scan::kShareBit);
  d.insert(d.end(), p.begin() + static_cast<std::ptrdiff_t>(hd.body) - 1, p.end());  // more on
  expect_decoded_otherwise(d, g);
}

TEST(ScanShares, GivenDamagedTurnSharesOrBitsThenCorrupt) {
  ScanHints h;
  const ScanGeometry g = sweep(&h, kOtherShare);
  const std::vector<uint8_t> p = coded(g, h);
  const size_t at = units_at(p),
               turn = payload_header(p).body - 1 - 4 - 4 * payload_header(p).table.rings();
  std::vector<uint8_t> d = p;
  d[at] = static_cast<uint8_t>(d[at] & ~scan::kTurnBit);  // bit 3 without bit 4
  expect_scan_corrupt(d);
  for (float v : {1e9f, NAN, -70000.0f}) {  // the turn out of range
    d = p;
    std::memcpy(&d[turn], &v, 4);
    expect_scan_corrupt(d);
  }
  for (float v : {17.0f, INFINITY}) {  // a share out of range
    d = p;
    std::memcpy(&d[turn + 4 + 4 * 3], &v, 4);
    expect_scan_corrupt(d);
  }
}

// The VLP-16's sweep written ring by ring (each ring's points in their firing order, as a cloud
// in rows has them): the ring changes once a row, so no run of points is a firing and the
// slots are not fitted (fit_slots' in_firing_order), which would fit each point its own base
// and turn, slowly (quadratic in the rings); the payload still decodes exactly.
TEST(ScanSlots, GivenASweepInRowsThenNoSlots) {
  ScanHints h;
  const ScanGeometry g = sweep(&h, kSlotShare);
  ScanGeometry rows;
  ScanHints rh;
  rh.grid_per_unit = h.grid_per_unit;
  for (uint32_t k = 0; k < 16; ++k)
    for (size_t i = 0; i < h.ring.size(); ++i) {
      if (h.ring[i] != k) continue;
      rows.valid.push_back(g.valid[i]);
      for (size_t a = 0; a < 3; ++a) {
        rows.q.push_back(g.q[3 * i + a]);
        rh.xyz.push_back(h.xyz[3 * i + a]);
      }
      rh.ring.push_back(k);
      rh.distance.push_back(h.distance[i]);
    }
  rows.counts = g.counts;
  ASSERT_EQ(rows.valid.size(), g.valid.size());
  const scan::Header hd = payload_header(coded(rows, rh));
  EXPECT_EQ(hd.table.slots, 0u);
  EXPECT_TRUE(hd.table.slot.empty());
}

}  // namespace
}  // namespace capz
