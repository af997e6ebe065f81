// Cells with counts (docs/FORMAT.md "Scans (format 1.1)", "Cells with counts"): a frame whose
// points share grid integers codes each run of them once, followed in a counts block of its own
// by the number of copies that follow it. The decoding side here (scan_cells.cpp), the encoding
// side in scan_cells_encode.cpp.
#pragma once

#include <cstddef>
#include <cstdint>
#include <vector>

#include "coding/entropy.h"
#include "coding/scan_geometry.h"

namespace capz {
namespace scan {

constexpr int kCellContexts = 16;

// A coded point's count context: the octave of its distance from the origin in grid steps,
// min(floor(bits(x^2 + y^2 + z^2) / 2), 15), the sum exact in 64 bits.
inline int cell_context(const int32_t* q) {
  const auto sq = [](int32_t v) {
    const auto a = static_cast<uint64_t>(v < 0 ? -static_cast<int64_t>(v) : v);
    return a * a;
  };
  const uint64_t s = sq(q[0]) + sq(q[1]) + sq(q[2]);  // < 3 * 2^62: no overflow
  const int bits = s == 0 ? 0 : 64 - __builtin_clzll(s);
  return bits / 2 < 15 ? bits / 2 : 15;
}

// A frame of n points whose first m = n - copies were decoded into q (3 per point) and valid:
// reads each valid coded point's count from `counts` and spreads the frame in place to its n
// points, each valid coded point followed by its copies. `scratch` is reused across frames.
// Throws Error(kCorrupt) through `counts` when the counts disagree with `copies`.
void expand_cells(IntDecoder* counts, uint32_t copies, size_t n, int32_t* q, uint8_t* valid,
                  std::vector<uint32_t>* scratch);

}  // namespace scan

// Encoder side (scan_cells_encode.cpp). The payload of g with cells with counts: every valid
// point equal to the valid point before it in its frame is a copy of it. Empty when no frame has
// copies, or when the payload of the points without their copies came out as a raster window
// with a fine shift (its integers are not the cells'): the caller then codes g as it is.
std::vector<uint8_t> encode_scan_cells(const ScanGeometry& g, const ScanHints& hints,
                                       ScanWorkspace* ws);
// The copies (valid points equal to the valid point before them in their frame) of g in the
// order group_cell_copies gives it, from any order: per frame, its valid points less its distinct
// valid points.
size_t scan_grouped_copies(const ScanGeometry& g);
// order (indices into g, each frame's points at its own places, as scan_point_order gives) with
// each valid point that has the grid integers of an earlier valid point of its frame (in
// `order`) moved to just after that point's run; the rest keeps its order.
std::vector<uint32_t> group_cell_copies(const ScanGeometry& g, const std::vector<uint32_t>& order);

}  // namespace capz
