// capz — byte patches: where a regenerated buffer differs from the original one.
//
// Stored form (docs/FORMAT.md 14.1, "Patch list"): varint runs, then per run varint
// skip (equal bytes before it, counted from the end of the previous run) and varint length - 1,
// then the replacement bytes of every run, in order. Runs closer than kJoin equal bytes are
// joined (a run costs about 2 bytes of header).
#pragma once

#include <cstddef>
#include <cstdint>
#include <vector>

#include "coding/bytes.h"

namespace capz {
namespace residue {

// The patch turning `regen` into `orig` (both n bytes); an empty vector when they are equal.
std::vector<uint8_t> diff_bytes(const uint8_t* regen, const uint8_t* orig, size_t n);

// Applies a patch made by diff_bytes to buf (n bytes). Throws Error(kCorrupt) naming `what` when
// the patch is malformed or reaches past n.
void apply_patch(const std::vector<uint8_t>& patch, uint8_t* buf, size_t n, const char* what);

}  // namespace residue
}  // namespace capz
