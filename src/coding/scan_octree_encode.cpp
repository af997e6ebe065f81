// Octree frames, the encoding side (scan_octree.h; docs/FORMAT.md "Octree frames").
#include <algorithm>
#include <cstdint>

#include "capz/error.h"
#include "coding/bytes.h"
#include "coding/scan_octree.h"
#include "coding/scan_shared.h"
#include "coding/scan_table.h"

namespace capz {

namespace {

// The frame's least integers and its tree's depth; false when it has no valid point or its
// valid points span 2^21 or more on an axis.
bool frame_cube(const ScanGeometry& g, size_t first, size_t n, int64_t* lo, int* depth) {
  int64_t hi[3] = {0, 0, 0};
  bool any = false;
  for (size_t i = first; i < first + n; ++i) {
    if (!g.valid[i]) continue;
    for (int a = 0; a < 3; ++a) {
      const int64_t v = g.q[3 * i + static_cast<size_t>(a)];
      lo[a] = any ? std::min(lo[a], v) : v;
      hi[a] = any ? std::max(hi[a], v) : v;
    }
    any = true;
  }
  if (!any) return false;
  int64_t ext = 1;
  for (int a = 0; a < 3; ++a) ext = std::max(ext, hi[a] - lo[a] + 1);
  *depth = 0;
  while ((int64_t{1} << *depth) < ext) ++*depth;
  if (*depth > scan::kMaxOctreeDepth) return false;
  for (int a = 0; a < 3; ++a)  // the cube within the int32 integers (FORMAT.md step 3)
    if (lo[a] + (int64_t{1} << *depth) - 1 > INT32_MAX) return false;
  return true;
}

uint64_t cell_key(const ScanGeometry& g, size_t i, const int64_t* lo) {
  const int32_t* q = &g.q[3 * i];
  return scan::octree::key(static_cast<uint64_t>(q[0] - lo[0]), static_cast<uint64_t>(q[1] - lo[1]),
                           static_cast<uint64_t>(q[2] - lo[2]));
}

// The encoder's child bits: whether the child is a node of its level in the actual tree.
class EncodeBits {
 public:
  EncodeBits(IntEncoder* enc, std::vector<std::vector<uint64_t>> levels, scan::OctreeMode* mode)
      : enc_(enc), levels_(std::move(levels)), mode_(mode) {}
  bool bit(int ctx, int l, uint64_t child) {
    const std::vector<uint64_t>& next = levels_[static_cast<size_t>(l) + 1];
    const bool b = std::binary_search(next.begin(), next.end(), child);
    if (mode_ && mode_->counting()) {
      const uint32_t one = mode_->one(ctx), zero = kTotal - one;
      enc_->encode(b ? zero : 0, b ? one : zero);
      mode_->update(ctx, b);
    } else {
      enc_->put_symbol(b ? 1 : 0, ctx);
    }
    return b;
  }
  [[noreturn]] void too_many() { throw Error(ErrorCode::kInternal, "octree: a level too large"); }
  [[noreturn]] void too_much() { throw Error(ErrorCode::kInternal, "octree: cone work unbounded"); }

 private:
  IntEncoder* enc_;
  std::vector<std::vector<uint64_t>> levels_;
  scan::OctreeMode* mode_;
};

}  // namespace

bool octree_frame_ok(const ScanGeometry& g, size_t first, size_t n) {
  int64_t lo[3];
  int depth;
  return frame_cube(g, first, n, lo, &depth);
}

std::vector<uint32_t> octree_frame_order(const ScanGeometry& g, size_t first, size_t n) {
  int64_t lo[3] = {0, 0, 0};
  int depth = 0;
  const bool ok = frame_cube(g, first, n, lo, &depth);
  std::vector<uint32_t> order(n);
  for (size_t j = 0; j < n; ++j) order[j] = static_cast<uint32_t>(j);
  if (!ok) return order;
  std::vector<uint64_t> keys(n, 0);
  for (size_t j = 0; j < n; ++j)
    if (g.valid[first + j]) keys[j] = cell_key(g, first + j, lo);
  std::stable_sort(order.begin(), order.end(), [&](uint32_t a, uint32_t b) {
    const bool va = g.valid[first + a] != 0, vb = g.valid[first + b] != 0;
    if (va != vb) return va;
    return va && keys[a] < keys[b];
  });
  return order;
}

void encode_octree_frame(const ScanGeometry& g, size_t first, size_t n, uint32_t copies,
                         std::vector<int32_t>* prev, IntEncoder* enc, scan::OctreeMode* mode) {
  int64_t lo[3];
  int depth;
  if (!frame_cube(g, first, n, lo, &depth))
    throw Error(ErrorCode::kInternal, "octree frame without valid points or too wide");
  std::vector<uint64_t> cells;
  std::vector<uint32_t> points;
  size_t gaps = 0;
  for (size_t i = first; i < first + n; ++i) {
    if (!g.valid[i]) {
      ++gaps;
      continue;
    }
    if (gaps > 0) throw Error(ErrorCode::kInternal, "octree frame: a gap before a valid point");
    const uint64_t k = cell_key(g, i, lo);
    if (!cells.empty() && k == cells.back()) {
      ++points.back();
      continue;
    }
    if (!cells.empty() && k < cells.back())
      throw Error(ErrorCode::kInternal, "octree frame: points not in Morton order");
    cells.push_back(k);
    points.push_back(1);
  }
  if (n - gaps - cells.size() != copies)
    throw Error(ErrorCode::kInternal, "octree frame: copies disagree with the cells");
  if (gaps > 0) enc->put(static_cast<uint32_t>(gaps), scan::kOctCornerCtx);
  enc->put(static_cast<uint32_t>(depth), scan::kOctDepthCtx);
  for (int a = 0; a < 3; ++a) enc->put_signed(static_cast<int32_t>(lo[a]), scan::kOctCornerCtx);
  std::vector<std::vector<uint64_t>> levels(static_cast<size_t>(depth) + 1);
  levels.back() = cells;
  for (int l = depth - 1; l >= 0; --l)
    for (uint64_t k : levels[static_cast<size_t>(l) + 1])
      if (levels[static_cast<size_t>(l)].empty() || levels[static_cast<size_t>(l)].back() != k >> 3)
        levels[static_cast<size_t>(l)].push_back(k >> 3);
  EncodeBits io(enc, std::move(levels), mode);
  scan::octree::code_tree(io, depth, cells.size(), lo, *prev, mode ? mode->cones() : nullptr,
                          mode ? mode->mixer() : nullptr);
  std::vector<int32_t> mine;  // this frame's cells and points, for the next
  for (size_t j = 0; j < cells.size(); ++j) {
    int64_t v[3];
    scan::octree::coords(cells[j], v);
    for (int a = 0; a < 3; ++a) mine.push_back(static_cast<int32_t>(v[a] + lo[a]));
    mine.push_back(static_cast<int32_t>(points[j]));
  }
  if (copies > 0) {
    std::vector<uint32_t> seen(cells.size(), 1);
    scan::octree::KeySet set, before;
    set.reset(cells.size());
    for (size_t j = 0; j < cells.size(); ++j) set.insert(cells[j], static_cast<uint32_t>(j));
    scan::octree::previous_cells(*prev, lo, depth, &before);
    for (size_t j = 0; j < cells.size(); ++j) {
      int64_t v[3];
      scan::octree::coords(cells[j], v);
      for (int a = 0; a < 3; ++a) v[a] += lo[a];
      enc->put(points[j] - 1, scan::octree::count_context(cells, set, seen, j, v, before, *prev));
      seen[j] = points[j];
    }
  }
  prev->swap(mine);
}

scan::Table octree_cone_table(const ScanGeometry& g, const ScanHints& hints) {
  const scan::RingFit r = scan::fit_rings(g, hints, false, false);
  scan::Table t;
  if (r.rings() == 0 || r.rings() > scan::kMaxConeRings) return t;
  t.step = 1;  // no point is placed by it: any valid step and one column
  t.columns = 1;
  t.azimuth0.assign(r.rings(), 0.0f);
  t.slope = r.slope;
  t.z0 = r.z0;
  scan::pack_table(&t, r.reach);
  return t;
}

std::vector<uint8_t> encode_scan_octree(const ScanGeometry& g, const scan::Table* table,
                                        uint32_t l) {
  const size_t frames = g.counts.size();
  std::vector<uint8_t> flags(frames, 0);
  std::vector<uint32_t> copies(frames, 0);
  IntEncoder tree(scan::kOctreeContexts);
  scan::start_octree_block(&tree);
  const scan::Table none;
  if (!table || table->rings() == 0) table = &none, l = 0;
  if (table->rings() > scan::kMaxConeRings) l &= ~1u;
  if (!(l & 2)) l &= ~4u;  // the mix only with counting models
  scan::OctreeMode mode((l & 1) ? scan::table_cones(*table) : scan::Cones{}, (l & 2) != 0,
                        (l & 4) != 0);
  if (table->rings() > 0) tree.put(l, scan::kOctFlagsCtx);  // L (FORMAT.md "The block's flags")
  std::vector<int32_t> prev;  // the previous frame's cells and points when an octree frame
  size_t first = 0;
  for (size_t f = 0; f < frames; ++f) {
    const size_t n = g.counts[f];
    size_t valid = 0;
    for (size_t i = first; i < first + n; ++i) valid += g.valid[i] != 0;
    if (valid == 0) {
      flags[f] = scan::kNoneValid;
      prev.clear();
    } else {
      if (!octree_frame_ok(g, first, n)) return {};
      // copies: valid points equal to the valid point before them (octree order puts them there)
      for (size_t i = first + 1; i < first + n; ++i)
        copies[f] += g.valid[i] && g.valid[i - 1] &&
                     std::equal(&g.q[3 * i], &g.q[3 * i] + 3, &g.q[3 * (i - 1)]);
      flags[f] = static_cast<uint8_t>(scan::kOctreeFrame | (valid < n ? scan::kSomeValid : 0) |
                                      (copies[f] > 0 ? scan::kCells : 0));
      encode_octree_frame(g, first, n, copies[f], &prev, &tree, &mode);
    }
    first += n;
  }
  ByteWriter w;
  w.varint(frames);
  for (uint32_t n : g.counts) w.varint(n);
  for (uint8_t fl : flags) w.u8(fl);
  for (uint32_t d : copies)
    if (d > 0) w.varint(d);
  scan::write_table(*table, &w);  // K and the table
  if (std::any_of(flags.begin(), flags.end(), scan::octree_frame)) {
    const std::vector<uint8_t> block = tree.finish();
    // The decoder's bound on the cone work (FORMAT.md "The block's flags"): never reached by the
    // sweeps measured (docs/lab/2026-11-30-octree-cones.md), so such a window goes without.
    if (mode.cones() && mode.cones()->work > scan::kMaxConeWorkPerByte * block.size())
      return encode_scan_octree(g, table, l & ~1u);
    put_block(&w, block);
  }
  IntEncoder main_block(scan::kContexts);  // no point codes a symbol there
  w.bytes(main_block.finish());
  return std::move(w.buffer());
}

}  // namespace capz
