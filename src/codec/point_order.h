// --point-order any (docs/FORMAT.md "Points reordered"): a window of a ragged take with each
// frame's points in the coded order, for the ragged encoder (scan_encoder.cpp) to code and check
// against.
#pragma once

#include <cstdint>
#include <vector>

#include "capz/stream.h"
#include "capz/take.h"
#include "codec/grid.h"
#include "coding/scan_geometry.h"

namespace capz {

// Block b (a window of a ragged take, as the encoder codes it) with each frame's points, and
// their fields, in the order coding/scan_geometry.h's scan_point_order gives under `grid`, the
// table inferred on the window. `ring`: the block's ring field of every point, or empty. The
// frames keep their counts and gaps (moved after their valid points). Returns false, b
// untouched, when the order chosen is the file's own. `distance`: the block's distance field
// (ScanHints::distance), or empty. The choice codes the window's geometry in
// each candidate order: *coded gets encode_scan_geometry's bytes of the order chosen and *kept
// those of the file's order (the same when that was chosen), so the encoder need not code them
// again (kept may be null). ws: the encoder's workspace kept across windows, or null. octree:
// octree frames are among the candidates (docs/FORMAT.md "Octree frames"), chosen on the
// geometry's bytes when `offer` is null; else never chosen, but offered (below). split: with
// octree, split frames (docs/FORMAT.md "Split frames") are candidates too, as octree frames are.
struct OctreeOffer;
bool reorder_window(FrameBlock* b, const Grid& grid, const std::vector<uint32_t>& ring,
                    const std::vector<float>& distance, std::vector<uint8_t>* coded,
                    std::vector<uint8_t>* kept, ScanWorkspace* ws = nullptr, bool octree = false,
                    OctreeOffer* offer = nullptr, bool split = true);

// A window with fields as octree frames (or split frames), for the encoder to compare whole windows
// (geometry and fields: the fields follow their points in the cells' Morton order, where they may
// cost more than in a firing's): `block`, reorder_window's b as it came with every frame's points
// (and fields) in octree order, and `coded` its geometry's bytes; left empty unless that geometry
// is smaller than the order reorder_window chose.
struct OctreeOffer {
  FrameBlock block;
  std::vector<uint8_t> coded;
};

}  // namespace capz
