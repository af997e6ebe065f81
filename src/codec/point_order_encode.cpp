// The ragged encoder's --point-order any (point_order.h).
#include <algorithm>

#include "capz/stream.h"
#include "codec/grid_choice.h"
#include "codec/point_order.h"
#include "coding/scan_cells.h"
#include "coding/scan_geometry.h"
#include "coding/scan_octree.h"

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
    if (!h.distance.empty()) s.distance[j] = h.distance[order[j]];
    if (!h.xyz.empty()) std::copy_n(&h.xyz[3 * size_t{order[j]}], 3, &s.xyz[3 * j]);
  }
  return s;
}

// Whether cells with counts (FORMAT.md "Cells with counts") are worth a trial on g: when the
// copies are at least 2 % of the valid points (else the counts cost about what the copies save).
// How many copies a frame has does not depend on its order.
bool cells_worth_trying(const ScanGeometry& g) {
  const size_t valid = static_cast<size_t>(std::count(g.valid.begin(), g.valid.end(), 1));
  return valid > 0 && scan_grouped_copies(g) * 50 >= valid;
}

// Cells with counts: `best` with each point's copies moved to just after it, coded with counts,
// replaces *coded when smaller; then the same with each frame ring by ring (`by_ring`:
// scan_point_order's kPerFrameByRing order).
void try_cells(const ScanGeometry& g, const ScanHints& hints, std::vector<uint8_t>* coded,
               std::vector<uint32_t>* best, const std::vector<uint32_t>& by_ring,
               ScanWorkspace* ws) {
  const std::vector<uint32_t>* orders[2] = {best, &by_ring};
  for (const std::vector<uint32_t>* from : orders) {
    std::vector<uint32_t> order = group_cell_copies(g, *from);
    const ScanGeometry grouped = permuted(g, order);
    std::vector<uint8_t> bytes = encode_scan_cells(grouped, permuted(hints, order), ws);
    if (!bytes.empty() && bytes.size() < coded->size()) coded->swap(bytes), best->swap(order);
  }
}

// Whether a window of several frames is worth coding as octree frames: its first frame alone as
// an octree (with no frame before it, its dearest) within 5/4 of that frame's share of `coded`
// bytes by points. A far scene's octree is far above it, a near one's below it (at 1 cm, the
// first frames' octrees against the archives' bits a point: pandar64 1.7, the E1 0.9, the
// Helios 0.8; docs/lab/2026-11-29-octree-1cm.md).
bool octree_worth_trying(const ScanGeometry& g, size_t coded) {
  const size_t n = g.counts.empty() ? 0 : g.counts[0];
  if (g.counts.size() < 2 || n == 0) return true;
  ScanGeometry first;
  first.counts = {g.counts[0]};
  first.q.reserve(3 * n);
  for (uint32_t j : octree_frame_order(g, 0, n)) {
    first.q.insert(first.q.end(), &g.q[3 * size_t{j}], &g.q[3 * size_t{j} + 3]);
    first.valid.push_back(g.valid[j]);
  }
  const std::vector<uint8_t> bytes = encode_scan_octree(first);
  return !bytes.empty() &&
         double(bytes.size()) * double(g.total()) <= 1.25 * double(coded) * double(n);
}

// Octree frames (FORMAT.md "Octree frames"): each frame's points in octree order, every frame
// with a valid point an octree frame, without a table and with the cones of the one fitted to
// the window (hints: g's). True, with the smallest payload in *bytes and its order in *order,
// when that payload is smaller than `coded`.
bool octree_window(const ScanGeometry& g, const ScanHints& hints, const std::vector<uint8_t>& coded,
                   std::vector<uint8_t>* bytes, std::vector<uint32_t>* order) {
  if (!octree_worth_trying(g, coded.size())) return false;
  order->clear();
  order->reserve(g.total());
  size_t first = 0;
  for (uint32_t n : g.counts) {
    for (uint32_t j : octree_frame_order(g, first, n))
      order->push_back(static_cast<uint32_t>(first + j));
    first += n;
  }
  const ScanGeometry sorted = permuted(g, *order);
  *bytes = encode_scan_octree(sorted);
  if (bytes->empty()) return false;
  // With the table's cones and the counting models (L = 3; 1 and 2 were never the smallest
  // where 3 could be: docs/lab/2026-11-30-octree-cones.md), unless the payload without them is
  // above 5/4 of `coded`: they saved at most 11 % (docs/lab/2026-11-30-octree-fields.md).
  if (4 * bytes->size() > 5 * coded.size()) return false;
  const scan::Table table = octree_cone_table(g, hints);
  if (table.rings() > 0) {
    std::vector<uint8_t> other = encode_scan_octree(sorted, &table, 3);
    if (other.size() < bytes->size()) bytes->swap(other);
  }
  return bytes->size() < coded.size();
}

// The coded order of the points of block b (a window's frames, ragged): indices from its first
// point; *coded: the geometry's bytes in that order, *kept (when not null): in the file's order.
// With octree_coded (and octree_order) not null, octree frames are not chosen but put there
// (left empty when not smaller than *coded).
std::vector<uint32_t> window_order(const FrameBlock& b, const Grid& grid,
                                   const std::vector<uint32_t>& ring,
                                   const std::vector<float>& distance, std::vector<uint8_t>* coded,
                                   std::vector<uint8_t>* kept, ScanWorkspace* ws, bool octree,
                                   std::vector<uint8_t>* octree_coded,
                                   std::vector<uint32_t>* octree_order) {
  ScanGeometry g;
  for (size_t k = 0; k < b.frames; ++k)
    g.counts.push_back(static_cast<uint32_t>(b.frame_points(k)));
  g.q = quantise_window(b, grid).q;
  g.valid = b.valid;
  ScanHints hints;
  hints.ring = ring;
  hints.distance = distance;
  hints.grid_per_unit = grid_per_unit(grid);
  bound_hints(grid, &hints);
  hints.xyz.resize(b.xyz.size());
  for (size_t i = 0; i < b.xyz.size(); ++i) hints.xyz[i] = static_cast<float>(b.xyz[i]);
  // Whether the elevations' rings differ from the ring field's: the same in every order.
  if (!hints.ring.empty()) hints.elevation_rings = scan_rings_differ(g, hints) ? 1 : 0;
  // The smallest window payload of: each frame sorted under its own table, sorted under the
  // window's table, or the file's order (a sensor whose file order is its firing order already,
  // or one no table describes); the encoder's choice, any order being allowed.
  std::vector<uint32_t> best(g.total());
  for (size_t j = 0; j < best.size(); ++j) best[j] = static_cast<uint32_t>(j);
  std::vector<uint8_t> file = encode_scan_geometry(g, hints, ws);
  *coded = file;
  const bool cells = cells_worth_trying(g);
  // The sorted orders of rings from `h` (the window's hints, or without their ring field), coded
  // with h (encode_scan_geometry tries the elevations' rings too where h has a ring field).
  const auto try_orders = [&](const ScanHints& h) {
    std::vector<uint32_t> by_ring;  // with cells: the per-frame tables' order ring by ring
    for (ScanOrderTable table : {ScanOrderTable::kPerFrame, ScanOrderTable::kWindow}) {
      std::vector<uint32_t> order = scan_point_order(
          g, h, table, cells && table == ScanOrderTable::kPerFrame ? &by_ring : nullptr);
      std::vector<uint8_t> bytes = encode_scan_geometry(permuted(g, order), permuted(h, order), ws);
      if (bytes.size() < coded->size()) coded->swap(bytes), best.swap(order);
    }
    if (cells) try_cells(g, h, coded, &best, by_ring, ws);
  };
  // Where the elevations' rings differ from the ring field's (the Helios 16P's near points), the
  // orders of the elevations' rings alone: the field's orders, each coded under both ring sets,
  // gave the same archives at 1 mm and 1 cm (octree frames) for 2.5 times the work.
  if (hints.elevation_rings != 1) try_orders(hints);
  if (hints.elevation_rings == 1) {
    ScanHints elevations = hints;
    elevations.ring.clear();
    try_orders(elevations);
  }
  // Octree frames: with octree_coded, offered (the caller compares whole windows); else chosen
  // when their payload is the smallest.
  std::vector<uint8_t> bytes;
  std::vector<uint32_t> order;
  if (cells && octree && octree_window(g, hints, *coded, &bytes, &order)) {
    if (octree_coded)
      octree_coded->swap(bytes), octree_order->swap(order);
    else
      coded->swap(bytes), best.swap(order);
  }
  if (kept) kept->swap(file);
  return best;
}

// v's elements of `size` bytes (or values) each in `order`.
template <typename T>
void permute(std::vector<T>* v, size_t size, const std::vector<uint32_t>& order) {
  std::vector<T> out(v->size());
  for (size_t j = 0; j < order.size(); ++j)
    std::copy_n(v->begin() + static_cast<std::ptrdiff_t>(size * order[j]), size,
                out.begin() + static_cast<std::ptrdiff_t>(size * j));
  v->swap(out);
}

// b's points, and their fields, in `order`.
void permute_block(FrameBlock* b, const std::vector<uint32_t>& order) {
  permute(&b->xyz, 3, order);
  permute(&b->valid, 1, order);
  const size_t n = b->total_points();
  for (std::vector<uint8_t>& a : b->attributes)
    if (n > 0 && a.size() % n == 0) permute(&a, a.size() / n, order);
}

}  // namespace

bool reorder_window(FrameBlock* b, const Grid& grid, const std::vector<uint32_t>& ring,
                    const std::vector<float>& distance, std::vector<uint8_t>* coded,
                    std::vector<uint8_t>* kept, ScanWorkspace* ws, bool octree,
                    OctreeOffer* offer) {
  std::vector<uint32_t> octree_order;
  if (offer) offer->coded.clear();
  const std::vector<uint32_t> order =
      window_order(*b, grid, ring, distance, coded, kept, ws, octree,
                   offer ? &offer->coded : nullptr, offer ? &octree_order : nullptr);
  if (offer && !offer->coded.empty()) {
    offer->block = *b;
    permute_block(&offer->block, octree_order);
  }
  bool moved = false;
  for (size_t j = 0; j < order.size() && !moved; ++j) moved = order[j] != j;
  if (!moved) return false;
  permute_block(b, order);
  return true;
}

}  // namespace capz
