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

// The payload offsets a damage test visits in a chunk of `len` bytes: every one when the payload
// is short; else every one of the first `head` (where the payload's structure is: transforms,
// predictors, sizes), `spread` evenly spaced through the middle, and every one of the last
// `tail` (block ends, trailing fields). Bounds a test's decodes (the suite also runs under
// AddressSanitizer), while every kind of field is still hit.
inline std::vector<size_t> payload_positions(size_t len, size_t head = 384, size_t spread = 384,
                                             size_t tail = 64) {
  std::vector<size_t> at;
  if (len <= head + spread + tail) {
    for (size_t i = 0; i < len; ++i) at.push_back(i);
    return at;
  }
  for (size_t i = 0; i < head; ++i) at.push_back(i);
  const size_t middle = len - head - tail;
  for (size_t k = 0; k < spread; ++k) at.push_back(head + k * middle / spread);
  for (size_t i = len - tail; i < len; ++i) at.push_back(i);
  return at;
}

}  // namespace capz_test
