// CRC-32C (Castagnoli): reflected polynomial 0x82F63B78, init and final xor 0xFFFFFFFF
// (docs/FORMAT.md 3.2). crc32c("123456789") = 0xE3069283.
#pragma once

#include <cstddef>
#include <cstdint>

namespace capz {

// Continues a CRC: crc32c_update(crc32c_update(0, a), b) == CRC of a followed by b.
uint32_t crc32c_update(uint32_t crc, const uint8_t* data, size_t size);
inline uint32_t crc32c(const uint8_t* data, size_t size) {
  return crc32c_update(0, data, size);
}

}  // namespace capz
