// Cells with counts, the encoding side (scan_cells.h; docs/FORMAT.md "Cells with counts").
#include <algorithm>
#include <numeric>

#include "capz/error.h"
#include "coding/bytes.h"
#include "coding/scan_cells.h"
#include "coding/scan_shared.h"

namespace capz {

namespace {

bool same_point(const ScanGeometry& g, size_t i, size_t j) {
  return std::equal(&g.q[3 * i], &g.q[3 * i] + 3, &g.q[3 * j]);
}

// Whether point i of g (not a frame's first) is a copy of the point before it.
bool is_copy(const ScanGeometry& g, size_t i) {
  return g.valid[i] && g.valid[i - 1] && same_point(g, i, i - 1);
}

// g without its copies, the hints of the points kept, per frame its copies and per point kept
// its count.
struct Cells {
  ScanGeometry coded;
  ScanHints hints;
  std::vector<uint32_t> copies, count;
};

Cells split_cells(const ScanGeometry& g, const ScanHints& hints) {
  Cells c;
  c.hints.grid_per_unit = hints.grid_per_unit;
  c.hints.elevation_rings = hints.elevation_rings;
  // No bound: a raster window's fine shift would code other integers than the cells' (their
  // copies' sources are up to a grid step apart).
  size_t first = 0;
  for (uint32_t n : g.counts) {
    uint32_t copies = 0;
    for (size_t i = first; i < first + n; ++i) {
      if (i > first && is_copy(g, i)) {
        ++copies;
        ++c.count.back();
        continue;
      }
      c.coded.q.insert(c.coded.q.end(), &g.q[3 * i], &g.q[3 * i] + 3);
      c.coded.valid.push_back(g.valid[i]);
      c.count.push_back(0);
      if (!hints.ring.empty()) c.hints.ring.push_back(hints.ring[i]);
      if (!hints.distance.empty()) c.hints.distance.push_back(hints.distance[i]);
      if (!hints.xyz.empty())
        c.hints.xyz.insert(c.hints.xyz.end(), &hints.xyz[3 * i], &hints.xyz[3 * i] + 3);
    }
    c.coded.counts.push_back(n - copies);
    c.copies.push_back(copies);
    first += n;
  }
  return c;
}

// The counts block: per frame with copies, each valid coded point's count.
std::vector<uint8_t> code_counts(const Cells& c) {
  IntEncoder enc(scan::kCellContexts);
  size_t first = 0;
  for (size_t f = 0; f < c.coded.counts.size(); ++f) {
    const size_t m = c.coded.counts[f];
    for (size_t i = first; c.copies[f] > 0 && i < first + m; ++i)
      if (c.coded.valid[i]) enc.put(c.count[i], scan::cell_context(&c.coded.q[3 * i]));
    first += m;
  }
  return enc.finish();
}

}  // namespace

size_t scan_grouped_copies(const ScanGeometry& g) {
  // Per frame, its distinct valid points in an open-addressed table of point indices (0: empty).
  std::vector<uint32_t> slot;
  size_t copies = 0, first = 0;
  for (uint32_t n : g.counts) {
    size_t size = 16;
    while (size < 2 * size_t{n}) size *= 2;
    slot.assign(size, 0);
    for (size_t i = first; i < first + n; ++i) {
      if (!g.valid[i]) continue;
      const int32_t* p = &g.q[3 * i];
      uint64_t h = static_cast<uint32_t>(p[0]);
      h = h * 0x9E3779B97F4A7C15ull + static_cast<uint32_t>(p[1]);
      h = h * 0x9E3779B97F4A7C15ull + static_cast<uint32_t>(p[2]);
      h *= 0x9E3779B97F4A7C15ull;
      for (size_t at = static_cast<size_t>(h >> 32) & (size - 1);; at = (at + 1) & (size - 1)) {
        if (slot[at] == 0) {
          slot[at] = static_cast<uint32_t>(i - first + 1);
          break;
        }
        if (same_point(g, first + slot[at] - 1, i)) {
          ++copies;
          break;
        }
      }
    }
    first += n;
  }
  return copies;
}

std::vector<uint32_t> group_cell_copies(const ScanGeometry& g, const std::vector<uint32_t>& order) {
  std::vector<uint32_t> out;
  out.reserve(order.size());
  std::vector<size_t> by_point;  // a frame's positions in `order`, sorted by point then position
  std::vector<size_t> lead;
  size_t first = 0;
  for (uint32_t n : g.counts) {
    const uint32_t* o = order.data() + first;
    by_point.resize(n);
    std::iota(by_point.begin(), by_point.end(), size_t{0});
    const auto same_run = [&](size_t a, size_t b) {
      return g.valid[o[a]] && g.valid[o[b]] && same_point(g, o[a], o[b]);
    };
    std::sort(by_point.begin(), by_point.end(), [&](size_t a, size_t b) {
      const int32_t *p = &g.q[3 * size_t{o[a]}], *r = &g.q[3 * size_t{o[b]}];
      if (g.valid[o[a]] != g.valid[o[b]]) return g.valid[o[a]] > g.valid[o[b]];
      if (g.valid[o[a]] && !std::equal(p, p + 3, r))
        return std::lexicographical_compare(p, p + 3, r, r + 3);
      return a < b;
    });
    // A run's points are together in by_point, its first position first: lead[a] is the index
    // in by_point of a's run's first when a is that first, else SIZE_MAX.
    lead.assign(n, SIZE_MAX);
    for (size_t k = 0; k < n; ++k)
      if (!(k > 0 && same_run(by_point[k - 1], by_point[k]))) lead[by_point[k]] = k;
    for (size_t a = 0; a < n; ++a) {
      if (lead[a] == SIZE_MAX) continue;
      out.push_back(o[a]);
      for (size_t k = lead[a] + 1; k < n && same_run(by_point[k - 1], by_point[k]); ++k)
        out.push_back(o[by_point[k]]);
    }
    first += n;
  }
  return out;
}

std::vector<uint8_t> encode_scan_cells(const ScanGeometry& g, const ScanHints& hints,
                                       ScanWorkspace* ws) {
  const Cells c = split_cells(g, hints);
  if (std::all_of(c.copies.begin(), c.copies.end(), [](uint32_t d) { return d == 0; })) return {};
  const std::vector<uint8_t> plain = encode_scan_geometry(c.coded, c.hints, ws);
  if (scan_fine_shift(plain.data(), plain.size(), "scan cells") > 0) return {};
  // plain's header with the frames' own counts, bit 4 and d_f, then the counts block before its
  // entropy-coded block (plain has no d_f: K follows its flags).
  const scan::Header h = scan::read_header(plain.data(), plain.size(), "scan cells", SIZE_MAX);
  const size_t frames = h.counts.size(), table = h.flags_end;
  ByteWriter w;
  w.varint(frames);
  for (uint32_t n : g.counts) w.varint(n);
  for (size_t f = 0; f < frames; ++f)
    w.u8(static_cast<uint8_t>(h.flags[f] | (c.copies[f] > 0 ? scan::kCells : 0)));
  for (uint32_t d : c.copies)
    if (d > 0) w.varint(d);
  w.bytes(plain.data() + table, h.body - table);
  put_block(&w, code_counts(c));
  w.bytes(plain.data() + h.body, plain.size() - h.body);
  return std::move(w.buffer());
}

}  // namespace capz
