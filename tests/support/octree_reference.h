// Reference statements of the octree walk's contexts (FORMAT.md "Ragged frames", step 4), from
// lookups of coordinates in KeySets: the walk (coding/scan_octree.h) finds the same contexts from
// its indices, and the tests hold it to these.
#pragma once

#include <cstdint>

#include "coding/scan_octree.h"

namespace capz_test {

// Whether the set holds the node at c (false outside [0, side)^3).
inline bool has(const capz::scan::octree::KeySet& set, const int64_t* c, int64_t side) {
  for (int a = 0; a < 3; ++a)
    if (c[a] < 0 || c[a] >= side) return false;
  return set.find(capz::scan::octree::key(static_cast<uint64_t>(c[0]), static_cast<uint64_t>(c[1]),
                                          static_cast<uint64_t>(c[2]))) >= 0;
}

// FORMAT.md step 4's context of child i of the node at p, worked out from lookups of coordinates
// (the walk finds it from its indices).
inline int bit_context(const int* nb, const capz::scan::octree::KeySet& next,
                       const capz::scan::octree::KeySet& before, const int64_t* p, int l, int d,
                       int i, int ones, int r = 2) {
  const int64_t c[3] = {2 * p[0] + ((i >> 2) & 1), 2 * p[1] + ((i >> 1) & 1), 2 * p[2] + (i & 1)};
  const uint64_t ck = capz::scan::octree::key(
      static_cast<uint64_t>(c[0]), static_cast<uint64_t>(c[1]), static_cast<uint64_t>(c[2]));
  int coded = 0;
  for (int j = 0; j < i; ++j)
    coded |= static_cast<int>(next.find((ck & ~uint64_t{7}) | static_cast<uint64_t>(j)) >= 0) << j;
  return capz::scan::octree::child_context(nb, next, before, ck, c, l, d, i, coded, ones, r);
}

}  // namespace capz_test
