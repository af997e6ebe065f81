#include <gtest/gtest.h>

#include <Eigen/Geometry>
#include <random>

#include "codec/ts/align.h"
#include "codec/ts/rigid.h"

using namespace capz;
using namespace capz::ts;

TEST(TsAlign, GivenKnownRigidMotionWhenAlignedThenRotationAndTranslationRecovered) {
  const size_t n = 300;
  std::mt19937 rng(7);
  std::normal_distribution<double> n01(0, 1);
  std::vector<double> xyz(2 * n * 3);
  std::vector<uint8_t> valid(2 * n, 1);
  for (size_t i = 0; i < n * 3; ++i) xyz[i] = 10 * n01(rng) + 100;  // far from the origin
  // Frame 1 = R^-1 (frame 0 - T): aligning it onto frame 0 must give p = R v + T.
  RigidParams truth;
  truth.rot[0] = 0.3;
  truth.rot[1] = -0.7;
  truth.rot[2] = 1.1;
  truth.trans[0] = 5;
  truth.trans[1] = -2;
  truth.trans[2] = 12.5;
  std::copy(xyz.begin(), xyz.begin() + n * 3, xyz.begin() + n * 3);
  apply_rigid_inverse(truth, xyz.data() + n * 3, n);
  // A few gaps in either frame must be ignored, even with garbage coordinates.
  for (size_t p = 0; p < n; p += 17) {
    valid[n + p] = 0;
    xyz[(n + p) * 3] = 1e6;
  }
  PositionsView v{2, n, xyz.data(), valid.data()};
  std::vector<RigidParams> r = estimate_alignment(v, AlignParams());
  ASSERT_EQ(r.size(), 2u);
  for (int a = 0; a < 3; ++a) {
    EXPECT_EQ(r[0].rot[a], 0.0);
    EXPECT_NEAR(r[1].rot[a], truth.rot[a], 1e-5);
    EXPECT_NEAR(r[1].trans[a], truth.trans[a], 1e-3);
  }
}

TEST(TsAlign, GivenRotationVectorWhenConvertedBothWaysThenSameMatrix) {
  RigidParams p;
  p.rot[0] = -2.0;
  p.rot[1] = 0.4;
  p.rot[2] = 0.9;
  const Eigen::Matrix3d r = rotation_matrix(p);
  EXPECT_NEAR((r * r.transpose() - Eigen::Matrix3d::Identity()).norm(), 0, 1e-12);
  Eigen::AngleAxisd aa(Eigen::Vector3d(-2.0, 0.4, 0.9).norm(),
                       Eigen::Vector3d(-2.0, 0.4, 0.9).normalized());
  EXPECT_NEAR((r - aa.toRotationMatrix()).norm(), 0, 1e-12);
  RigidParams q = params_from_transform(r, Eigen::Vector3d(1, 2, 3));
  for (int a = 0; a < 3; ++a) EXPECT_NEAR(q.rot[a], p.rot[a], 1e-12);
  std::vector<double> pts = {1, 2, 3, -4, 5, 0.5};
  std::vector<double> orig = pts;
  apply_rigid(q, pts.data(), 2);
  apply_rigid_inverse(q, pts.data(), 2);
  for (size_t i = 0; i < pts.size(); ++i) EXPECT_NEAR(pts[i], orig[i], 1e-12);
}

TEST(TsAlign, GivenTooFewCommonPointsThenIdentity) {
  std::vector<double> xyz = {0, 0, 0, 1, 0, 0, 0, 1, 0, 5, 5, 5, 6, 5, 5, 5, 6, 5};
  std::vector<uint8_t> valid = {1, 1, 1, 1, 0, 1};
  PositionsView v{2, 3, xyz.data(), valid.data()};
  auto r = estimate_alignment(v, AlignParams());
  for (int a = 0; a < 3; ++a) EXPECT_EQ(r[1].trans[a], 0.0);
}
