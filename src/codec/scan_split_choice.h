// The float32 split of a lossless mode 2 window of ragged frames (docs/FORMAT.md "Lossless ragged
// streams": SCNW's split exponent, the geometry on the grid 2^-e, the corrections) for the
// encoder of ragged takes (scan_encoder.cpp): SCNW's bytes after `total`, and the search for the
// exponent that codes smallest.
#pragma once

#include <cstdint>
#include <vector>

#include "capz/stream.h"
#include "coding/scan_geometry.h"

namespace capz {

// Split integers stay below 2^29, where the scan payload's spherical frames work.
constexpr int64_t kSplitLimit = int64_t{1} << 29;

// SCNW's bytes after `total` ("Scans (format 1.1)"): in mode 2 the split exponent e, and with a
// split (g.q on the grid 2^-e, t the corrections) the geometry's length, the geometry and the
// corrections block; else the geometry alone. coded: encode_scan_geometry(g, hints) when the
// caller has it already, else null. *geo_out (when not null): the geometry.
std::vector<uint8_t> scan_body(const ScanGeometry& g, const ScanHints& hints, bool mode2, int e,
                               const std::vector<uint32_t>& t, ScanWorkspace* ws,
                               const std::vector<uint8_t>* coded = nullptr,
                               std::vector<uint8_t>* geo_out = nullptr);

// The float32 split of a lossless mode 2 window (b's points, counts frames): the exponent whose
// SCNW is smallest on the window's first two frames (scan::kNoSplit when none beats the float32
// bits there, or no exponent applies). `start`: the window before's exponent, where the search
// starts in steps of 1 (scan::kNoSplit: from kSplitStart in steps of kSplitStep, then the best
// one's neighbours). Coding only a part of the frames to choose was tried and dropped
// (docs/lab/2026-11-30-lossless-organized.md: the E1 and ot128 lost 2.3x and 3.7x).
int choose_split(const FrameBlock& b, const std::vector<uint32_t>& counts, const ScanHints& hints,
                 const std::vector<int32_t>& bits, int start, ScanWorkspace* ws);

}  // namespace capz
