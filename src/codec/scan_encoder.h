// The encoder of ragged takes (frames of their own point counts; docs/FORMAT.md "Scans
// (format 1.1)"): the grid chosen as for every take (grid_choice.h), windows of whole frames,
// each window's positions coded by the scan geometry coder (coding/scan_geometry.h) into an SCNW
// chunk, and every window decoded again by the one decoder (decoder.h) and checked.
#pragma once

#include <cstdint>
#include <string>
#include <vector>

#include "capz/codec.h"

namespace capz {

// A ragged take (t.ragged()) to .capz bytes. Throws Error(kInvalidParameter) for what format
// 1.1 does not code yet (a KG target, point fields unless opts.drop_fields, analog or
// rotations, other sources than PCD frames), Error(kInternal) when the self-check fails.
// `original`: the PCD folder the take was read from (FrameSource::original_file), or empty; a
// lossless stream of a folder carries the residue that rebuilds its frame files byte for byte
// (FORMAT.md "Lossless ragged streams").
std::vector<uint8_t> compress_ragged(const Take& t, const CompressOptions& opts,
                                     CompressStats* stats, const std::string& original = "");

}  // namespace capz
