// ATTR's predictor 13, ring (docs/FORMAT.md "Scans (format 1.1)": point fields of a ragged
// window): the walk's predictions by the rules; the geometry rings the scan encoder works out
// for its payload are the ones the decoder finds in it; a ring field that relabels the
// geometry's rings coded at almost nothing and exact back; damaged streams refused; the real
// sweeps' ring and channel fields.
#include <gtest/gtest.h>

#include <algorithm>
#include <cmath>
#include <filesystem>
#include <numeric>
#include <random>
#include <string>
#include <vector>

#include "capz/error.h"
#include "capz/io.h"
#include "capz/take.h"
#include "coding/attributes.h"
#include "coding/attributes_ring.h"
#include "coding/scan_geometry.h"
#include "scan_geometry_expect.h"
#include "test_util.h"

namespace capz {
namespace {

constexpr uint16_t kNo = ScanGeometry::kNoRing;

void put_u16(std::vector<uint8_t>* b, uint32_t v) {
  b->push_back(static_cast<uint8_t>(v));
  b->push_back(static_cast<uint8_t>(v >> 8));
}

TEST(AttrRing, WalkPredictsByTheRules) {
  // Point: 0 ring 0; 1 ring 1; 2 ring 0 again; 3, 4 without a ring; 5 a gap; 6 ring 1; 7 none.
  std::vector<uint64_t> lane = {5, 7, 5, 9, 7, 3, 8, 6};
  const std::vector<uint8_t> valid = {1, 1, 1, 1, 1, 0, 1, 1};
  const std::vector<uint16_t> rings = {0, 1, 0, kNo, kNo, kNo, 1, kNo};
  std::vector<uint64_t> preds;
  std::vector<bool> gaps;
  attr::walk_ring(&lane, valid.data(), rings.data(), [&](uint64_t*, uint64_t p, bool gap) {
    preds.push_back(p);
    gaps.push_back(gap);
  });
  // 0: nothing before (last = 0); 1: ring 1 not seen, no successor of 5 yet: last; 2: ring 0's
  // latest (5); 3: no ring, the successor of 5 (7, after point 0); 4: no successor of 9: last;
  // 5: a gap, the previous gap's value (0 for the first); 6: ring 1's latest (7); 7: no ring, no
  // successor of 8 (point 6 followed 9, point 4 across the gap): last.
  EXPECT_EQ(preds, (std::vector<uint64_t>{0, 5, 5, 7, 9, 0, 7, 8}));
  EXPECT_EQ(gaps, (std::vector<bool>{false, false, false, false, false, true, false, false}));
  // Without rings, only successors and the previous value: 2 has no successor of 7 yet, 3 the
  // successor of 5 (7), 6 that of 7 (5, after point 1).
  preds.clear();
  attr::walk_ring(&lane, valid.data(), nullptr,
                  [&](uint64_t*, uint64_t p, bool) { preds.push_back(p); });
  EXPECT_EQ(preds, (std::vector<uint64_t>{0, 5, 7, 7, 9, 0, 5, 8}));
}

// A window of n points whose ring field is a relabelling (value 100 + 7 k mod 32) of the
// geometry's 32 rings, each firing's rings in a shuffled order (as pandar64's files have them),
// a stretch of points without a geometry ring (a Cartesian frame's) and a gap every 97th point.
struct RingWindow {
  std::vector<AttrSpec> specs = {capz_test::field_spec("ring", 'U', 2)};
  std::vector<std::vector<uint8_t>> data = std::vector<std::vector<uint8_t>>(1);
  std::vector<uint8_t> valid;
  std::vector<uint16_t> rings;
  std::vector<double> xyz;
};

RingWindow ring_window(size_t n) {
  RingWindow w;
  std::mt19937 rng(3);
  std::vector<uint32_t> firing(32);
  std::iota(firing.begin(), firing.end(), 0u);
  for (size_t i = 0; i < n; ++i) {
    if (i % 32 == 0) std::shuffle(firing.begin(), firing.end(), rng);
    const uint32_t k = firing[i % 32];
    const bool valid = i % 97 != 5;
    w.valid.push_back(valid ? 1 : 0);
    w.rings.push_back(valid && (i < n / 2 || i >= n / 2 + 640) ? static_cast<uint16_t>(k) : kNo);
    put_u16(&w.data[0], valid ? 100 + (7 * k) % 32 : 0);
    for (int a = 0; a < 3; ++a) w.xyz.push_back(valid ? 1.0 + a : 0.0);
  }
  return w;
}

std::vector<uint8_t> encode(const RingWindow& w, const uint16_t* rings) {
  RaggedFields rf;
  rf.xyz = w.xyz.data();
  rf.ring = rings;
  const size_t n = w.valid.size();
  return encode_attributes(w.specs, w.data, w.valid.data(), 1, n, n, nullptr, true, &rf);
}

ErrorCode decode(const RingWindow& w, const std::vector<uint8_t>& e, const uint16_t* rings,
                 std::vector<std::vector<uint8_t>>* back, bool ragged = true,
                 std::string* msg = nullptr) {
  RaggedFields rf;
  rf.xyz = w.xyz.data();
  rf.ring = rings;
  const size_t n = w.valid.size();
  return capz_test::error_of(
      [&] {
        decode_attributes(e.data(), e.size(), w.specs, w.valid.data(), 1, n, n, back, "test",
                          nullptr, ragged ? &rf : nullptr);
      },
      msg);
}

TEST(AttrRing, RingFieldFromTheGeometryAtAlmostNothing) {
  const RingWindow w = ring_window(40000);
  const std::vector<uint8_t> e = encode(w, w.rings.data());
  std::vector<std::vector<uint8_t>> back;
  ASSERT_EQ(decode(w, e, w.rings.data(), &back), ErrorCode::kInternal);
  EXPECT_EQ(back, w.data);
  EXPECT_EQ(e[0], 0);   // transform 0
  EXPECT_EQ(e[1], 13);  // predictor 13
  // Without the geometry's rings the shuffled firings cost bits a point: LZMA or a successor.
  const std::vector<uint8_t> without = encode(w, nullptr);
  ASSERT_EQ(decode(w, without, nullptr, &back), ErrorCode::kInternal);
  EXPECT_EQ(back, w.data);
  EXPECT_LT(e.size() * 10, without.size()) << e.size() << " " << without.size();
  // The stretch without rings (640 points in firing order shuffled) aside, about nothing a point.
  EXPECT_LT(e.size(), 640u + w.valid.size() / 256) << e.size();
  // The decoder predicts from the rings it is given: other rings (two lasers on one) give other
  // values (a relabelling of the rings would not).
  std::vector<uint16_t> merged = w.rings;
  for (uint16_t& k : merged)
    if (k != kNo) k = static_cast<uint16_t>(k / 2);
  ASSERT_EQ(decode(w, e, merged.data(), &back), ErrorCode::kInternal);
  EXPECT_NE(back, w.data);
}

TEST(AttrRing, DamagedStreamsAreCorrupt) {
  const RingWindow w = ring_window(3000);
  const std::vector<uint8_t> e = encode(w, w.rings.data());
  ASSERT_EQ(e[1], 13);
  std::vector<std::vector<uint8_t>> back;
  std::string msg;
  // 13 outside a ragged window is an unknown predictor.
  EXPECT_EQ(decode(w, e, w.rings.data(), &back, false, &msg), ErrorCode::kCorrupt);
  EXPECT_NE(msg.find("unknown predictor 13"), std::string::npos) << msg;
  // 13 on a field that is not an integer of 1 or 2 bytes (the same bytes read as U4 or F4).
  for (char type : {'U', 'F'}) {
    RingWindow other = w;
    other.specs[0] = capz_test::field_spec("ring", type, 4);
    EXPECT_EQ(decode(other, e, w.rings.data(), &back, true, &msg), ErrorCode::kCorrupt) << type;
    EXPECT_NE(msg.find("predictor 13 on a field"), std::string::npos) << msg;
  }
  // Every truncation is refused, never a crash; so is a byte more.
  for (size_t cut = 0; cut < e.size(); cut += 7) {
    const std::vector<uint8_t> t(e.begin(), e.begin() + static_cast<std::ptrdiff_t>(cut));
    EXPECT_EQ(decode(w, t, w.rings.data(), &back), ErrorCode::kCorrupt) << cut;
  }
  std::vector<uint8_t> longer = e;
  longer.push_back(0);
  EXPECT_EQ(decode(w, longer, w.rings.data(), &back), ErrorCode::kCorrupt);
}

// Three frames of a 16-laser sensor on the 2 mm grid, the lasers in firing order, with a ring
// field; with `offset` the points sit on cones from a centre off the axis, so that the encoder
// also codes the rings it finds from the elevations (scan_encode.cpp) and may keep those.
ScanGeometry sweeps(double offset, ScanHints* h) {
  std::mt19937 rng(9);
  std::uniform_real_distribution<double> u(0, 1);
  ScanGeometry g;
  for (int f = 0; f < 3; ++f) {
    uint32_t n = 0;
    for (int c = 0; c < 1200; ++c) {
      const double az = 6.283185307179586 * c / 1200;
      for (int k = 0; k < 16; ++k) {
        if (u(rng) < 0.05) continue;  // no return
        const double el = -0.26 + 0.03 * k, d = (k % 2 ? 0.4 : 3.0) + 0.2 * std::sin(2 * az);
        const double p[3] = {d * std::cos(el) * std::cos(az) + offset * std::cos(az - 0.07),
                             d * std::cos(el) * std::sin(az) + offset * std::sin(az - 0.07),
                             d * std::sin(el)};
        push_point(&g, h, p, static_cast<uint32_t>(k));
        ++n;
      }
    }
    g.counts.push_back(n);
  }
  h->grid_per_unit = 500;
  return g;
}

// The encoder's rings of its payload (ScanWorkspace::rings) are the decoder's; *ringed: how
// many points have one.
void expect_decoder_rings(const ScanGeometry& g, const ScanHints& h, size_t* ringed) {
  ScanWorkspace ws;
  const std::vector<uint8_t> p = encode_scan_geometry(g, h, &ws);
  EXPECT_EQ(ws.ring_payload, p);
  const ScanGeometry back =
      decode_scan_geometry(p.data(), p.size(), "rings", g.total(), nullptr, true);
  expect_same(g, back);
  ASSERT_EQ(back.ring.size(), g.total());
  EXPECT_EQ(ws.rings, back.ring);
  *ringed = static_cast<size_t>(
      std::count_if(back.ring.begin(), back.ring.end(), [](uint16_t k) { return k != kNo; }));
  // Asked for nothing, the decoder fills no rings.
  EXPECT_TRUE(decode_scan_geometry(p.data(), p.size(), "rings").ring.empty());
}

TEST(AttrRing, EncoderRingsAreTheDecoders) {
  for (double offset : {0.0, 0.035}) {
    ScanHints h;
    const ScanGeometry g = sweeps(offset, &h);
    size_t ringed = 0;
    expect_decoder_rings(g, h, &ringed);
    EXPECT_GT(ringed, g.total() / 2) << offset;
  }
}

// The first frames of the shared sequences: the encoder's geometry rings are the decoder's (1 mm
// and 1 cm grids), and the ring or channel field coded from them costs almost nothing (under
// 1/64 byte a point; pandar64's files shuffle each firing's lasers, which LZMA coded in about
// 0.7 bits a point) and comes back exact.
TEST(AttrRing, SharedSweepsRingFieldFromTheGeometry) {
  const std::string root = capz_test::shared_data_or_skip("scan");
  if (root.empty()) return;
  capz_test::TempDir tmp("capz_attr_ring");
  size_t done = 0;
  for (const char* name : {"pandar64-factory20", "robosense-helios16p"}) {
    const std::filesystem::path dir = std::filesystem::path(root) / name;
    if (!std::filesystem::is_directory(dir)) continue;
    std::vector<std::filesystem::path> frames;
    for (const auto& e : std::filesystem::directory_iterator(dir))
      if (e.path().extension() == ".pcd") frames.push_back(e.path());
    std::sort(frames.begin(), frames.end());
    const std::filesystem::path cut = tmp.path() / name;
    std::filesystem::create_directories(cut);
    for (size_t f = 0; f < frames.size() && f < 3; ++f)
      std::filesystem::copy_file(frames[f], cut / frames[f].filename());
    const Take t = read_take(cut.string());
    ASSERT_TRUE(t.ragged()) << name;
    size_t key = t.attributes.size();
    for (size_t a = 0; a < t.attributes.size(); ++a)
      if (t.attributes[a].name == "ring" || t.attributes[a].name == "channel") key = a;
    ASSERT_LT(key, t.attributes.size()) << name;
    const PointAttribute& field = t.attributes[key];
    ASSERT_EQ(field.size, 2) << name;
    for (double step : {0.002, 0.02}) {
      ScanGeometry g;
      ScanHints h;
      for (size_t f = 0; f + 1 < t.frame_offsets.size(); ++f)
        g.counts.push_back(static_cast<uint32_t>(t.frame_offsets[f + 1] - t.frame_offsets[f]));
      const size_t n = t.valid.size();
      g.valid = t.valid;
      for (size_t i = 0; i < n; ++i) {
        for (int a = 0; a < 3; ++a) {
          const double c = t.valid[i] ? t.xyz[3 * i + size_t(a)] : 0.0;
          g.q.push_back(static_cast<int32_t>(std::floor(c / step + 0.5)));
          h.xyz.push_back(static_cast<float>(c));
        }
        h.ring.push_back(uint32_t{field.data[2 * i]} | uint32_t{field.data[2 * i + 1]} << 8);
      }
      h.grid_per_unit = 1 / step;
      ScanWorkspace ws;
      const std::vector<uint8_t> p = encode_scan_geometry(g, h, &ws);
      const ScanGeometry back = decode_scan_geometry(p.data(), p.size(), name, n, nullptr, true);
      ASSERT_EQ(back.ring, ws.rings) << name << " " << step;
      const std::vector<AttrSpec> specs = {capz_test::field_spec(field.name, 'U', 2)};
      const std::vector<std::vector<uint8_t>> data = {field.data};
      std::vector<double> xyz(3 * n, 0.0);
      RaggedFields rf;
      rf.xyz = xyz.data();
      rf.ring = ws.rings.data();
      const std::vector<uint8_t> e =
          encode_attributes(specs, data, g.valid.data(), 1, n, n, nullptr, true, &rf);
      EXPECT_EQ(e[1], 13) << name << " " << step;
      EXPECT_LT(e.size() * 64, n) << name << " " << step << ": " << e.size() << " bytes";
      rf.ring = back.ring.data();
      std::vector<std::vector<uint8_t>> out;
      decode_attributes(e.data(), e.size(), specs, g.valid.data(), 1, n, n, &out, name, nullptr,
                        &rf);
      EXPECT_EQ(out, data) << name << " " << step;
    }
    ++done;
  }
  if (done == 0) GTEST_SKIP() << "no scan sequence in " << root;
}

}  // namespace
}  // namespace capz
