// Raw windows for the encoder of ragged takes (docs/FORMAT.md "Raw windows"; scan_encoder.cpp):
// a lossless window's coordinates as their bits through LZMA2, always in mode 3 (float64 on no
// decimal grid), in mode 2 where the scan coder's window is larger.
#pragma once

#include <cstddef>
#include <cstdint>
#include <string>
#include <vector>

#include "capz/stream.h"
#include "codec/grid.h"

namespace capz {

// SCNW's payload of window w as a raw window of block b (its points as read: a point at 0 0 0 is
// a point) in grid mode m (kFloat32 or kFloat64). source: named by a kInternal error.
std::vector<uint8_t> raw_scan_payload(size_t w, const FrameBlock& b, PosMode m,
                                      const std::string& source);

// The integers a raw window of block b offers ATTR's predictors (FORMAT.md "Raw windows"): in
// mode 2 the float32 ordered integers, in mode 3 none.
std::vector<int32_t> raw_scan_ints(const FrameBlock& b, PosMode m);

// Whether a mode 2 window of block b whose SCNW chunk takes scan_bytes is coded raw too: when
// the raw window's estimate (scan::raw_window_estimate, about 15 % above the raw window) is below
// it.
bool raw_may_win(const FrameBlock& b, size_t scan_bytes);

}  // namespace capz
