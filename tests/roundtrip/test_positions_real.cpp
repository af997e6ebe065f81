// The position coder's reference predictors (docs/FORMAT.md 8, predictors 5/6) on real data:
// a mesh sequence's float32 bits (the lossless path) and grid integers, and a mocap take's grid
// integers, are coded with references chosen by the encoder and decode to the same integers.
#include <gtest/gtest.h>

#include <cmath>

#include "capz/io.h"
#include "coding/positions.h"
#include "coding/predict.h"
#include "coding/quantiser.h"
#include "support/positions_round_trip.h"
#include "test_util.h"

namespace capz {
namespace {

// Integers of frames [0, frames) of t: ordered float32 bits (step 0) or round(x / step).
WindowInts ints_of(const Take& t, size_t frames, double step) {
  WindowInts w;
  w.frames = std::min(frames, t.frames);
  w.points = t.points;
  w.valid.assign(t.valid.begin(), t.valid.begin() + static_cast<long>(w.frames * t.points));
  w.q.resize(w.frames * t.points * 3);
  for (size_t k = 0; k < w.q.size(); ++k) {
    const double x = std::isfinite(t.xyz[k]) ? t.xyz[k] : 0.0;
    w.q[k] = step > 0 ? round_to_int(x / step) : float_to_ordered(static_cast<float>(x));
  }
  return w;
}

size_t refs_and_check(const WindowInts& w) {
  return count_refs(positions_round_trip(w, kPositionScheme));
}

TEST(PositionsReal, GivenMeshSequenceThenReferencesUsedAndExact) {
  const std::string path = capz_test::shared_data_or_skip("pcd/chickenCrossing");
  if (path.empty()) return;
  Take t = read_take(path);
  // Most vertices move with a neighbour: expect references for a clear majority of points.
  EXPECT_GT(refs_and_check(ints_of(t, 40, 0)), t.points / 2);      // float32 bits (lossless)
  EXPECT_GT(refs_and_check(ints_of(t, 40, 0.004)), t.points / 2);  // a grid
}

TEST(PositionsReal, GivenMocapTakeThenReferencesUsedAndExact) {
  const std::string path =
      capz_test::shared_data_or_skip("c3d/c3dorg/sample_37/ART-Human_2persons_integer.c3d");
  if (path.empty()) return;
  Take t = read_take(path);
  EXPECT_GT(refs_and_check(ints_of(t, 500, 2.0)), 0u);
  EXPECT_GT(refs_and_check(ints_of(t, 500, 0.049)), 0u);
}

}  // namespace
}  // namespace capz
