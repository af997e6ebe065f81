// Hints the scan coder takes from a block's point fields (docs/FORMAT.md "Scan geometry
// payload", informative): the ring / laser number and the measured range of every point.
#pragma once

#include <cstdint>
#include <vector>

#include "capz/stream.h"
#include "capz/take.h"

namespace capz {

// The ring / laser / channel number of every point of block b from an unsigned or signed
// integer field of that name (layouts: the take's attributes), or empty.
std::vector<uint32_t> ring_field(const std::vector<PointAttribute>& layouts, const FrameBlock& b);

// The source's distance field (a float `distance` or `range`, the sensor's measured range), or
// empty: a hint of the sensor's range step (ScanHints::distance).
std::vector<float> distance_field(const std::vector<PointAttribute>& layouts, const FrameBlock& b);

// Frees every point field of block b but the two above read (--drop-fields: the others are
// not coded, and held through the window's coding they cost their bytes a point for nothing).
void keep_hint_fields(const std::vector<PointAttribute>& layouts, FrameBlock* b);

}  // namespace capz
