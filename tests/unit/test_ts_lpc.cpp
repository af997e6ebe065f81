#include <gtest/gtest.h>

#include <cmath>
#include <random>

#include "codec/ts/lcps.h"
#include "codec/ts/lpc.h"

using namespace capz::ts;

TEST(TsLpc, GivenSinusoidWhenFittedThenOrderTwoPredictsExactly) {
  // x_t = sin(w t) satisfies x_t = 2 cos(w) x_{t-1} - x_{t-2}.
  const double w = 0.3;
  std::vector<double> x(50);
  for (size_t t = 0; t < x.size(); ++t) x[t] = std::sin(w * static_cast<double>(t));
  std::vector<double> a = lpc_fit(x.data(), x.size(), 2);
  EXPECT_NEAR(a[0], 2 * std::cos(w), 1e-6);
  EXPECT_NEAR(a[1], -1, 1e-6);
}

TEST(TsLpc, GivenFineStepWhenCodedThenTrainingFramesReconstructedAndDecodeMatches) {
  std::mt19937 rng(1);
  std::normal_distribution<double> n01(0, 1);
  Eigen::MatrixXd s(4, 30);
  for (int i = 0; i < 4; ++i)
    for (int t = 0; t < 30; ++t) s(i, t) = std::cos(0.2 * (i + 1) * t) * (i + 1) + 0.01 * n01(rng);
  const std::vector<double> steps(4, 1e-9);
  LpcParams p;
  p.order = 3;
  Eigen::MatrixXd rec;
  LpcCode c = lpc_encode(s, steps, p, &rec);
  EXPECT_LT((rec - s).cwiseAbs().maxCoeff(), 1e-9);
  Eigen::MatrixXd dec = lpc_decode(c, steps);
  EXPECT_EQ(0, std::memcmp(dec.data(), rec.data(), sizeof(double) * rec.size()));  // bit exact
  // The predictor does its job: residuals are much smaller than the values.
  double res = 0, val = 0;
  for (int i = 0; i < 4; ++i)
    for (int t = 3; t < 30; ++t) {
      res += std::fabs(static_cast<double>(c.values[i * 30 + t]));
      val += std::fabs(s(i, t)) / 1e-9;
    }
  EXPECT_LT(res, 0.2 * val);
}

TEST(TsLpc, GivenCoarseStepThenErrorWithinHalfStep) {
  Eigen::MatrixXd s(2, 40);
  for (int t = 0; t < 40; ++t) {
    s(0, t) = 3 * std::sin(0.1 * t);
    s(1, t) = t * t * 0.01;
  }
  const std::vector<double> steps = {0.05, 0.02};
  Eigen::MatrixXd rec;
  lpc_encode(s, steps, LpcParams(), &rec);
  for (int t = 0; t < 40; ++t) {
    EXPECT_LE(std::fabs(rec(0, t) - s(0, t)), 0.025 + 1e-12);
    EXPECT_LE(std::fabs(rec(1, t) - s(1, t)), 0.01 + 1e-12);
  }
}

TEST(TsLcps, GivenFrameInSpanOfTwoReferencesThenChosenAndReconstructed) {
  std::mt19937 rng(2);
  std::normal_distribution<double> n01(0, 1);
  Eigen::MatrixXd refs(10, 8);
  for (int j = 0; j < 8; ++j)
    for (int i = 0; i < 10; ++i) refs(i, j) = n01(rng);
  Eigen::VectorXd w = 0.7 * refs.col(5) - 0.4 * refs.col(2);
  std::vector<uint32_t> idx;
  std::vector<double> wt;
  lcps_select(w, refs, 2, &idx, &wt);
  ASSERT_EQ(idx.size(), 2u);
  EXPECT_EQ(idx[0], 5u);  // the most parallel one first
  EXPECT_EQ(idx[1], 2u);
  EXPECT_NEAR(wt[0], 0.7, 1e-12);
  EXPECT_NEAR(wt[1], -0.4, 1e-12);
  // Unquantised inputs (fine step, many weight bits) reconstruct the frame.
  LcpsParams p;
  p.weight_bits = 24;
  Eigen::VectorXd rec;
  LcpsFrame f = lcps_encode(w, refs, 1e-9, p, &rec);
  EXPECT_LT((rec - w).cwiseAbs().maxCoeff(), 1e-9);
  for (int64_t r : f.resid) EXPECT_LE(std::llabs(r), 1000);  // the prediction did the work
  Eigen::VectorXd dec = lcps_decode(f, refs, 1e-9, p.weight_bits);
  EXPECT_EQ(0, std::memcmp(dec.data(), rec.data(), sizeof(double) * rec.size()));
}

TEST(TsLcps, GivenTrainingFrameThenOneReferenceSuffices) {
  Eigen::MatrixXd refs = Eigen::MatrixXd::Random(6, 5);
  Eigen::VectorXd w = refs.col(3);
  std::vector<uint32_t> idx;
  std::vector<double> wt;
  lcps_select(w, refs, 2, &idx, &wt);
  ASSERT_GE(idx.size(), 1u);
  EXPECT_EQ(idx[0], 3u);
  EXPECT_NEAR(wt[0], 1.0, 1e-12);
}
