// ATTR's predictor 12 with the sweep bit (docs/FORMAT.md "Scans (format 1.1)": point fields of a
// ragged window): the cells by the diamond angle of the SCNW integers; the previous frame's k at
// the point's cell as the prediction; a still scene's intensity coded smaller with it and exact
// back; damaged parameters refused.
#include <gtest/gtest.h>

#include <cmath>
#include <cstring>
#include <random>
#include <string>
#include <vector>

#include "capz/error.h"
#include "coding/attributes.h"
#include "coding/attributes_quantum.h"
#include "test_util.h"

namespace capz {
namespace {

using attr::sweep_cells;

TEST(AttrSweep, CellsByTheDiamondAngle) {
  // x y z per point: +x, +y, -x, -y, the four diagonals, the origin; keys 0 and 3 and 300.
  const std::vector<int32_t> q = {5, 0,  0,  0, 5, 0,  -5, 0, 0, 0, -5, 0, 3, 3, 0, -3, 3,
                                  0, -3, -3, 0, 3, -3, 0,  0, 0, 7, 7,  0, 0, 7, 0, 0};
  const std::vector<uint16_t> keys = {0, 0, 0, 0, 0, 0, 0, 0, 0, 3, 300};
  const std::vector<uint8_t> valid(11, 1);
  const std::vector<int32_t> c = sweep_cells(keys.data(), q.data(), valid.data(), 11, 4);
  // 16 bins a turn, 4 a quadrant: a = 0, 1, 2, 3 at the axes, 0.5 + j at the diagonals.
  EXPECT_EQ(c, (std::vector<int32_t>{0, 4, 8, 12, 2, 6, 10, 14, -1, 3 * 16 + 0, -1}));
  // Just below the +x axis (y < 0): the last bin of the turn.
  const std::vector<int32_t> below = {1000000, -1, 0};
  EXPECT_EQ(sweep_cells(keys.data(), below.data(), valid.data(), 1, 12)[0], 4095);
  const std::vector<uint8_t> gap = {0};
  EXPECT_EQ(sweep_cells(keys.data(), below.data(), gap.data(), 1, 12)[0], -1);
}

TEST(AttrSweep, PredictsFromThePreviousFramesCell) {
  // Frames of 3, 2 and 2 points; cells 5, 6, 5 | 5, 9 | 6, 5 (base 1 keyed by nothing: k 0).
  std::vector<uint64_t> lane(7, 0);
  const std::vector<uint8_t> valid(7, 1);
  const std::vector<int32_t> cells = {5, 6, 5, 5, 9, 6, 5};
  const std::vector<size_t> offsets = {0, 3, 5, 7};
  RaggedFields rf;
  rf.frame_offsets = offsets.data();
  rf.frames = 3;
  attr::QuantumParams qp;
  qp.base = attr::kBaseKey;
  qp.sweep = 4;
  const std::vector<uint16_t> keys(7, 0);
  const std::vector<int32_t> ks = {10, 20, 30, 40, 50, 60, 70};
  std::vector<int32_t> kh;
  size_t p = 0;
  attr::walk_quantum(
      &lane, valid.data(), qp, keys.data(), nullptr, nullptr, [](uint64_t*, uint64_t) {},
      [&](uint64_t*, int32_t h, int32_t* k) {
        kh.push_back(h);
        *k = ks[p++];
      },
      cells.data(), &rf);
  // Frame 0: base 1 (the key's latest k); frame 1: cell 5's latest in frame 0 (30), cell 9 none
  // (base 1: 40); frame 2: cell 6 in frame 1 none (base 1: 50), cell 5 in frame 1 (40).
  EXPECT_EQ(kh, (std::vector<int32_t>{0, 10, 20, 30, 40, 50, 40}));
}

// Three sweeps of a still 16-laser scene: an intensity (float32 whole numbers) that each surface
// keeps from sweep to sweep, noisy along a laser; the ring U2; the SCNW integers on a 2 mm grid.
struct Sweeps {
  std::vector<AttrSpec> specs = {capz_test::field_spec("intensity", 'F', 4),
                                 capz_test::field_spec("ring", 'U', 2)};
  std::vector<std::vector<uint8_t>> data = std::vector<std::vector<uint8_t>>(2);
  std::vector<uint8_t> valid;
  std::vector<double> xyz;
  std::vector<int32_t> q;
  std::vector<size_t> offsets = {0};
};

Sweeps still_scene() {
  Sweeps w;
  std::mt19937 rng(7);
  std::uniform_int_distribution<int> wobble(-1, 1);
  std::vector<int> surface(16 * 600);
  for (int& s : surface) s = std::uniform_int_distribution<int>(0, 200)(rng);
  for (int f = 0; f < 3; ++f) {
    for (int c = 0; c < 600; ++c)
      for (int k = 0; k < 16; ++k) {
        const double az = 6.283185307179586 * (c + 0.01 * f) / 600, el = -0.2 + 0.02 * k;
        const double r = 4 + std::sin(3 * az);
        const double p[3] = {r * std::cos(el) * std::cos(az), r * std::cos(el) * std::sin(az),
                             r * std::sin(el)};
        w.valid.push_back(1);
        for (double v : p) {
          w.q.push_back(static_cast<int32_t>(std::floor(v / 0.002 + 0.5)));
          w.xyz.push_back(w.q.back() * 0.002);
        }
        const float in = static_cast<float>(surface[static_cast<size_t>(c * 16 + k)] + wobble(rng));
        uint32_t b;
        std::memcpy(&b, &in, 4);
        for (int i = 0; i < 4; ++i) w.data[0].push_back(static_cast<uint8_t>(b >> (8 * i)));
        w.data[1].push_back(static_cast<uint8_t>(k));
        w.data[1].push_back(0);
      }
    w.offsets.push_back(w.valid.size());
  }
  return w;
}

RaggedFields fields_of(const Sweeps& w, bool sweep) {
  RaggedFields rf;
  rf.xyz = w.xyz.data();
  if (sweep) {
    rf.q = w.q.data();
    rf.frame_offsets = w.offsets.data();
    rf.frames = w.offsets.size() - 1;
  }
  return rf;
}

std::vector<uint8_t> encode(const Sweeps& w, bool sweep) {
  const RaggedFields rf = fields_of(w, sweep);
  const size_t n = w.valid.size();
  return encode_attributes(w.specs, w.data, w.valid.data(), 1, n, n, w.q.data(), true, &rf);
}

ErrorCode decode(const Sweeps& w, const std::vector<uint8_t>& e, bool sweep,
                 std::vector<std::vector<uint8_t>>* back, std::string* msg = nullptr) {
  const RaggedFields rf = fields_of(w, sweep);
  const size_t n = w.valid.size();
  return capz_test::error_of(
      [&] {
        decode_attributes(e.data(), e.size(), w.specs, w.valid.data(), 1, n, n, back, "test",
                          w.q.data(), &rf);
      },
      msg);
}

// The offset of the intensity's base byte (after the ring, key-first; one lane each).
size_t base_byte(const std::vector<uint8_t>& e) {
  size_t at = 2;  // the ring's transform and predictor (13 or another, no parameters)
  size_t size = 0;
  for (int sh = 0;; sh += 7) {
    size |= static_cast<size_t>(e[at] & 0x7F) << sh;
    if (!(e[at++] & 0x80)) break;
  }
  at += size;
  EXPECT_EQ(e[at], 0);       // transform 0
  EXPECT_EQ(e[at + 1], 12);  // predictor 12
  return at + 10;            // after the quantum
}

TEST(AttrSweep, StillSceneCodedFromThePreviousSweep) {
  const Sweeps w = still_scene();
  const std::vector<uint8_t> e = encode(w, true);
  std::vector<std::vector<uint8_t>> back;
  ASSERT_EQ(decode(w, e, true, &back), ErrorCode::kInternal);
  EXPECT_EQ(back, w.data);
  const size_t b = base_byte(e);
  EXPECT_EQ(e[b], 1 | 8);   // base 1, the sweep bit
  EXPECT_EQ(e[b + 3], 11);  // after the key (attribute 1, element 0): 2^11 bins
  const std::vector<uint8_t> without = encode(w, false);
  ASSERT_EQ(decode(w, without, false, &back), ErrorCode::kInternal);
  EXPECT_EQ(back, w.data);
  // Without the sweep (the best of the others: LZMA finds the sweeps' repeats in part), two
  // sweeps of three code from their previous sweep in fewer bits.
  EXPECT_LT(e.size() * 5, without.size() * 4) << e.size() << " " << without.size();
}

TEST(AttrSweep, DamagedParametersAreCorrupt) {
  const Sweeps w = still_scene();
  const std::vector<uint8_t> e = encode(w, true);
  const size_t b = base_byte(e);
  ASSERT_EQ(e[b], 9);
  std::vector<std::vector<uint8_t>> back;
  const auto with = [&](size_t at, uint8_t v) {
    std::vector<uint8_t> d = e;
    d[at] = v;
    return d;
  };
  const std::vector<std::pair<std::vector<uint8_t>, std::string>> bad = {
      {with(b, 8), "without a key"},          // base 0 with the sweep bit
      {with(b, 1 | 8 | 16), "unknown base"},  // bit 4
      {with(b + 3, 3), "outside 4..12"},      // bins
      {with(b + 3, 13), "outside 4..12"},
  };
  for (const auto& [d, what] : bad) {
    std::string msg;
    EXPECT_EQ(decode(w, d, true, &back, &msg), ErrorCode::kCorrupt) << what;
    EXPECT_NE(msg.find(what), std::string::npos) << msg;
  }
  // Without the window's integers and frames the sweep bit is corrupt.
  std::string msg;
  EXPECT_EQ(decode(w, e, false, &back, &msg), ErrorCode::kCorrupt);
  EXPECT_NE(msg.find("previous sweep"), std::string::npos) << msg;
}

}  // namespace
}  // namespace capz
