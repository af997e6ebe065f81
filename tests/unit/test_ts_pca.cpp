#include <gtest/gtest.h>

#include <random>

#include "codec/ts/pca.h"

using namespace capz::ts;

namespace {
Eigen::MatrixXd random_matrix(int rows, int cols, unsigned seed) {
  std::mt19937 rng(seed);
  std::normal_distribution<double> n01(0, 1);
  Eigen::MatrixXd m(rows, cols);
  for (int j = 0; j < cols; ++j)
    for (int i = 0; i < rows; ++i) m(i, j) = n01(rng) + 3;
  return m;
}
}  // namespace

TEST(TsPca, GivenMoreDimensionsThanFramesWhenAllComponentsKeptThenExact) {
  Eigen::MatrixXd f = random_matrix(90, 12, 1);  // Gram route
  Pca p = pca_frames(f, PcaParams());
  ASSERT_EQ(p.basis.cols(), 12);
  EXPECT_LT((p.basis * p.coeff - f).norm(), 1e-10 * f.norm());
  EXPECT_LT((p.basis.transpose() * p.basis - Eigen::MatrixXd::Identity(12, 12)).norm(), 1e-10);
  for (int i = 1; i < 12; ++i) EXPECT_GE(p.sigma[i - 1], p.sigma[i]);
}

TEST(TsPca, GivenMoreFramesThanDimensionsWhenAllComponentsKeptThenExact) {
  Eigen::MatrixXd f = random_matrix(9, 40, 2);  // SVD route
  Pca p = pca_frames(f, PcaParams());
  ASSERT_EQ(p.basis.cols(), 9);
  EXPECT_LT((p.basis * p.coeff - f).norm(), 1e-10 * f.norm());
}

TEST(TsPca, GivenRankTwoDataThenTwoComponents) {
  Eigen::MatrixXd f = random_matrix(50, 2, 3) * random_matrix(2, 20, 4);
  Pca p = pca_frames(f, PcaParams());
  EXPECT_EQ(p.basis.cols(), 2);
  EXPECT_LT((p.basis * p.coeff - f).norm(), 1e-9 * f.norm());
}

TEST(TsPca, GivenBitsWhenQuantisedThenErrorWithinHalfStep) {
  Eigen::VectorXd v = random_matrix(100, 1, 5).col(0);
  for (int bits : {8, 12, 16}) {
    QuantisedVector q = quantise_vector(v.data(), 100, bits);
    std::vector<double> back(100);
    dequantise_vector(q, back.data());
    const double step = quant_step(bits, q.scale);
    for (int i = 0; i < 100; ++i) {
      EXPECT_LE(std::fabs(back[i] - v[i]), step / 2 * (1 + 1e-12));
      EXPECT_LE(std::abs(q.q[i]), (1 << (bits - 1)) - 1);
    }
  }
  EXPECT_EQ(basis_bits_for(1e-9, 1.0, 100, 1.0, 8, 16), 8);
  EXPECT_EQ(basis_bits_for(1e9, 1.0, 100, 1e-30, 8, 16), 16);
}
