// "Lossless ragged streams" (docs/FORMAT.md, format 1.1): the negative zeros of a mode 1 window
// (lossless). A decimal grid decodes q = 0 as +0.0; the window's SCNW lists, after `total` and
// `gaps`, the coordinates that are -0.0 (a `-0.000000` in a PLY or PCD text), and the decoder
// negates them.
#pragma once

#include <cstddef>
#include <cstdint>
#include <string>
#include <vector>

#include "coding/bytes.h"
#include "coding/container.h"

namespace capz {

// Whether a window of a stream with header h carries the list: ragged, mode 1 (which the capz
// encoder writes only lossless; the list does not depend on HEAD's lossless bit).
inline bool lists_negative_zeros(const StreamHeader& h) {
  return h.ragged && h.mode == PosMode::kDecimal;
}

// Writes the list of the window's valid coordinates (xyz: 3 per point, valid: one per point)
// that are -0.0: the count, then the indices 3 p + a as gaps. Encoder only.
void write_negative_zeros(const std::vector<double>& xyz, const std::vector<uint8_t>& valid,
                          ByteWriter* w);

// Reads a window's list (total: its points): the indices 3 p + a, ascending, each below
// 3 total. Throws kCorrupt (r->what()) for a count above 3 total or an index beyond the window.
std::vector<uint64_t> read_negative_zeros(ByteReader* r, uint64_t total);

// Negates the listed coordinates of the decoded window (xyz from its integers, valid its gaps).
// Throws kCorrupt (what) for one of a gap point or one that did not decode to +0.0.
void apply_negative_zeros(const std::vector<uint64_t>& zeros, const std::vector<uint8_t>& valid,
                          const std::string& what, std::vector<double>* xyz);

}  // namespace capz
