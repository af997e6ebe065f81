// --point-order any (docs/FORMAT.md "Points reordered"): a ragged take with each frame's points
// in the coded order, for the ragged encoder (scan_encoder.cpp) to code and check against.
#pragma once

#include <cstdint>
#include <vector>

#include "capz/take.h"
#include "codec/grid.h"

namespace capz {

// t (a ragged take) with each frame's points, and their fields, in the order
// coding/scan_geometry.h's scan_point_order gives under `grid`, the table inferred per window
// of `window_frames` frames, as the encoder codes them. `ring`: the take's ring field of every
// point, or empty. The frames keep their counts and gaps (moved after their valid points).
Take reordered_take(const Take& t, const Grid& grid, uint32_t window_frames,
                    const std::vector<uint32_t>& ring);

}  // namespace capz
