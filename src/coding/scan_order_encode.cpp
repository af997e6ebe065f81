// The coded order of --point-order any (docs/FORMAT.md "Points reordered"): each frame's points
// in the laser's firing order under the table the scan encoder infers.
#include <algorithm>
#include <tuple>

#include "capz/error.h"
#include "coding/scan_geometry.h"
#include "coding/scan_shared.h"
#include "coding/scan_table.h"

namespace capz {

namespace {

// A placed point's sort key: column, ring, range, then its place in the file (or ring first).
struct Placed {
  int32_t column;
  uint32_t ring;
  int32_t range;
  uint32_t index;
  bool operator<(const Placed& o) const {
    return std::tie(column, ring, range, index) < std::tie(o.column, o.ring, o.range, o.index);
  }
  static bool by_ring(const Placed& a, const Placed& b) {
    return std::tie(a.ring, a.column, a.range, a.index) <
           std::tie(b.ring, b.column, b.range, b.index);
  }
};

// Appends the order of frame [first, first + n) to *out: the placed points sorted, the valid
// points the table does not place in file order, then the gaps.
void order_frame(const ScanGeometry& g, bool table, const std::vector<scan::Polar>& polar,
                 size_t first, size_t n, std::vector<uint32_t>* out, bool by_ring = false) {
  std::vector<Placed> placed;
  std::vector<uint32_t> rest, gaps;
  placed.reserve(n);
  for (size_t i = first; i < first + n; ++i) {
    const auto idx = static_cast<uint32_t>(i);
    if (!g.valid[i])
      gaps.push_back(idx);
    else if (table && scan::spherical_ok(g, i, 1))
      placed.push_back(Placed{polar[i].column, polar[i].ring, polar[i].range, idx});
    else
      rest.push_back(idx);
  }
  if (by_ring)
    std::sort(placed.begin(), placed.end(), Placed::by_ring);
  else
    std::sort(placed.begin(), placed.end());
  for (const Placed& p : placed) out->push_back(p.index);
  out->insert(out->end(), rest.begin(), rest.end());
  out->insert(out->end(), gaps.begin(), gaps.end());
}

// The order of points [first, first + n) of g (one frame), under the table inferred from that
// frame alone with the step of its rings' sorted azimuths (sorted_step: over a window the
// sweeps' azimuths would interleave), appended to *out by column (or by ring with `by_ring`)
// and, when ring_out is not null, ring by ring to *ring_out as well (one fit for both).
void order_one(const ScanGeometry& g, const ScanHints& hints, size_t first, size_t n,
               std::vector<uint32_t>* out, bool by_ring, std::vector<uint32_t>* ring_out) {
  ScanGeometry f;
  f.counts = {static_cast<uint32_t>(n)};
  const auto b = static_cast<std::ptrdiff_t>(first), e = static_cast<std::ptrdiff_t>(first + n);
  f.q.assign(g.q.begin() + 3 * b, g.q.begin() + 3 * e);
  f.valid.assign(g.valid.begin() + b, g.valid.begin() + e);
  ScanHints h;
  if (hints.ring.size() == g.total()) h.ring.assign(hints.ring.begin() + b, hints.ring.begin() + e);
  if (hints.xyz.size() == 3 * g.total())
    h.xyz.assign(hints.xyz.begin() + 3 * b, hints.xyz.begin() + 3 * e);
  scan::RingFit fit = scan::fit_rings(f, h, false, false);
  fit.step = scan::sorted_step(fit);  // the sensor's step, whatever the file's order
  scan::Placement placed;
  const scan::Table t = scan::table_for(f, fit, 1.0, false, &placed);
  for (std::vector<uint32_t>* o : {out, ring_out}) {
    if (o == nullptr) continue;
    const size_t at = o->size();
    order_frame(f, t.rings() > 0, placed.polar, 0, n, o, o == ring_out || by_ring);
    for (size_t j = at; j < o->size(); ++j) (*o)[j] += static_cast<uint32_t>(first);
  }
}

}  // namespace

std::vector<uint32_t> scan_point_order(const ScanGeometry& g, const ScanHints& hints,
                                       ScanOrderTable table, std::vector<uint32_t>* by_ring) {
  size_t total = 0;
  for (uint32_t n : g.counts) total += n;
  if (g.valid.size() != total || g.q.size() != 3 * total || total > UINT32_MAX)
    fail(ErrorCode::kInternal, "scan geometry", "the points disagree with the frames' counts");
  std::vector<uint32_t> order;
  order.reserve(total);
  size_t first = 0;
  if (by_ring) by_ring->clear();
  if (table != ScanOrderTable::kWindow) {
    if (by_ring && table == ScanOrderTable::kPerFrame) by_ring->reserve(total);
    for (uint32_t n : g.counts) {
      order_one(g, hints, first, n, &order, table == ScanOrderTable::kPerFrameByRing,
                table == ScanOrderTable::kPerFrame ? by_ring : nullptr);
      first += n;
    }
    return order;
  }
  // The payload's own inference, but for the range units and the firing's base and slots (the
  // order's table, of the step as found, has none of them).
  const scan::RingFit fit = scan::fit_rings(g, hints, false, false);
  scan::Placement placed;
  const scan::Table t = scan::table_for(g, fit, 1.0, false, &placed);
  for (uint32_t n : g.counts) {
    order_frame(g, t.rings() > 0, placed.polar, first, n, &order);
    first += n;
  }
  return order;
}

}  // namespace capz
