// What the PCD residue's encoder (pcd_residue_encode.cpp) and decoder (pcd_residue.cpp) share.
#pragma once

#include <cstddef>
#include <cstdint>
#include <vector>

namespace capz {
namespace residue {
namespace pcdr {

inline constexpr uint8_t kKind = 3;  // PCDR's kind byte (FORMAT.md 7.3)

inline bool is_space(uint8_t c) {
  return c == ' ' || c == '\t' || c == '\r' || c == '\v' || c == '\f';
}

inline std::vector<uint8_t> slice(const std::vector<uint8_t>& v, size_t a, size_t b) {
  return std::vector<uint8_t>(v.begin() + static_cast<long>(a), v.begin() + static_cast<long>(b));
}

}  // namespace pcdr
}  // namespace residue
}  // namespace capz
