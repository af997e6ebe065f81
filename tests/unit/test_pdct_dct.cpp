#include <gtest/gtest.h>

#include <cmath>
#include <random>
#include <vector>

#include "codec/pdct/dct.h"
#include "codec/pdct/predict.h"

using capz::pdct::BlockDct;
using capz::pdct::CoefQuantParams;
using capz::pdct::cos_pi_ratio;
using capz::pdct::DctPlan;
using capz::pdct::zero_and_quantise;

TEST(PdctDct, GivenRatiosWhenCosPiRatioThenMatchesLibm) {
  for (int64_t den = 1; den <= 600; den += 7)
    for (int64_t num = -3 * den; num <= 3 * den; ++num)
      // long double reference: libm's double cos of a rounded pi*num/den is itself off by ~1e-15.
      ASSERT_NEAR(
          cos_pi_ratio(num, den),
          static_cast<double>(std::cos(3.141592653589793238462643383279502884L * num / den)), 3e-16)
          << num << "/" << den;
}

TEST(PdctDct, GivenSignalWhenForwardThenInverseThenRoundTrip) {
  std::mt19937 rng(3);
  std::uniform_real_distribution<double> u(-10, 10);
  for (size_t n : {1, 2, 3, 7, 64, 255}) {
    DctPlan plan(n);
    std::vector<double> x(n), X(n), y(n);
    for (double& v : x) v = u(rng);
    plan.forward(x.data(), X.data());
    plan.inverse(X.data(), y.data());
    double ex = 0, eX = 0;
    for (size_t i = 0; i < n; ++i) {
      EXPECT_NEAR(y[i], x[i], 1e-12) << n;
      ex += x[i] * x[i];
      eX += X[i] * X[i];
    }
    EXPECT_NEAR(ex, eX, 1e-9 * ex);  // orthonormal: energy kept
  }
}

TEST(PdctDct, GivenConstantSignalWhenForwardThenOnlyDcCoefficient) {
  DctPlan plan(16);
  std::vector<double> x(16, 2.0), X(16);
  plan.forward(x.data(), X.data());
  EXPECT_NEAR(X[0], 2.0 * 4.0, 1e-12);  // sqrt(1/16) * 16 * 2
  for (size_t l = 1; l < 16; ++l) EXPECT_NEAR(X[l], 0, 1e-13);
}

TEST(PdctDct, GivenBlocksWhenRoundTripThenExactToRounding) {
  std::mt19937 rng(5);
  std::uniform_real_distribution<double> u(-10, 10);
  BlockDct dct(300, 128);
  EXPECT_EQ(dct.blocks(), 3u);
  EXPECT_EQ(dct.block_size(2), 44u);
  std::vector<double> x(300), X(300), y(300);
  for (double& v : x) v = u(rng);
  dct.forward(x.data(), X.data());
  dct.inverse(X.data(), y.data());
  for (size_t i = 0; i < 300; ++i) EXPECT_NEAR(y[i], x[i], 1e-12);
}

TEST(PdctDct, GivenShareWhenQuantiseThenSmallestZeroedAndRoundedHalfAway) {
  const double X[6] = {5.0, -0.1, 2.5, 0.2, -2.5, 9.0};
  int64_t q[6];
  zero_and_quantise(X, 6, CoefQuantParams{1.0, 0.5}, q);  // 3 smallest |X| zeroed
  const int64_t want[6] = {5, 0, 0, 0, -3, 9};            // ties 2.5/-2.5: lower index zeroed
  for (int i = 0; i < 6; ++i) EXPECT_EQ(q[i], want[i]) << i;
  zero_and_quantise(X, 6, CoefQuantParams{1.0, 0.0}, q);
  const int64_t all[6] = {5, 0, 3, 0, -3, 9};
  for (int i = 0; i < 6; ++i) EXPECT_EQ(q[i], all[i]) << i;
}
