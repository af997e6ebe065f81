// capz — compression API. The container, the bound layer and the codec registry live behind it.
// (Filled in by the container work: compress()/decompress() of a Take to .capz bytes.)
#pragma once

#include <cstddef>
#include <cstdint>
#include <string>
#include <vector>

#include "capz/take.h"

namespace capz {

// A read-only view of a block of positions, as transform codecs (ts, pdct) see it.
// xyz: frames x points x 3 (frame-major, see take.h); valid: frames x points (1 = measured).
// Gap samples in xyz hold filled-in values chosen by the caller (never garbage, never NaN).
struct PositionsView {
  size_t frames = 0;
  size_t points = 0;
  const double* xyz = nullptr;
  const uint8_t* valid = nullptr;
};

}  // namespace capz
