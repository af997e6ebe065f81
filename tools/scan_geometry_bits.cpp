// Bits per point of the scan geometry coder (src/coding/scan_geometry.h) on PCD sequences: each
// folder (or single .pcd file) is one sequence, coded as one window. The points are quantised at
// step 2 x bound (rounding to the nearest grid point, so the error is at most the bound in
// metres), NaN points kept as gaps; the payload is decoded and compared with the integers.
//
//   scan_geometry_bits [--bound M]... [--no-ring] [--no-units] [--window F] [--dump N]
//                      [--breakdown [--divisor D] [--hypot] [--walk | --pairs]] [--sorted] PATH...
//
// --bound: bounds in metres (default 0.001 and 0.01); --no-ring: ignore the ring / channel
// field (the coder then infers the rings); --no-units: no range units (the encoder is not told
// the grid's scale, so it does not look for the sensor's range step); --window: frames per window
// (default: all);
// --dump: print the first N points of each sequence's first frame in polar form; --breakdown:
// bits per point of each kind of symbol (ring, column, range, x, y, z), step divisor 4 or
// --divisor D, the second of x y from the azimuth or (--hypot) from the range's hypotenuse;
// --sorted: each frame in --point-order any's coded order (coding/scan_geometry.h);
// --walk: --breakdown's frames coded with the ring walk (frame flag bit 3); --pairs: with ring
// pairs (bit 7).
// Prints one line per sequence and bound: points, payload bytes, bits per point, encode and
// decode milliseconds. Exits 1 when a round trip is not exact.

#include <algorithm>
#include <chrono>
#include <cmath>
#include <cstdio>
#include <memory>
#include <string>
#include <vector>

#include "capz/error.h"
#include "coding/scan_geometry.h"
#include "coding/scan_table.h"
#include "scan_frames.h"

namespace {

using scan_tools::Frame;
using scan_tools::list_frames;
using scan_tools::read_frame;

bool show_breakdown = false;
double breakdown_divisor = 4;  // --divisor: the table's step divisor of --breakdown
bool sorted_order = false;     // --sorted: --point-order any's coded order (scan_point_order)
bool range_units = true;       // --no-units: no ScanHints::grid_per_unit (no range units)
bool ring_walk = false;        // --walk: --breakdown codes its frames with the ring walk
bool ring_pairs = false;       // --pairs: --breakdown codes its frames with ring pairs
bool breakdown_hypot = false;  // --hypot: --breakdown's second of x y from the hypotenuse

// --breakdown: the bytes each kind of symbol takes when every frame that can be is coded
// spherically (each kind through its own range coder with the coder's contexts).
class BreakdownIo {
 public:
  BreakdownIo(const capz::ScanGeometry& g, const capz::scan::Placement& placed)
      : g_(g), placed_(placed) {
    for (auto& e : enc_) {
      e.reset(new capz::IntEncoder(capz::scan::kContexts));
      e->add_bit_models();
    }
  }
  int32_t sym(int32_t actual, int32_t pred, int ctx) {
    put(capz::zigzag(capz::wrap_sub(actual, pred)), ctx);
    return actual;
  }
  int32_t sym_plain(int32_t actual, int32_t pred, int ctx) { return sym(actual, pred, ctx); }
  uint32_t ring(uint32_t d, uint32_t, int ctx) { return put(d, ctx), d; }
  bool flag(bool v, int ctx) { return put(v, ctx), v; }
  capz::scan::Polar polar(size_t i) const { return placed_.polar[i]; }
  capz::scan::Fire fire(size_t i) const { return placed_.fire[i]; }
  const int32_t* actual(size_t i) const { return &g_.q[3 * i]; }
  bool actual_valid(size_t i) const { return g_.valid[i] != 0; }
  void print(size_t points) {
    using namespace capz::scan;
    const char* names[8] = {"valid",    "ring",      "column", "range",
                            "xy-first", "xy-second", "z",      "cartesian"};
    std::printf("  bits/pt:");
    for (int k = 0; k < 8; ++k) {
      const size_t n = enc_[k]->finish().size();
      if (n > 8) std::printf(" %s %.3f", names[k], 8.0 * double(n) / double(points));
    }
    std::printf("\n");
  }

 private:
  void put(uint32_t u, int ctx) {
    using namespace capz::scan;
    const int k = ctx < kCtxRing         ? 0
                  : ctx < kCtxColumn     ? 1
                  : ctx < kCtxRange      ? 2
                  : ctx < kCtxX          ? 3
                  : ctx < kCtxY          ? 7  // unused
                  : ctx < kCtxZ          ? 5  // the second of x y from the azimuth
                  : ctx < kCtxImage      ? 7  // unused, Cartesian, raster
                  : ctx < kCtxAxis1      ? 3
                  : ctx < kCtxAxis2      ? 4
                  : ctx < kCtxZFrac      ? 5
                  : ctx < kCtxWalkRepeat ? 6
                  : ctx < kCtxWalkColumn ? 1
                  : ctx < kCtxPairRing   ? 2
                  : ctx >= kCtxShare     ? 2  // the column against the firing's base
                                         : 1;
    capz::scan::put_value(*enc_[k], u, ctx);
  }
  const capz::ScanGeometry& g_;
  const capz::scan::Placement& placed_;
  std::unique_ptr<capz::IntEncoder> enc_[8];
};

void breakdown(const capz::ScanGeometry& g, const capz::ScanHints& h) {
  capz::scan::Placement placed;
  const capz::scan::Table t = capz::scan::table_for(g, capz::scan::fit_rings(g, h),
                                                    breakdown_divisor, range_units, &placed);
  BreakdownIo io(g, placed);
  capz::scan::State st(t);
  std::vector<int32_t> q;
  std::vector<uint8_t> v;
  size_t first = 0;
  for (uint32_t n : g.counts) {
    q.resize(3 * size_t{n});
    v.resize(n);
    uint8_t flags = capz::scan::kSomeValid;
    if (t.rings() > 0 && capz::scan::spherical_ok(g, first, n))
      flags |= capz::scan::kSpherical | (ring_walk ? capz::scan::kRingWalk : 0) |
               (ring_pairs && !ring_walk ? capz::scan::kRingPairs : 0) |
               (breakdown_hypot ? capz::scan::kHypot : 0);
    capz::scan::code_frame(io, st, flags, first, n, q.data(), v.data());
    first += n;
  }
  std::printf("  rings %zu step %g columns %u\n", t.rings(), double(t.step), t.columns);
  io.print(g.total());
}

double ms_since(std::chrono::steady_clock::time_point t) {
  return std::chrono::duration<double, std::milli>(std::chrono::steady_clock::now() - t).count();
}

// Codes frames [a, b) at bound `bound` as one window; adds to the totals; false if not exact.
bool code_window(const std::vector<Frame>& frames, size_t a, size_t b, double bound, size_t* points,
                 size_t* bytes, double* enc_ms, double* dec_ms) {
  capz::ScanGeometry g;
  capz::ScanHints h;
  const double step = 2 * bound;
  if (range_units) h.grid_per_unit = 1.0 / step;
  for (size_t f = a; f < b; ++f) {
    const Frame& fr = frames[f];
    const size_t n = fr.xyz.size() / 3;
    g.counts.push_back(static_cast<uint32_t>(n));
    for (size_t i = 0; i < n; ++i) {
      const double* x = &fr.xyz[3 * i];
      const bool ok = std::isfinite(x[0]) && std::isfinite(x[1]) && std::isfinite(x[2]);
      g.valid.push_back(ok);
      for (int k = 0; k < 3; ++k) h.xyz.push_back(static_cast<float>(x[k]));
      for (int k = 0; k < 3; ++k)
        g.q.push_back(ok ? static_cast<int32_t>(std::floor(x[k] / step + 0.5)) : 0);
    }
    if (!fr.ring.empty()) h.ring.insert(h.ring.end(), fr.ring.begin(), fr.ring.end());
    h.distance.insert(h.distance.end(), fr.distance.begin(), fr.distance.end());
  }
  if (h.ring.size() != g.valid.size()) h.ring.clear();
  if (h.distance.size() != g.valid.size()) h.distance.clear();
  if (sorted_order) {  // each frame in the coded order of --point-order any
    const std::vector<uint32_t> order = capz::scan_point_order(g, h);
    capz::ScanGeometry s = g;
    capz::ScanHints sh = h;
    for (size_t j = 0; j < order.size(); ++j) {
      s.valid[j] = g.valid[order[j]];
      for (int k = 0; k < 3; ++k) {
        s.q[3 * j + k] = g.q[3 * order[j] + k];
        sh.xyz[3 * j + k] = h.xyz[3 * order[j] + k];
      }
      if (!h.ring.empty()) sh.ring[j] = h.ring[order[j]];
      if (!h.distance.empty()) sh.distance[j] = h.distance[order[j]];
    }
    g = std::move(s);
    h.ring.swap(sh.ring);
    h.xyz.swap(sh.xyz);
    h.distance.swap(sh.distance);
  }
  auto t0 = std::chrono::steady_clock::now();
  const std::vector<uint8_t> payload = capz::encode_scan_geometry(g, h);
  *enc_ms += ms_since(t0);
  t0 = std::chrono::steady_clock::now();
  const capz::ScanGeometry d = capz::decode_scan_geometry(payload.data(), payload.size(), "scan");
  *dec_ms += ms_since(t0);
  if (show_breakdown) breakdown(g, h);
  *points += g.valid.size();
  *bytes += payload.size();
  return d.counts == g.counts && d.valid == g.valid && d.q == g.q;
}

}  // namespace

int main(int argc, char** argv) {
  std::vector<double> bounds;
  std::vector<std::string> paths;
  bool use_ring = true;
  size_t window = 0, dump = 0;
  for (int i = 1; i < argc; ++i) {
    const std::string a = argv[i];
    if (a == "--bound" && i + 1 < argc) {
      bounds.push_back(std::atof(argv[++i]));
    } else if (a == "--breakdown") {
      show_breakdown = true;
    } else if (a == "--divisor" && i + 1 < argc) {
      breakdown_divisor = std::atof(argv[++i]);
    } else if (a == "--sorted") {
      sorted_order = true;
    } else if (a == "--pairs") {
      ring_pairs = true;
    } else if (a == "--walk") {
      ring_walk = true;
    } else if (a == "--hypot") {
      breakdown_hypot = true;
    } else if (a == "--no-units") {
      range_units = false;
    } else if (a == "--no-ring") {
      use_ring = false;
    } else if (a == "--dump" && i + 1 < argc) {
      dump = static_cast<size_t>(std::atol(argv[++i]));
    } else if (a == "--window" && i + 1 < argc) {
      window = static_cast<size_t>(std::atol(argv[++i]));
    } else {
      paths.push_back(a);
    }
  }
  if (bounds.empty()) bounds = {0.001, 0.01};
  bool exact = true;
  std::printf("%-28s %7s %9s %10s %8s %8s %8s\n", "sequence", "bound", "points", "bytes", "bits/pt",
              "enc_ms", "dec_ms");
  for (const std::string& p : paths) {
    std::vector<Frame> frames;
    for (const std::string& f : list_frames(p)) frames.push_back(read_frame(f, use_ring));
    for (size_t i = 0; !frames.empty() && i < dump && 3 * i < frames[0].xyz.size(); ++i) {
      const double* x = &frames[0].xyz[3 * i];
      std::printf("%zu ring %u az %.4f el %.4f rho %.4f z %.4f\n", i,
                  frames[0].ring.empty() ? 0u : frames[0].ring[i],
                  std::atan2(x[1], x[0]) * 57.29577951308232,
                  std::atan2(x[2], std::hypot(x[0], x[1])) * 57.29577951308232,
                  std::hypot(x[0], x[1]), x[2]);
    }
    std::string name = p;
    while (!name.empty() && name.back() == '/') name.pop_back();
    name = name.substr(name.find_last_of('/') + 1);
    for (double bound : bounds) {
      size_t points = 0, bytes = 0;
      double enc = 0, dec = 0;
      const size_t w = window ? window : std::max<size_t>(frames.size(), 1);
      for (size_t a = 0; a < frames.size(); a += w)
        exact &= code_window(frames, a, std::min(frames.size(), a + w), bound, &points, &bytes,
                             &enc, &dec);
      std::printf("%-28s %7g %9zu %10zu %8.3f %8.1f %8.1f\n", name.c_str(), bound, points, bytes,
                  points ? 8.0 * static_cast<double>(bytes) / static_cast<double>(points) : 0.0,
                  enc, dec);
    }
  }
  if (!exact) std::printf("ROUND TRIP NOT EXACT\n");
  return exact ? 0 : 1;
}
