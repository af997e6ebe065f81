// What the analog window's encoder (analog_codec_encode.cpp) and decoder (analog_codec.cpp)
// share (docs/FORMAT.md 11): the window's version byte, the LPC block length, which channels have
// numbers in the entropy-coded block, the header rules and the references a channel may use.
#pragma once

#include <cstddef>
#include <cstdint>
#include <vector>

#include "coding/analog/analog_cross.h"
#include "coding/analog/analog_repr.h"

namespace capz {
namespace analog {
namespace window {

inline constexpr size_t kBlockRows = 4096;  // LPC block length (A.3)
// The window's version byte (FORMAT.md 4.2.1): format 1.0 defines one value, 2 (integer
// residuals' tokens relative to the magnitude context, 9.7, and the two bits below them through
// a model, 9.5); any other is corrupt.
inline constexpr int kWindowVersion = 2;

// Whether a channel of this kind has numbers in the entropy-coded block (a window whose
// channels have none omits the block).
inline bool coded(Kind k) {
  return k != Kind::kConst;
}

// What the window's channel headers may carry: repeat lists with repeat_S > 0.
inline HeaderRules header_rules(size_t repeat_S) {
  HeaderRules rules;
  rules.S = repeat_S;
  return rules;
}

// The LPC residuals of the channels before c that can serve as references (A.3.2).
inline std::vector<const std::vector<int32_t>*> cross_refs(
    const std::vector<std::vector<int32_t>>& r1s, const std::vector<bool>& has, int c) {
  std::vector<const std::vector<int32_t>*> refs;
  for (int d = 1; d <= kMaxCrossDistance && c - d >= 0; ++d)
    refs.push_back(has[c - d] ? &r1s[c - d] : nullptr);
  return refs;
}

}  // namespace window
}  // namespace analog
}  // namespace capz
