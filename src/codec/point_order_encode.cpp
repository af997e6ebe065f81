// The ragged encoder's --point-order any (point_order.h).
#include <algorithm>

#include "capz/stream.h"
#include "codec/grid_choice.h"
#include "codec/point_order.h"
#include "coding/scan_geometry.h"

namespace capz {

namespace {

// g's points in `order`.
ScanGeometry permuted(const ScanGeometry& g, const std::vector<uint32_t>& order) {
  ScanGeometry s = g;
  for (size_t j = 0; j < order.size(); ++j) {
    s.valid[j] = g.valid[order[j]];
    std::copy_n(&g.q[3 * size_t{order[j]}], 3, &s.q[3 * j]);
  }
  return s;
}
ScanHints permuted(const ScanHints& h, const std::vector<uint32_t>& order) {
  ScanHints s = h;
  for (size_t j = 0; j < order.size(); ++j) {
    if (!h.ring.empty()) s.ring[j] = h.ring[order[j]];
    if (!h.xyz.empty()) std::copy_n(&h.xyz[3 * size_t{order[j]}], 3, &s.xyz[3 * j]);
  }
  return s;
}

// The coded order of frames [f0, f1) of t: indices from the window's first point.
std::vector<uint32_t> window_order(const Take& t, const Grid& grid, size_t f0, size_t f1,
                                   const std::vector<uint32_t>& ring) {
  const size_t p0 = t.frame_begin(f0), p1 = t.frame_begin(f1);
  FrameBlock b;
  b.frames = 1;
  b.points = p1 - p0;
  b.xyz.assign(t.xyz.begin() + static_cast<std::ptrdiff_t>(3 * p0),
               t.xyz.begin() + static_cast<std::ptrdiff_t>(3 * p1));
  b.valid.assign(t.valid.begin() + static_cast<std::ptrdiff_t>(p0),
                 t.valid.begin() + static_cast<std::ptrdiff_t>(p1));
  ScanGeometry g;
  for (size_t f = f0; f < f1; ++f) g.counts.push_back(static_cast<uint32_t>(t.frame_points(f)));
  g.q = quantise_window(b, grid).q;
  g.valid = std::move(b.valid);
  ScanHints hints;
  if (!ring.empty())
    hints.ring.assign(ring.begin() + static_cast<std::ptrdiff_t>(p0),
                      ring.begin() + static_cast<std::ptrdiff_t>(p1));
  hints.xyz.resize(b.xyz.size());
  for (size_t i = 0; i < b.xyz.size(); ++i) hints.xyz[i] = static_cast<float>(b.xyz[i]);
  // The smallest window payload of: each frame sorted under its own table, sorted under the
  // window's table, or the file's order (a sensor whose file order is its firing order already,
  // or one no table describes); the encoder's choice, any order being allowed.
  std::vector<uint32_t> best(g.total());
  for (size_t j = 0; j < best.size(); ++j) best[j] = static_cast<uint32_t>(j);
  size_t least = encode_scan_geometry(g, hints).size();
  for (ScanOrderTable table : {ScanOrderTable::kPerFrame, ScanOrderTable::kWindow}) {
    std::vector<uint32_t> order = scan_point_order(g, hints, table);
    const size_t bytes = encode_scan_geometry(permuted(g, order), permuted(hints, order)).size();
    if (bytes < least) least = bytes, best.swap(order);
  }
  return best;
}

}  // namespace

Take reordered_take(const Take& t, const Grid& grid, uint32_t window_frames,
                    const std::vector<uint32_t>& ring) {
  Take r = t;
  const size_t wf = std::max<size_t>(window_frames, 1);
  for (size_t f0 = 0; f0 < t.frames; f0 += wf) {
    const size_t f1 = std::min(f0 + wf, t.frames), p0 = t.frame_begin(f0);
    const std::vector<uint32_t> order = window_order(t, grid, f0, f1, ring);
    for (size_t j = 0; j < order.size(); ++j) {
      const size_t from = p0 + order[j], to = p0 + j;
      std::copy_n(t.xyz.begin() + static_cast<std::ptrdiff_t>(3 * from), 3,
                  r.xyz.begin() + static_cast<std::ptrdiff_t>(3 * to));
      r.valid[to] = t.valid[from];
    }
    for (size_t a = 0; a < t.attributes.size(); ++a) {
      const size_t bpp = t.attributes[a].bytes_per_point();
      const std::vector<uint8_t>& src = t.attributes[a].data;
      if (src.size() != t.total_points() * bpp) continue;  // dropped (--drop-fields)
      std::vector<uint8_t>& dst = r.attributes[a].data;
      for (size_t j = 0; j < order.size(); ++j)
        std::copy_n(src.begin() + static_cast<std::ptrdiff_t>((p0 + order[j]) * bpp), bpp,
                    dst.begin() + static_cast<std::ptrdiff_t>((p0 + j) * bpp));
    }
  }
  return r;
}

}  // namespace capz
