// The gap mask of a window (docs/FORMAT.md 9): which samples were measured, coded as runs
// per point.
#pragma once

#include <cstddef>
#include <cstdint>
#include <string>
#include <vector>

namespace capz {

// Gap mask: frames x points, 1 = valid. Runs per point (3.4).
std::vector<uint8_t> encode_mask(const uint8_t* valid, size_t frames, size_t points);
void decode_mask(const uint8_t* data, size_t size, size_t frames, size_t points, uint8_t* valid,
                 const std::string& what);

}  // namespace capz
