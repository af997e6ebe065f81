// ATTR's predictor 13, ring (docs/FORMAT.md "Scans (format 1.1)": point fields of a ragged
// window), shared by the encoder and the decoder: a laser's number (a ring or channel field)
// predicted by the value of the latest point the scan geometry put on the same ring, else by
// the value that last followed the previous point's value; the valid points coded in runs of
// points that take their prediction, each run ended by a miss.
#pragma once

#include <cstddef>
#include <cstdint>
#include <vector>

#include "coding/attributes_entropy.h"
#include "coding/attributes_lanes.h"
#include "coding/attributes_quantum.h"

namespace capz {
namespace attr {

inline constexpr int kRingPredictor = 13;
// A point without a geometry ring (ScanGeometry::kNoRing), and the most rings a payload has.
inline constexpr uint16_t kNoGeometryRing = 0xFFFF;
inline constexpr size_t kMaxGeometryRings = 1024;

// Whether predictor 13 may code a lane of attribute s: a plain lane of a U or I field of size 1
// or 2 (lane values below 2^16).
inline bool ring_lane(const AttrSpec& s, bool colour) {
  return !colour && is_key_field(s);
}

// Walks a predictor-13 lane in coding order: step(&value, prediction, gap) for each point (gap:
// a gap point, predicted by the previous gap point's value). rings: each point's geometry ring
// (kNoGeometryRing for none), or nullptr when no point has one. The lane's values are below 2^16.
template <typename Step>
inline void walk_ring(std::vector<uint64_t>* lane, const uint8_t* valid, const uint16_t* rings,
                      Step&& step) {
  // Per ring and per value: 1 + the value predicted (0: none yet).
  std::vector<uint32_t> by_ring(rings ? kMaxGeometryRings : 0, 0), succ(size_t{1} << 16, 0);
  uint64_t last_gap = 0, last = 0;
  bool have_last = false;
  for (size_t p = 0; p < lane->size(); ++p) {
    uint64_t* v = &(*lane)[p];
    if (!valid[p]) {
      step(v, last_gap, true);
      last_gap = *v;
      continue;
    }
    const size_t g = rings ? rings[p] : kNoGeometryRing;
    const bool ringed = g < kMaxGeometryRings;
    uint64_t pred = last;
    if (ringed && by_ring[g] != 0)
      pred = by_ring[g] - 1;
    else if (have_last && succ[static_cast<size_t>(last)] != 0)
      pred = succ[static_cast<size_t>(last)] - 1;
    step(v, pred, false);
    const auto seen = static_cast<uint32_t>(*v + 1);
    if (ringed) by_ring[g] = seen;
    if (have_last) succ[static_cast<size_t>(last)] = seen;
    last = *v;
    have_last = true;
  }
}

// A predictor-13 lane's residuals in coding order (FORMAT.md: runs and misses): the valid
// points' as (value - prediction) mod 2^bits, the gap points' likewise against the previous gap
// point's value. sink(kind, u): kind 0 a run count, 1 a miss (zigzag of the residual, less 1),
// 2 a gap point's residual (signed, in u's bits); the runs are found by looking ahead.
template <typename Sink>
inline void ring_symbols(Lane& l, const uint8_t* valid, const uint16_t* rings, Sink&& sink) {
  const size_t n = l.u.size();
  const uint64_t mask = mask_of(l.bits);
  std::vector<uint64_t> res(n);  // each point's residual mod 2^bits
  size_t at = 0;
  walk_ring(&l.u, valid, rings,
            [&](uint64_t* v, uint64_t p, bool) { res[at++] = (*v - p) & mask; });
  bool need = true;  // a run count is due at the next valid point
  uint64_t left = 0;
  for (size_t p = 0; p < n; ++p) {
    if (!valid[p]) {
      sink(2, static_cast<uint64_t>(signed_residual(res[p], l.bits)));
      continue;
    }
    if (need) {
      left = 0;
      for (size_t k = p; k < n && (!valid[k] || res[k] == 0); ++k) left += valid[k];
      sink(0, left);
      need = false;
    }
    if (left > 0) {
      --left;
      continue;
    }
    sink(1, zigzag64(signed_residual(res[p], l.bits)) - 1);
    need = true;
  }
}

}  // namespace attr
}  // namespace capz
