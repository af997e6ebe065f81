// Fuzz target: the scan geometry decoder (decode_scan_geometry, docs/FORMAT.md "Scans (format
// 1.1)") on arbitrary payloads, at most 2^20 points. A payload that decodes must re-encode to
// one that decodes to the same points, with cells with counts (scan_cells.h) as well when its
// frames hold runs of the same point, and as octree frames (scan_octree.h) in octree order:
// plainly, and with the counting models and the cones of the payload's table (when it has one),
// and as split frames (an octree near part and a far part).
#include <cstddef>
#include <cstdint>

#include "capz/error.h"
#include "coding/scan_cells.h"
#include "coding/scan_geometry.h"
#include "coding/scan_octree.h"
#include "coding/scan_shared.h"
#include "fuzz_common.h"

// o (each frame in octree order) as split frames (FORMAT.md "Split frames"): each frame's first
// half of its valid points with its gaps the near part, the rest the far part; decoded, each
// frame is its near part then its far part, as o holds them.
static void split_round_trip(const capz::ScanGeometry& o) {
  capz::ScanGeometry near, far, whole;
  std::vector<uint8_t> has_far;
  size_t first = 0;
  const auto take = [&](capz::ScanGeometry* to, size_t from, size_t n) {
    for (size_t i = from; i < from + n; ++i) {
      to->valid.push_back(o.valid[i]);
      to->q.insert(to->q.end(), &o.q[3 * i], &o.q[3 * i] + 3);
    }
  };
  for (uint32_t n : o.counts) {
    size_t valid = 0;
    while (valid < n && o.valid[first + valid]) ++valid;
    const size_t k = (valid + 1) / 2;  // near valid points
    near.counts.push_back(static_cast<uint32_t>(k > 0 ? k + n - valid : 0));
    if (k > 0) take(&near, first, k), take(&near, first + valid, n - valid);
    has_far.push_back(k == 0 || valid > k);
    if (has_far.back()) {
      far.counts.push_back(static_cast<uint32_t>(k > 0 ? valid - k : n));
      take(&far, first + k, k > 0 ? valid - k : n);
    }
    whole.counts.push_back(n);
    if (k > 0) take(&whole, first, k), take(&whole, first + valid, n - valid);
    if (has_far.back()) take(&whole, first + k, k > 0 ? valid - k : n);
    first += n;
  }
  const std::vector<uint8_t> split =
      capz::encode_scan_split(near, capz::encode_scan_geometry(far), has_far);
  if (split.empty()) return;
  const capz::ScanGeometry s =
      capz::decode_scan_geometry(split.data(), split.size(), "split", 1 << 20);
  CAPZ_FUZZ_CHECK(s.counts == whole.counts && s.valid == whole.valid && s.q == whole.q);
}

extern "C" int LLVMFuzzerTestOneInput(const uint8_t* data, size_t size) {
  try {
    const capz::ScanGeometry g = capz::decode_scan_geometry(data, size, "fuzz scan", 1 << 20);
    size_t total = 0;
    for (uint32_t n : g.counts) total += n;
    CAPZ_FUZZ_CHECK(g.valid.size() == total && g.q.size() == 3 * total);
    const std::vector<uint8_t> again = capz::encode_scan_geometry(g);
    const capz::ScanGeometry h =
        capz::decode_scan_geometry(again.data(), again.size(), "re-encoded", 1 << 20);
    CAPZ_FUZZ_CHECK(h.counts == g.counts && h.valid == g.valid && h.q == g.q);
    const std::vector<uint8_t> cells = capz::encode_scan_cells(g, {}, nullptr);
    if (!cells.empty()) {
      const capz::ScanGeometry c =
          capz::decode_scan_geometry(cells.data(), cells.size(), "with cells", 1 << 20);
      CAPZ_FUZZ_CHECK(c.counts == g.counts && c.valid == g.valid && c.q == g.q);
    }
    capz::ScanGeometry o = g;  // each frame in octree order, coded as octree frames
    size_t first = 0;
    for (uint32_t n : g.counts) {
      const std::vector<uint32_t> order = capz::octree_frame_order(g, first, n);
      for (size_t j = 0; j < n; ++j) {
        o.valid[first + j] = g.valid[first + order[j]];
        for (size_t a = 0; a < 3; ++a)
          o.q[3 * (first + j) + a] =
              g.valid[first + order[j]] ? g.q[3 * (first + order[j]) + a] : 0;
      }
      first += n;
    }
    split_round_trip(o);
    const capz::scan::Table table = capz::scan::read_header(data, size, "fuzz", 1 << 20).table;
    for (uint32_t l : {0u, 3u, 7u}) {  // no table; cones and counting models; and the mix
      const std::vector<uint8_t> tree = capz::encode_scan_octree(o, l ? &table : nullptr, l);
      if (tree.empty()) continue;
      const capz::ScanGeometry t =
          capz::decode_scan_geometry(tree.data(), tree.size(), "octree", 1 << 20);
      CAPZ_FUZZ_CHECK(t.counts == o.counts && t.valid == o.valid && t.q == o.q);
    }
  } catch (const capz::Error&) {
  }
  return 0;
}
