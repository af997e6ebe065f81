// Inter-channel prediction's choice (analog_cross.h): its bit counts, on the AVX2 path and the
// portable one (analog_simd.h).
#include <gtest/gtest.h>

#include <cmath>
#include <random>
#include <vector>

#include "coding/analog/analog_cross.h"
#include "coding/analog/analog_simd.h"

namespace capz {
namespace analog {
namespace {

int64_t bit_length(int64_t v) {
  const uint64_t u = (static_cast<uint64_t>(v) << 1) ^ static_cast<uint64_t>(v >> 63);
  int64_t b = 0;
  while (u >> b) ++b;
  return b;
}

// A reference is taken when the summed bit lengths it saves, less 20, exceed min_gain_bits: the
// choice around saved - 20 shows choose_cross counted exactly `saved` (computed here sample by
// sample), with AVX2 allowed and not, for every length up to 9 and odd long ones (the vector
// loops' tails), near-equal and unrelated references, small and large values.
TEST(AnalogCross, GivenReferenceWhenChosenThenSavedBitsExactOnEveryPath) {
  std::mt19937 rng(17);
  std::normal_distribution<double> e(0, 1);
  int checked = 0;
  for (size_t n : {1, 2, 3, 4, 5, 6, 7, 8, 9, 1001, 4097}) {
    for (double scale : {30.0, 3e6}) {
      std::vector<int32_t> ref(n), r1(n);
      for (size_t i = 0; i < n; ++i) {
        ref[i] = static_cast<int32_t>(std::lround(scale * e(rng)));
        r1[i] = static_cast<int32_t>(std::lround(0.7 * ref[i] + 0.1 * scale * e(rng)));
      }
      const double err = reference_energy(ref);
      double ecr = 0;
      for (size_t i = 0; i < n; ++i) ecr += static_cast<double>(r1[i]) * ref[i];
      if (!(err > 0)) continue;
      const double beta = std::round(ecr / err * (1 << kCrossShift));
      if (!(std::fabs(beta) < kMaxBeta) || beta == 0) continue;
      const int32_t q = static_cast<int32_t>(beta);
      int64_t saved = 0;
      for (size_t i = 0; i < n; ++i)
        saved += bit_length(r1[i]) - bit_length(r1[i] - cross_predict(q, ref[i]));
      const std::vector<const std::vector<int32_t>*> refs = {&ref};
      const double gain = static_cast<double>(saved) - 20;
      for (bool avx2 : {false, true}) {
        allow_avx2(avx2);
        const CrossParams below = choose_cross(r1, refs, {err}, gain - 0.5);
        const CrossParams above = choose_cross(r1, refs, {err}, gain + 0.5);
        EXPECT_EQ(below.distance, 1) << n << " " << scale << " avx2 " << avx2;
        EXPECT_EQ(below.beta, q);
        EXPECT_EQ(above.distance, 0) << n << " " << scale << " avx2 " << avx2;
      }
      allow_avx2(true);
      ++checked;
    }
  }
  EXPECT_GE(checked, 18);  // of 22: a length-1 pair may have no usable beta
}

}  // namespace
}  // namespace analog
}  // namespace capz
