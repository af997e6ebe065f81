#include <gtest/gtest.h>

#include <cmath>
#include <random>

#include "codec/pdct/lcf.h"

using capz::pdct::Lcf;
using capz::pdct::make_lcf;
using capz::pdct::to_local;
using capz::pdct::to_world;

namespace {

void expect_orthonormal(const Lcf& f) {
  for (int r = 0; r < 3; ++r)
    for (int s = 0; s < 3; ++s) {
      double d = 0;
      for (int c = 0; c < 3; ++c) d += f.t[3 * r + c] * f.t[3 * s + c];
      EXPECT_NEAR(d, r == s ? 1.0 : 0.0, 1e-14) << r << "," << s;
    }
  // Right-handed: det = +1.
  const double* t = f.t;
  const double det = t[0] * (t[4] * t[8] - t[5] * t[7]) - t[1] * (t[3] * t[8] - t[5] * t[6]) +
                     t[2] * (t[3] * t[7] - t[4] * t[6]);
  EXPECT_NEAR(det, 1.0, 1e-14);
}

}  // namespace

TEST(PdctLcf, GivenTriangleWhenBuiltThenFollowsFigure2) {
  const double p1[3] = {1, 1, 1}, p2[3] = {3, 1, 1}, p3[3] = {2, 4, 1};
  const Lcf f = make_lcf(p1, p2, p3);
  EXPECT_DOUBLE_EQ(f.o[0], 2);  // midpoint of (p1, p2)
  EXPECT_DOUBLE_EQ(f.o[1], 1);
  EXPECT_DOUBLE_EQ(f.o[2], 1);
  EXPECT_DOUBLE_EQ(f.t[0], 1);  // x along p1 -> p2
  EXPECT_DOUBLE_EQ(f.t[4], 1);  // y towards p3, in the plane
  EXPECT_DOUBLE_EQ(f.t[8], 1);  // z normal
  double q[3];
  to_local(f, p3, q);
  EXPECT_NEAR(q[0], 0, 1e-15);
  EXPECT_NEAR(q[1], 3, 1e-15);
  EXPECT_NEAR(q[2], 0, 1e-15);
}

TEST(PdctLcf, GivenRandomTrianglesWhenBuiltThenOrthonormalAndInverseExact) {
  std::mt19937 rng(7);
  std::uniform_real_distribution<double> u(-1000, 1000);
  for (int trial = 0; trial < 2000; ++trial) {
    double p[9];
    for (double& v : p) v = u(rng);
    const Lcf f = make_lcf(p, p + 3, p + 6);
    expect_orthonormal(f);
    // p3 lies in the local x-y plane with y >= 0.
    double q3[3];
    to_local(f, p + 6, q3);
    EXPECT_NEAR(q3[2], 0, 1e-9);
    EXPECT_GE(q3[1], 0);
    for (int k = 0; k < 5; ++k) {
      const double x[3] = {u(rng), u(rng), u(rng)};
      double q[3], back[3];
      to_local(f, x, q);
      to_world(f, q, back);
      // Round trip to rounding: |p - o| < 3500 here, and 3500 * 2^-52 ~ 7.8e-13; a handful of
      // roundings in T and its transpose stay below 1e-11.
      for (int a = 0; a < 3; ++a) EXPECT_NEAR(back[a], x[a], 1e-11);
    }
  }
}

TEST(PdctLcf, GivenDegenerateTrianglesWhenBuiltThenStillOrthonormal) {
  const double a[3] = {5, 5, 5}, b[3] = {6, 7, 8}, on_line[3] = {7, 9, 11};
  expect_orthonormal(make_lcf(a, a, a));        // coincident
  expect_orthonormal(make_lcf(a, b, on_line));  // collinear
  expect_orthonormal(make_lcf(a, a, b));        // zero x edge
}
