// What the scan geometry tests (test_scan_geometry.cpp, test_scan_raster.cpp, ...) compare: two
// windows' counts, gaps and valid points' integers, exactly; how their synthetic sweeps add
// a point; how they code one frame with flags of their choice; a real sweep as integers.
#pragma once

#include <gtest/gtest.h>

#include <cmath>
#include <cstdint>
#include <random>
#include <string>
#include <vector>

#include "capz/error.h"
#include "capz/take.h"
#include "coding/bytes.h"
#include "coding/scan_geometry.h"
#include "coding/scan_shared.h"
#include "coding/scan_table.h"

namespace capz {

inline void expect_same(const ScanGeometry& a, const ScanGeometry& b) {
  ASSERT_EQ(a.counts, b.counts);
  ASSERT_EQ(a.valid, b.valid);
  for (size_t i = 0; i < a.valid.size(); ++i) {
    if (!a.valid[i]) continue;
    for (int k = 0; k < 3; ++k) ASSERT_EQ(a.q[3 * i + k], b.q[3 * i + k]) << "point " << i;
  }
}

// Payload p's header, read back (at most 2^24 points).
inline scan::Header payload_header(const std::vector<uint8_t>& p) {
  return scan::read_header(p.data(), p.size(), "payload", size_t{1} << 24);
}

// Decoding payload d fails as corrupt, naming it ("damaged").
inline void expect_scan_corrupt(const std::vector<uint8_t>& d) {
  try {
    decode_scan_geometry(d.data(), d.size(), "damaged");
    ADD_FAILURE() << "decoded";
  } catch (const Error& e) {
    EXPECT_EQ(e.code(), ErrorCode::kCorrupt);
    EXPECT_NE(std::string(e.what()).find("damaged"), std::string::npos);
  }
}

// Appends a valid point p (metres) of ring k to g (on the 2 mm grid) and to h (as float32).
inline void push_point(ScanGeometry* g, ScanHints* h, const double p[3], uint32_t k) {
  g->valid.push_back(1);
  for (int a = 0; a < 3; ++a) {
    g->q.push_back(static_cast<int32_t>(std::floor(p[a] / 0.002 + 0.5)));
    h->xyz.push_back(static_cast<float>(p[a]));
  }
  h->ring.push_back(k);
}

// A point of ring k at azimuth az and elevation el (radians) and a range on a 4 mm step (from
// `range`, metres), with the range as the source's distance field.
inline void push_polar(ScanGeometry* g, ScanHints* h, double az, double el, double range,
                       uint32_t k) {
  range = 0.004 * std::floor(range / 0.004 + 0.5);
  const double rho = range * std::cos(el);
  const double p[3] = {rho * std::cos(az), rho * std::sin(az), range * std::sin(el)};
  push_point(g, h, p, k);
  h->distance.push_back(static_cast<float>(range));
}

constexpr double kQuantum001 = 0.01 * 3.141592653589793 / 180;  // 0.01 degree in radians

// A laser's point in a firing (quantum_sweep): its ring, azimuth in 0.01 degree quanta,
// elevation (radians) and range (metres, before the noise quantum_sweep adds).
struct SweepLaser {
  uint32_t ring = 0;
  int64_t quanta = 0;
  double elevation = 0, range = 0;
};

// One sweep of a spinning sensor on a 1 mm grid (step 0.002 m) in firing order, ranges on a
// 4 mm step and also the distance field, its azimuths on the 0.01 degree quantum as a Velodyne
// driver writes them: each firing turns 19 to 21 quanta from the last (random from `seed`)
// until a whole turn. A firing's `lasers` slots each miss with probability `drop`.
// firing(f, turn, draw) is called once a firing (draw() gives the next uniform [0, 1) of the
// sweep's generator) and returns what its slots see; slot(s, a, turn, v) places slot s of the
// firing at azimuth a (quanta) given v. A point's range gets 0 to 4 mm of noise.
template <typename Firing, typename Slot>
ScanGeometry quantum_sweep(ScanHints* h, unsigned seed, int lasers, double drop, Firing firing,
                           Slot slot) {
  std::mt19937 rng(seed);
  std::uniform_real_distribution<double> u(0, 1);
  const auto draw = [&] { return u(rng); };
  ScanGeometry g;
  uint32_t n = 0;
  int64_t a = 0;
  for (int f = 0; a < 36000; ++f) {
    const int turn = 19 + static_cast<int>(u(rng) * 3);
    a += turn;
    const int v = firing(f, turn, draw);
    for (int s = 0; s < lasers; ++s) {
      if (u(rng) < drop) continue;
      const SweepLaser l = slot(s, a, turn, v);
      push_polar(&g, h, static_cast<double>(l.quanta) * kQuantum001, l.elevation,
                 l.range + 0.004 * u(rng), l.ring);
      ++n;
    }
  }
  g.counts.push_back(n);
  h->grid_per_unit = 500;
  return g;
}

// g coded with hints h: the payload, checked to decode to g exactly (`what` names it).
inline std::vector<uint8_t> coded_exact(const ScanGeometry& g, const ScanHints& h,
                                        const std::string& what) {
  const std::vector<uint8_t> p = encode_scan_geometry(g, h);
  expect_same(g, decode_scan_geometry(p.data(), p.size(), what));
  return p;
}

// Payload d, g's with a header field taken away, decodes to other integers than g's or fails
// as corrupt.
inline void expect_decoded_otherwise(const std::vector<uint8_t>& d, const ScanGeometry& g) {
  try {
    const ScanGeometry back = decode_scan_geometry(d.data(), d.size(), "damaged");
    EXPECT_NE(back.q, g.q);
  } catch (const Error& e) {
    EXPECT_EQ(e.code(), ErrorCode::kCorrupt);
  }
}

// Codes through a block, the ring and column symbols also counted apart.
class BlockIo {
 public:
  BlockIo(IntEncoder* enc, const ScanGeometry& g, const scan::Placement& placed)
      : enc_(enc), g_(g), placed_(placed) {
    apart_.add_bit_models();
  }
  int32_t sym(int32_t actual, int32_t pred, int ctx) {
    put(zigzag(wrap_sub(actual, pred)), ctx);
    return actual;
  }
  int32_t sym_plain(int32_t actual, int32_t pred, int ctx) { return sym(actual, pred, ctx); }
  uint32_t ring(uint32_t d, uint32_t, int ctx) { return put(d, ctx), d; }
  bool flag(bool v, int ctx) { return put(v ? 1u : 0u, ctx), v; }
  scan::Polar polar(size_t i) const { return placed_.polar[i]; }
  scan::Fire fire(size_t i) const { return placed_.fire[i]; }
  const int32_t* actual(size_t i) const { return &g_.q[3 * i]; }
  bool actual_valid(size_t i) const { return g_.valid[i] != 0; }
  // The bytes the ring and column symbols alone take.
  size_t ring_column_bytes() { return apart_.finish().size(); }

 private:
  void put(uint32_t u, int ctx) {
    scan::put_value(*enc_, u, ctx);
    const bool ring_or_column = ctx < scan::kCtxRange || ctx >= scan::kCtxWalkRepeat;
    if (ring_or_column) scan::put_value(apart_, u, ctx);
  }
  IntEncoder* enc_;
  IntEncoder apart_{scan::kContexts};
  const ScanGeometry& g_;
  const scan::Placement& placed_;
};

// g's one frame coded under the table the encoder infers (step as found, no range units) with
// `flags`: the payload, and (*ring_column) the bytes its ring and column symbols alone take.
inline std::vector<uint8_t> one_frame_payload(const ScanGeometry& g, const ScanHints& h,
                                              uint8_t flags, size_t* ring_column) {
  scan::Placement placed;
  const scan::Table t = scan::table_for(g, scan::fit_rings(g, h, false), 1.0, false, &placed);
  EXPECT_GT(t.rings(), 0u);
  IntEncoder enc(scan::kContexts);
  enc.add_bit_models();
  BlockIo io(&enc, g, placed);
  scan::State st(t);
  std::vector<int32_t> q(g.q.size());
  std::vector<uint8_t> v(g.valid.size());
  scan::code_frame(io, st, flags, 0, g.total(), q.data(), v.data());
  *ring_column = io.ring_column_bytes();
  std::vector<uint8_t> out;
  scan::write_header(g, {flags}, t, &out);
  const std::vector<uint8_t> block = enc.finish();
  out.insert(out.end(), block.begin(), block.end());
  return out;
}

// The offset of a payload's laser table `units` byte (after F, the counts, the frames' flags,
// their copies, K, step and C; FORMAT.md "Scan geometry payload").
inline size_t units_offset(const std::vector<uint8_t>& p) {
  ByteReader r(p.data(), p.size(), "units");
  const uint64_t frames = r.varint();
  for (uint64_t f = 0; f < frames; ++f) r.varint();
  const uint8_t* flags = r.bytes(static_cast<size_t>(frames));
  for (uint64_t f = 0; f < frames; ++f)
    if (flags[f] & scan::kCells) r.varint();
  r.varint();
  r.f32();
  r.varint();
  return r.offset();
}

// Payload p with its laser table written plain (units bit 5 clear): the same values, so the
// same points. (For payloads without cells or raster frames, whose header ends with the table.)
inline std::vector<uint8_t> unpacked(const std::vector<uint8_t>& p) {
  const scan::Header hd = scan::read_header(p.data(), p.size(), "plain", size_t{1} << 24);
  for (uint8_t f : hd.flags) EXPECT_EQ(f & (scan::kCells | scan::kRaster), 0);
  scan::Table t = hd.table;
  t.pack.clear();
  ScanGeometry head;
  head.counts = hd.counts;
  std::vector<uint8_t> out;
  scan::write_header(head, hd.flags, t, &out, &hd.turns);
  out.insert(out.end(), p.begin() + static_cast<std::ptrdiff_t>(hd.body), p.end());
  return out;
}

// One sweep of t (its first frame's points) as one frame of integers at per_metre a metre
// (floor(x per_metre + 1/2)), a point valid when t's is and finite; *hints its coordinates and
// per_metre.
inline ScanGeometry sweep_geometry(const Take& t, double per_metre, ScanHints* hints) {
  ScanGeometry g;
  hints->grid_per_unit = per_metre;
  g.counts.push_back(static_cast<uint32_t>(t.total_points()));
  for (size_t i = 0; i < t.total_points(); ++i) {
    const double* x = &t.xyz[3 * i];
    const bool ok = t.valid[i] && std::isfinite(x[0]) && std::isfinite(x[1]) && std::isfinite(x[2]);
    g.valid.push_back(ok);
    for (int a = 0; a < 3; ++a) {
      g.q.push_back(ok ? static_cast<int32_t>(std::floor(x[a] * per_metre + 0.5)) : 0);
      hints->xyz.push_back(static_cast<float>(x[a]));
    }
  }
  return g;
}

}  // namespace capz
