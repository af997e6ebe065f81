// Test helpers: exact comparison of Takes and C3D parameter sections (gtest expectations).
#pragma once

#include <gtest/gtest.h>

#include <cstring>
#include <set>
#include <string>

#include "capz/take.h"

namespace capz {
namespace testing_support {

// Every field a C3D round trip must keep, bit for bit (xyz compared as bytes).
inline void expect_same_take(const Take& a, const Take& b) {
  ASSERT_EQ(a.frames, b.frames);
  ASSERT_EQ(a.points, b.points);
  EXPECT_EQ(a.valid, b.valid);
  ASSERT_EQ(a.xyz.size(), b.xyz.size());
  if (!a.xyz.empty()) {  // memcmp must not see the null data() of an empty vector
    EXPECT_EQ(0, std::memcmp(a.xyz.data(), b.xyz.data(), a.xyz.size() * sizeof(double)));
  }
  EXPECT_EQ(a.labels, b.labels);
  EXPECT_EQ(a.descriptions, b.descriptions);
  EXPECT_EQ(a.rate, b.rate);
  EXPECT_EQ(a.units, b.units);
  EXPECT_EQ(a.first_frame, b.first_frame);
  EXPECT_EQ(a.analog.channels, b.analog.channels);
  EXPECT_EQ(a.analog.samples_per_frame, b.analog.samples_per_frame);
  EXPECT_EQ(a.analog.rate, b.analog.rate);
  EXPECT_EQ(a.analog.labels, b.analog.labels);
  ASSERT_EQ(a.analog.values.size(), b.analog.values.size());
  // memcmp must not see the null data() of an empty vector
  if (!a.analog.values.empty()) {
    EXPECT_EQ(0, std::memcmp(a.analog.values.data(), b.analog.values.data(),
                             a.analog.values.size() * sizeof(double)));
  }
  EXPECT_EQ(a.rotations.segments, b.rotations.segments);
  EXPECT_EQ(a.rotations.samples_per_frame, b.rotations.samples_per_frame);
  EXPECT_EQ(a.rotations.rate, b.rotations.rate);
  EXPECT_EQ(a.rotations.labels, b.rotations.labels);
  ASSERT_EQ(a.rotations.matrices.size(), b.rotations.matrices.size());
  ASSERT_EQ(a.rotations.reliability.size(), b.rotations.reliability.size());
  if (!a.rotations.matrices.empty()) {  // as bytes: NaN payloads count
    EXPECT_EQ(0, std::memcmp(a.rotations.matrices.data(), b.rotations.matrices.data(),
                             a.rotations.matrices.size() * sizeof(float)));
    EXPECT_EQ(0, std::memcmp(a.rotations.reliability.data(), b.rotations.reliability.data(),
                             a.rotations.reliability.size() * sizeof(float)));
  }
  ASSERT_TRUE(a.c3d && b.c3d);
  EXPECT_EQ(a.c3d->residual, b.c3d->residual);
  EXPECT_EQ(a.c3d->camera_mask, b.c3d->camera_mask);
  EXPECT_EQ(a.c3d->max_interpolation_gap, b.c3d->max_interpolation_gap);
  ASSERT_EQ(a.c3d->header_events.size(), b.c3d->header_events.size());
  for (size_t i = 0; i < a.c3d->header_events.size(); ++i) {
    EXPECT_EQ(a.c3d->header_events[i].time, b.c3d->header_events[i].time);
    EXPECT_EQ(a.c3d->header_events[i].display, b.c3d->header_events[i].display);
    EXPECT_EQ(a.c3d->header_events[i].label, b.c3d->header_events[i].label);
  }
}

// Groups and parameters in order, with ids, descriptions, locks, types, dims and bytes.
// `a` may have fewer parameters per group than `b` only if `b_may_add`; parameters named
// "GROUP:NAME" in `may_differ` may differ in type, dims and data.
inline void expect_same_groups(const std::vector<C3DGroup>& a, const std::vector<C3DGroup>& b,
                               const std::set<std::string>& may_differ = {},
                               bool b_may_add = false) {
  if (!b_may_add) {
    ASSERT_EQ(a.size(), b.size());
  }
  ASSERT_LE(a.size(), b.size());
  for (size_t g = 0; g < a.size(); ++g) {
    const C3DGroup& x = a[g];
    const C3DGroup& y = b[g];
    EXPECT_EQ(x.id, y.id);
    EXPECT_EQ(x.name, y.name);
    EXPECT_EQ(x.description, y.description);
    EXPECT_EQ(x.locked, y.locked);
    EXPECT_EQ(x.implicit, y.implicit);
    if (!b_may_add) {
      ASSERT_EQ(x.params.size(), y.params.size()) << x.name;
    }
    ASSERT_LE(x.params.size(), y.params.size()) << x.name;
    for (size_t k = 0; k < x.params.size(); ++k) {
      const C3DParameter& p = x.params[k];
      const C3DParameter& q = y.params[k];
      SCOPED_TRACE(x.name + ":" + p.name);
      EXPECT_EQ(p.name, q.name);
      EXPECT_EQ(p.description, q.description);
      EXPECT_EQ(p.locked, q.locked);
      if (may_differ.count(x.name + ":" + p.name)) continue;
      EXPECT_EQ(p.type, q.type);
      EXPECT_EQ(p.dims, q.dims);
      EXPECT_EQ(p.data, q.data);
    }
  }
}

}  // namespace testing_support
}  // namespace capz
