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

// *bytes (the plain octree payload of `sorted`, g's points in octree order), or the payload
// with the cones of g's laser table (L = 3; 1 and 2 were never the smallest where 3 could be:
// docs/lab/2026-11-30-octree-cones.md) or with the mix too (L = 7,
// docs/lab/2026-11-30-octree-mixing.md) when one of those is smaller.
void with_cones(const ScanGeometry& sorted, const ScanGeometry& g, const ScanHints& hints,
                std::vector<uint8_t>* bytes) {
  const scan::Table table = octree_cone_table(g, hints);
  if (table.rings() == 0) return;
  for (uint32_t l : {3u, 7u}) {
    std::vector<uint8_t> other = encode_scan_octree(sorted, &table, l);
    if (other.size() < bytes->size()) bytes->swap(other);
  }
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
  // With the cones and the mix (with_cones), unless the payload without them is above 5/4 of
  // `coded`: they saved at most 11 % (docs/lab/2026-11-30-octree-fields.md).
  if (4 * bytes->size() > 5 * coded.size()) return false;
  with_cones(sorted, g, hints, bytes);
  return bytes->size() < coded.size();
}

// g's points `idx` (window indices) as a geometry of frames of `counts` points, and their hints.
ScanGeometry picked(const ScanGeometry& g, const std::vector<uint32_t>& idx,
                    std::vector<uint32_t> counts) {
  ScanGeometry s;
  s.counts = std::move(counts);
  s.q.resize(3 * idx.size());
  s.valid.resize(idx.size());
  for (size_t j = 0; j < idx.size(); ++j) {
    s.valid[j] = g.valid[idx[j]];
    std::copy_n(&g.q[3 * size_t{idx[j]}], 3, &s.q[3 * j]);
  }
  return s;
}
ScanHints picked(const ScanHints& h, const std::vector<uint32_t>& idx) {
  ScanHints s = permuted(h, idx);
  if (!s.ring.empty()) s.ring.resize(idx.size());
  if (!s.distance.empty()) s.distance.resize(idx.size());
  if (!s.xyz.empty()) s.xyz.resize(3 * idx.size());
  return s;
}

// The far parts' payload (FORMAT.md "Split frames"): the far points in file order (`table`
// null) or sorted under *table, and with cells (ring by ring too) when they are worth a trial
// (the smaller kept; not tried without cells_allowed); its order in *order. The window's own
// choice of order is the far parts'.
std::vector<uint8_t> far_payload(const ScanGeometry& g, const ScanHints& h,
                                 const ScanOrderTable* table, ScanWorkspace* ws,
                                 std::vector<uint32_t>* order, bool cells_allowed = true) {
  const bool cells = cells_allowed && cells_worth_trying(g);
  std::vector<uint32_t> by_ring;
  if (table) {
    *order = scan_point_order(g, h, *table,
                              cells && *table == ScanOrderTable::kPerFrame ? &by_ring : nullptr);
  } else {
    order->resize(g.total());
    for (size_t j = 0; j < order->size(); ++j) (*order)[j] = static_cast<uint32_t>(j);
  }
  std::vector<uint8_t> coded = encode_scan_geometry(permuted(g, *order), permuted(h, *order), ws);
  if (cells && by_ring.empty()) by_ring = *order;
  if (cells) try_cells(g, h, &coded, order, by_ring, ws);
  return coded;
}

// Whether grid integers q lie within the radius whose square is r2 (grid units).
bool is_near(const int32_t* q, double r2) {
  const double x = q[0], y = q[1], z = q[2];
  return x * x + y * y + z * z < r2;
}

// A window's points parted at radius^2 r2 (FORMAT.md "Split frames"): per frame, when it has a
// valid point within the radius, those and its gaps are its near part and its other points its
// far part; else all of it is a far part. Indices into the window, each part in file order.
struct Parted {
  std::vector<uint32_t> near, far, near_counts, far_counts;
  std::vector<uint8_t> has_far;  // per frame
  size_t near_valid = 0, far_valid = 0;
  bool split = false;  // some frame has both parts
};

Parted part(const ScanGeometry& g, double r2) {
  Parted p;
  size_t first = 0;
  for (uint32_t n : g.counts) {
    size_t nv = 0, fv = 0;
    for (size_t i = first; i < first + n; ++i)
      if (g.valid[i]) ++(is_near(&g.q[3 * i], r2) ? nv : fv);
    const size_t nb = p.near.size(), fb = p.far.size();
    for (size_t i = first; i < first + n; ++i)
      (nv > 0 && (!g.valid[i] || is_near(&g.q[3 * i], r2)) ? p.near : p.far)
          .push_back(static_cast<uint32_t>(i));
    p.near_counts.push_back(static_cast<uint32_t>(p.near.size() - nb));
    p.has_far.push_back(nv == 0 || fv > 0);
    if (p.has_far.back()) p.far_counts.push_back(static_cast<uint32_t>(p.far.size() - fb));
    p.split = p.split || (nv > 0 && fv > 0);
    p.near_valid += nv, p.far_valid += fv;
    first += n;
  }
  return p;
}

// The window's order of a split: each frame's near part (near_order's) then its far part
// (p.far in far_order).
std::vector<uint32_t> split_order(const Parted& p, const std::vector<uint32_t>& near_order,
                                  const std::vector<uint32_t>& far_order) {
  std::vector<uint32_t> order;
  size_t at_near = 0, at_far = 0, k = 0;
  for (size_t f = 0; f < p.near_counts.size(); ++f) {
    order.insert(order.end(), near_order.begin() + static_cast<std::ptrdiff_t>(at_near),
                 near_order.begin() + static_cast<std::ptrdiff_t>(at_near + p.near_counts[f]));
    at_near += p.near_counts[f];
    if (!p.has_far[f]) continue;
    for (size_t j = at_far; j < at_far + p.far_counts[k]; ++j) order.push_back(p.far[far_order[j]]);
    at_far += p.far_counts[k++];
  }
  return order;
}

// The bytes of near's octree frames (their `cells` cells): of one frame coded; of several, the
// first frame's with a near part coded alone, times the cells over its cells (the later frames
// cost less, with the cells of the one before).
double near_octree_estimate(const ScanGeometry& near, size_t cells) {
  if (near.counts.size() < 2) return double(encode_scan_octree(near).size());
  size_t first = 0, f = 0;
  while (f < near.counts.size() && near.counts[f] == 0) ++f;
  if (f == near.counts.size()) return 0;
  ScanGeometry one;
  one.counts = {near.counts[f]};
  const size_t n = near.counts[f];
  for (size_t k = 0; k < f; ++k) first += near.counts[k];
  one.valid.assign(near.valid.begin() + static_cast<std::ptrdiff_t>(first),
                   near.valid.begin() + static_cast<std::ptrdiff_t>(first + n));
  one.q.assign(near.q.begin() + static_cast<std::ptrdiff_t>(3 * first),
               near.q.begin() + static_cast<std::ptrdiff_t>(3 * (first + n)));
  const size_t own = one.total() - scan_grouped_copies(one) -
                     static_cast<size_t>(std::count(one.valid.begin(), one.valid.end(), 0));
  return own == 0 ? 0 : double(encode_scan_octree(one).size()) * double(cells) / double(own);
}

// A split of a window at one radius: its parts, the near parts in octree order (as a geometry
// and as window indices), and the estimate of its payload.
struct Split {
  Parted p;
  ScanGeometry near;
  std::vector<uint32_t> near_order;
  double estimate = 0;
  double r2 = 0;  // the radius^2 (grid units)
};

// The split of g at radius^2 r2 and its estimate: the near parts' octree plus the far points'
// share of `per_point` (the window's best payload of the per-point coder, of whose valid points
// `copies` are copies). The octree: its cells at `per_cell` bytes (the window's octree payload a
// cell, its cones and the cells of the frames before included) when that is not 0, else
// near_octree_estimate less a tenth for the cones. False when no frame is split,
// or the near parts' copies are below 5 % of their valid points (the octree does not pay: at 1 cm
// the splits kept had 7 to 70 %; at 1 mm the near parts of hesai-ot128 and xt32 had 2 to 5 % and
// cost the octree trials a third of the compress without a split).
bool split_estimate(const ScanGeometry& g, double r2, size_t per_point, size_t copies,
                    double per_cell, Split* s) {
  s->p = part(g, r2);
  if (!s->p.split) return false;
  const Parted& p = s->p;
  s->near = picked(g, p.near, p.near_counts);
  s->near_order.clear();
  size_t first = 0;
  for (uint32_t n : s->near.counts) {
    for (uint32_t j : octree_frame_order(s->near, first, n))
      s->near_order.push_back(p.near[first + j]);
    first += n;
  }
  s->near = picked(g, s->near_order, p.near_counts);
  const size_t near_copies = scan_grouped_copies(s->near);
  if (near_copies * 20 < p.near_valid) return false;
  // The far points' share by points and by coded points (less copies, which cost little): the
  // mean of the two.
  const double coded = double(p.near_valid + p.far_valid - copies);
  const double far_coded =
      double(p.far_valid - scan_grouped_copies(picked(g, p.far, p.far_counts)));
  const double far_share = 0.5 * double(per_point) *
                           (double(p.far_valid) / double(p.near_valid + p.far_valid) +
                            (coded > 0 ? far_coded / coded : 0));
  const size_t cells = p.near_valid - near_copies;
  s->estimate = far_share + (per_cell > 0 ? per_cell * double(cells)
                                          : 0.9 * near_octree_estimate(s->near, cells));
  return true;
}

// Split s coded, its far parts in `table`'s order (far_payload's, with cells as `cells`
// allows) on ws: true, with the payload in *bytes and the window's order in *order, when the
// payload is below `limit` bytes.
bool split_coded(const ScanGeometry& g, const ScanHints& hints, const Split& s,
                 const ScanOrderTable* table, size_t limit, ScanWorkspace* ws,
                 std::vector<uint8_t>* bytes, std::vector<uint32_t>* order, bool cells = true) {
  const Parted& p = s.p;
  std::vector<uint32_t> far_order;
  const std::vector<uint8_t> far_bytes = far_payload(
      picked(g, p.far, p.far_counts), picked(hints, p.far), table, ws, &far_order, cells);
  std::vector<uint8_t> payload = encode_scan_split(s.near, far_bytes, p.has_far, 3);
  std::vector<uint8_t> mixed = encode_scan_split(s.near, far_bytes, p.has_far, 7);
  if (!mixed.empty() && (payload.empty() || mixed.size() < payload.size())) payload.swap(mixed);
  if (payload.empty() || payload.size() >= limit) return false;
  bytes->swap(payload);
  *order = split_order(p, s.near_order, far_order);
  return true;
}

// A window of one frame (g1, hints h1) as octree frames, as octree_window codes it: the bytes
// of the smaller payload with and without the cones, SIZE_MAX when it has none.
size_t octree_bytes(const ScanGeometry& g1, const ScanHints& h1) {
  const ScanGeometry sorted = permuted(g1, octree_frame_order(g1, 0, g1.total()));
  std::vector<uint8_t> bytes = encode_scan_octree(sorted);
  if (bytes.empty()) return SIZE_MAX;
  with_cones(sorted, g1, h1, &bytes);
  return bytes.size();
}

// The split of a window of several frames worth coding: each of `splits` (split_estimate's)
// coded on the window's first frame alone, the radius of the smallest kept (splits resized to
// it) when that is 1 % below the first frame's payload of the window's choice (octree: coded
// alone as octree frames; else its share of per_point by valid points). Both are that frame
// with no frame before it, its dearest; split_estimate misjudged the Helios' splits by 1.06 to
// 1.18 times, ranking the radii wrongly, and their first frames ranked them as their windows
// (docs/lab/2026-11-30-split-radius.md).
void first_frame_radius(const ScanGeometry& g, const ScanHints& hints, const ScanOrderTable* table,
                        size_t per_point, size_t octree, ScanWorkspace* ws,
                        std::vector<Split>* splits) {
  std::vector<uint32_t> idx(g.counts[0]);
  for (size_t j = 0; j < idx.size(); ++j) idx[j] = static_cast<uint32_t>(j);
  const ScanHints h1 = picked(hints, idx);
  const ScanGeometry g1 = picked(g, idx, {g.counts[0]});
  const size_t valid = static_cast<size_t>(std::count(g.valid.begin(), g.valid.end(), 1));
  const size_t valid1 = static_cast<size_t>(std::count(g1.valid.begin(), g1.valid.end(), 1));
  const size_t copies1 = scan_grouped_copies(g1);
  const size_t share = valid > 0 ? per_point * valid1 / valid : 0;
  size_t least = SIZE_MAX, at = 0;
  for (size_t k = 0; k < splits->size(); ++k) {
    Split s1;
    std::vector<uint8_t> bytes;
    std::vector<uint32_t> order;
    // (per_cell 1: the estimate is not used, and the near parts' octree not coded for it; the far
    // parts without cells: their two trials cost the most, on xt32m's far points 1.3 G
    // instructions each, and the Helios' first frames ranked the radii the same without them)
    if (split_estimate(g1, (*splits)[k].r2, share, copies1, 1, &s1) &&
        split_coded(g1, h1, s1, table, least, ws, &bytes, &order, false))
      least = bytes.size(), at = k;
  }
  const size_t reference = octree > 0 ? octree_bytes(g1, h1) : share;
  if (least == SIZE_MAX || double(least) >= 0.99 * double(reference)) {
    splits->clear();
    return;
  }
  std::swap((*splits)[0], (*splits)[at]);  // (not a move: at may be 0)
  splits->resize(1);
}

// Split frames (FORMAT.md "Split frames") at 1, 2, 4 or 8 m, below `limit` bytes: true, with the
// smallest payload in *bytes and the window's order in *order, else false. A window of several
// frames is coded at the radius first_frame_radius keeps, if any; a window of one frame at each
// radius whose estimate is below 1.15 of the smallest payload so far, least estimate first (the
// estimates rank the radii roughly: hesai-xt32m's smallest at 1 cm was 1.11 of the payload
// before it; one frame costs little). A split whose estimate is not below the payload to beat
// is coded with its far parts without cells (the Helios' window the same bytes either way).
// per_point: the window's best payload of the per-point coder; table: its order; octree: the bytes
// of its octree payload, or 0 (none smaller than per_point).
bool split_window(const ScanGeometry& g, const ScanHints& hints, const ScanOrderTable* table,
                  size_t per_point, size_t limit, size_t octree, const ScanWorkspace* window_ws,
                  std::vector<uint8_t>* bytes, std::vector<uint32_t>* order) {
  if (!(hints.grid_per_unit > 0) || g.total() == 0) return false;
  // Copies under 0.2 % of the valid points: a radius's near parts seldom have 5 % (vls128 at 1 cm
  // 0.4 %, split at 8 m with 7 %).
  const size_t copies = scan_grouped_copies(g);
  const size_t valid = static_cast<size_t>(std::count(g.valid.begin(), g.valid.end(), 1));
  if (copies * 500 < valid) return false;
  const double per_cell =
      octree > 0 && g.counts.size() > 1 ? double(octree) / double(valid - copies) : 0;
  std::vector<Split> splits;
  for (double metres : {1.0, 2.0, 4.0, 8.0}) {
    const double r = metres * hints.grid_per_unit;
    Split s;
    s.r2 = r * r;
    if (split_estimate(g, r * r, per_point, copies, per_cell, &s)) splits.push_back(std::move(s));
  }
  // A copy of the encoder's: its remembered table choice spares the far payload a choice of its
  // own, and that does not move the encoder's (the maps are shared memory, reset by each payload).
  ScanWorkspace ws = window_ws ? *window_ws : ScanWorkspace{};
  const bool one = g.counts.size() == 1;
  // Several frames: the radii estimated within 5/4 of the limit (the Helios' best at 1.11),
  // the first frame's choice among them.
  if (!one)
    splits.erase(std::remove_if(splits.begin(), splits.end(),
                                [&](const Split& s) { return s.estimate >= 1.25 * double(limit); }),
                 splits.end());
  if (!one && !splits.empty()) first_frame_radius(g, hints, table, per_point, octree, &ws, &splits);
  std::sort(splits.begin(), splits.end(),
            [](const Split& a, const Split& b) { return a.estimate < b.estimate; });
  bool found = false;
  for (const Split& s : splits) {
    const size_t most = found ? bytes->size() : limit;
    if (one && s.estimate >= 1.15 * double(most)) break;
    found = split_coded(g, hints, s, table, most, &ws, bytes, order, s.estimate < double(most)) ||
            found;
  }
  return found;
}

// The coded order of the points of block b (a window's frames, ragged): indices from its first
// point; *coded: the geometry's bytes in that order, *kept (when not null): in the file's order.
// With octree_coded (and octree_order) not null, octree frames are not chosen but put there
// (left empty when not smaller than *coded); split: split frames are tried where octree frames
// are, and offered or chosen as they are.
std::vector<uint32_t> window_order(const FrameBlock& b, const Grid& grid,
                                   const std::vector<uint32_t>& ring,
                                   const std::vector<float>& distance, std::vector<uint8_t>* coded,
                                   std::vector<uint8_t>* kept, ScanWorkspace* ws, bool octree,
                                   std::vector<uint8_t>* octree_coded,
                                   std::vector<uint32_t>* octree_order, bool split) {
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
  ScanOrderTable won = ScanOrderTable::kPerFrame;  // the order of *coded (with `sorted`)
  bool sorted = false;
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
      if (bytes.size() < coded->size())
        coded->swap(bytes), best.swap(order), won = table, sorted = true;
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
  bool tree = cells && octree && octree_window(g, hints, *coded, &bytes, &order);
  // Split frames, where octree frames may be (near copies are the split's own gate): chosen or
  // offered as octree frames are.
  if (octree && split &&
      split_window(g, hints, sorted ? &won : nullptr, coded->size(),
                   tree ? bytes.size() : coded->size(), tree ? bytes.size() : 0, ws, &bytes,
                   &order))
    tree = true;
  if (tree) {
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
                    std::vector<uint8_t>* kept, ScanWorkspace* ws, bool octree, OctreeOffer* offer,
                    bool split) {
  std::vector<uint32_t> octree_order;
  if (offer) offer->coded.clear();
  const std::vector<uint32_t> order =
      window_order(*b, grid, ring, distance, coded, kept, ws, octree,
                   offer ? &offer->coded : nullptr, offer ? &octree_order : nullptr, split);
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
