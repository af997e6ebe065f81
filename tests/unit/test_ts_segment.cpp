// ts point segmentation (segment.h): planted groups of points moving with different rigid
// motions are separated; the result is deterministic; degenerate inputs are handled.
#include <gtest/gtest.h>

#include <cmath>
#include <random>
#include <set>

#include "capz/error.h"
#include "codec/ts/segment.h"

using namespace capz;

namespace {

// 3N x F frames: `groups` groups of `per` points; group g rotates about its own axis with its
// own angular speed and translates along its own direction.
Eigen::MatrixXd planted(int groups, int per, int frames, uint32_t seed) {
  std::mt19937 rng(seed);
  std::normal_distribution<double> n01(0, 1);
  const int n = groups * per;
  Eigen::MatrixXd x(3 * n, frames);
  for (int g = 0; g < groups; ++g) {
    const double speed = 0.05 * (g + 1), tx = 0.3 * std::cos(g), ty = 0.3 * std::sin(2.0 * g);
    for (int k = 0; k < per; ++k) {
      // Interleave the groups in point order, so no group is a contiguous run.
      const int i = k * groups + g;
      const double p[3] = {n01(rng), n01(rng), n01(rng)};
      for (int f = 0; f < frames; ++f) {
        const double a = speed * f, c = std::cos(a), s = std::sin(a);
        const double axis_is_z = g % 2 == 0;
        double q[3];
        if (axis_is_z) {
          q[0] = c * p[0] - s * p[1];
          q[1] = s * p[0] + c * p[1];
          q[2] = p[2];
        } else {
          q[0] = p[0];
          q[1] = c * p[1] - s * p[2];
          q[2] = s * p[1] + c * p[2];
        }
        x(3 * i + 0, f) = q[0] + tx * f;
        x(3 * i + 1, f) = q[1] + ty * f;
        x(3 * i + 2, f) = q[2] + 0.1 * g * f;
      }
    }
  }
  return x;
}

}  // namespace

TEST(TsSegment, GivenPlantedRigidGroupsThenEachGroupIsOneSegment) {
  const int groups = 4, per = 30;
  const Eigen::MatrixXd x = planted(groups, per, 40, 7);
  ts::SegmentParams sp;
  sp.segments = groups;
  const ts::Segmentation seg = ts::segment_points(x, sp);
  ASSERT_EQ(seg.segments, groups);
  ASSERT_EQ(seg.label.size(), static_cast<size_t>(groups * per));
  // Same group <=> same segment.
  for (int i = 0; i < groups * per; ++i)
    for (int j = 0; j < groups * per; ++j)
      EXPECT_EQ(i % groups == j % groups, seg.label[i] == seg.label[j]) << i << " " << j;
  // Numbered by first appearance in point order.
  for (int g = 0; g < groups; ++g) EXPECT_EQ(seg.label[g], g);
  // Deterministic.
  EXPECT_EQ(ts::segment_points(x, sp).label, seg.label);
  // Members: the inverse of the labels.
  const auto mem = ts::segment_members(seg.label, seg.segments);
  for (int g = 0; g < groups; ++g) {
    ASSERT_EQ(mem[g].size(), static_cast<size_t>(per));
    for (uint32_t p : mem[g]) EXPECT_EQ(seg.label[p], g);
  }
}

TEST(TsSegment, GivenFewerPointsOrDistinctTrajectoriesThanSegmentsThenNoEmptySegment) {
  // 3 points, 8 segments wanted: clamped to 3.
  Eigen::MatrixXd x = planted(3, 1, 10, 3);
  ts::SegmentParams sp;
  sp.segments = 8;
  ts::Segmentation seg = ts::segment_points(x, sp);
  EXPECT_EQ(seg.segments, 3);
  EXPECT_EQ(std::set<uint8_t>(seg.label.begin(), seg.label.end()).size(), 3u);
  // A static window: every displacement is zero, one segment whatever was asked.
  Eigen::MatrixXd still = Eigen::MatrixXd::Zero(60, 10);
  for (int i = 0; i < 20; ++i) still.row(3 * i).setConstant(i);  // constant: zero displacement
  seg = ts::segment_points(still, sp);
  EXPECT_EQ(seg.segments, 1);
  // One segment wanted: all zero labels.
  sp.segments = 1;
  seg = ts::segment_points(x, sp);
  EXPECT_EQ(seg.segments, 1);
  EXPECT_EQ(seg.label, std::vector<uint8_t>(3, 0));
  sp.segments = 0;
  EXPECT_THROW(ts::segment_points(x, sp), Error);
}

TEST(TsSegment, GivenInconsistentLabelsThenMembersRejectAsCorrupt) {
  try {
    ts::segment_members({0, 2, 0}, 2);  // label >= segments
    FAIL();
  } catch (const Error& e) {
    EXPECT_EQ(e.code(), ErrorCode::kCorrupt);
  }
  try {
    ts::segment_members({0, 0, 2}, 3);  // segment 1 empty
    FAIL();
  } catch (const Error& e) {
    EXPECT_EQ(e.code(), ErrorCode::kCorrupt);
  }
}
