// Chunks of a .capz in memory, for tests that damage one chunk's payload and fix its CRC so
// that only the payload's own checks can tell (docs/FORMAT.md 3.2: type, u32 length, payload,
// CRC-32C of type and payload).
#pragma once

#include <algorithm>
#include <cstddef>
#include <cstdint>
#include <string>
#include <vector>

#include "coding/crc32c.h"

namespace capz_test {

// Offset of the first chunk of type `type` (its 4-byte tag), or npos.
inline size_t find_chunk(const std::vector<uint8_t>& b, const char* type) {
  for (size_t i = 0; i + 4 <= b.size(); ++i)
    if (std::equal(type, type + 4, b.begin() + static_cast<long>(i))) return i;
  return std::string::npos;
}

inline uint32_t chunk_len(const std::vector<uint8_t>& b, size_t at) {
  return b[at + 4] | b[at + 5] << 8 | b[at + 6] << 16 | static_cast<uint32_t>(b[at + 7]) << 24;
}

inline void fix_crc(std::vector<uint8_t>* b, size_t at) {
  const uint8_t* p = b->data() + at;
  const uint32_t len = chunk_len(*b, at);
  const uint32_t crc = capz::crc32c_update(capz::crc32c(p, 4), p + 8, len);
  for (int k = 0; k < 4; ++k) (*b)[at + 8 + len + k] = static_cast<uint8_t>(crc >> (8 * k));
}

}  // namespace capz_test
