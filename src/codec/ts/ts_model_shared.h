// What the ts payload's writer (ts_model_encode.cpp) and reader (ts_model.cpp) share
// (docs/CODEC-TS.md): its versions, the contexts of its entropy-coded part, the move-to-front
// list of segment labels and the bits of an LCPS frame index.
#pragma once

#include <algorithm>
#include <cstddef>
#include <cstdint>
#include <vector>

#include "codec/ts/ts_model.h"

namespace capz {
namespace ts {
namespace payload {

inline const char* const kWhat = "ts payload";
inline constexpr uint8_t kVersionOneSegment = 1;  // the paper's model
inline constexpr uint8_t kVersionSegments = 2;    // point segments (docs/CODEC-TS.md)

// The entropy-coded part: one IntEncoder block; each kind of value has its own group of 16
// contexts chosen by the previous token of that group, labels use context 128 + previous label,
// segment labels 384 + the previous point's segment.
enum Group {
  kLabels = 0,
  kRigid,
  kBasis,
  kLpcWeight,
  kLpcValue,
  kLcpsCount,
  kLcpsWeight,
  kLcpsResid,
  kGroups
};
inline constexpr int kLabelCtx = kGroups * 16;
inline constexpr int kSegmentCtx = kLabelCtx + 256;
inline constexpr int kContexts = kSegmentCtx + kMaxSegments;

// Move-to-front list of segment indices (segment labels are coded as their rank in it).
class SegmentMtf {
 public:
  explicit SegmentMtf(int segments) {
    for (int s = 0; s < segments; ++s) list_.push_back(static_cast<uint8_t>(s));
  }
  uint32_t rank_of(uint8_t seg) const {
    return static_cast<uint32_t>(std::find(list_.begin(), list_.end(), seg) - list_.begin());
  }
  // The segment at `rank` (< size), moved to the front.
  uint8_t take(uint32_t rank) {
    const uint8_t seg = list_[rank];
    list_.erase(list_.begin() + rank);
    list_.insert(list_.begin(), seg);
    return seg;
  }
  size_t size() const { return list_.size(); }

 private:
  std::vector<uint8_t> list_;
};

inline int index_bits(size_t l1) {  // ceil(log2 l1)
  int b = 0;
  while ((size_t{1} << b) < l1) ++b;
  return b;
}

}  // namespace payload
}  // namespace ts
}  // namespace capz
