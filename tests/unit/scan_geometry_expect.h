// What the scan geometry tests (test_scan_geometry.cpp, test_scan_raster.cpp, ...) compare: two
// windows' counts, gaps and valid points' integers, exactly; and how their synthetic sweeps add
// a point.
#pragma once

#include <gtest/gtest.h>

#include <cmath>
#include <string>
#include <vector>

#include "capz/error.h"
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

// Decoding payload d fails as corrupt, naming it ("damaged").
inline void expect_scan_corrupt(const std::vector<uint8_t>& d) {
  try {
    decode_scan_geometry(d.data(), d.size(), "damaged");
    ADD_FAILURE() << "decoded";
  } catch (const Error& e) {
    EXPECT_EQ(e.code(), ErrorCode::kCorrupt);
    EXPECT_NE(std::string(e.what()).find("damaged"), std::string::npos);
  }
}

// Appends a valid point p (metres) of ring k to g (on the 2 mm grid) and to h (as float32).
inline void push_point(ScanGeometry* g, ScanHints* h, const double p[3], uint32_t k) {
  g->valid.push_back(1);
  for (int a = 0; a < 3; ++a) {
    g->q.push_back(static_cast<int32_t>(std::floor(p[a] / 0.002 + 0.5)));
    h->xyz.push_back(static_cast<float>(p[a]));
  }
  h->ring.push_back(k);
}

}  // namespace capz
