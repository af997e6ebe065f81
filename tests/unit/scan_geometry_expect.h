// What the scan geometry tests (test_scan_geometry.cpp, test_scan_raster.cpp) compare: two
// windows' counts, gaps and valid points' integers, exactly.
#pragma once

#include <gtest/gtest.h>

#include "coding/scan_geometry.h"

namespace capz {

inline void expect_same(const ScanGeometry& a, const ScanGeometry& b) {
  ASSERT_EQ(a.counts, b.counts);
  ASSERT_EQ(a.valid, b.valid);
  for (size_t i = 0; i < a.valid.size(); ++i) {
    if (!a.valid[i]) continue;
    for (int k = 0; k < 3; ++k) ASSERT_EQ(a.q[3 * i + k], b.q[3 * i + k]) << "point " << i;
  }
}

}  // namespace capz
