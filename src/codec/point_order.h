// --point-order any (docs/FORMAT.md "Points reordered"): a window of a ragged take with each
// frame's points in the coded order, for the ragged encoder (scan_encoder.cpp) to code and check
// against.
#pragma once

#include <cstdint>
#include <vector>

#include "capz/stream.h"
#include "capz/take.h"
#include "codec/grid.h"

namespace capz {

// Block b (a window of a ragged take, as the encoder codes it) with each frame's points, and
// their fields, in the order coding/scan_geometry.h's scan_point_order gives under `grid`, the
// table inferred on the window. `ring`: the block's ring field of every point, or empty. The
// frames keep their counts and gaps (moved after their valid points). Returns false, b
// untouched, when the order chosen is the file's own.
bool reorder_window(FrameBlock* b, const Grid& grid, const std::vector<uint32_t>& ring,
                    const std::vector<float>& distance = {});

}  // namespace capz
