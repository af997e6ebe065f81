// The POSW position coder alone (docs/FORMAT.md 3.3): every predictor, the reference predictors
// 5/6 and both residual context schemes round-trip exactly, the encoder's choices decode to the
// same integers, and malformed predictor / reference fields are rejected.
#include <gtest/gtest.h>

#include <random>

#include "capz/error.h"
#include "coding/bytes.h"
#include "coding/entropy.h"
#include "coding/predict.h"
#include "coding/window_coder.h"
#include "support/positions_round_trip.h"

namespace capz {
namespace {

// Rigid groups of `group` points sharing one noisy motion plus small own jitter, on a grid of
// integers; gap_rate > 0 knocks out samples in runs.
WindowInts rigid_groups(size_t frames, size_t points, size_t group, double gap_rate,
                        unsigned seed) {
  WindowInts w;
  w.frames = frames;
  w.points = points;
  w.q.assign(frames * points * 3, 0);
  w.valid.assign(frames * points, 1);
  std::mt19937 rng(seed);
  std::normal_distribution<double> n(0, 1);
  std::uniform_real_distribution<double> u(0, 1);
  std::vector<double> base(3), vel(3), off(points * 3);
  for (double& o : off) o = n(rng) * 200;
  for (size_t g0 = 0; g0 < points; g0 += group) {
    for (int a = 0; a < 3; ++a) base[a] = n(rng) * 5000, vel[a] = 0;
    for (size_t f = 0; f < frames; ++f) {
      for (int a = 0; a < 3; ++a) {
        vel[a] = 0.95 * vel[a] + n(rng) * 4;
        base[a] += vel[a];
      }
      for (size_t p = g0; p < std::min(points, g0 + group); ++p)
        for (int a = 0; a < 3; ++a)
          w.q[(f * points + p) * 3 + a] =
              static_cast<int32_t>(std::lround(base[a] + off[p * 3 + a] + n(rng) * 0.4));
    }
  }
  if (gap_rate > 0)
    for (size_t p = 0; p < points; ++p) {
      bool gap = false;
      for (size_t f = 0; f < frames; ++f) {
        if (u(rng) < gap_rate) gap = !gap;
        if (gap) w.valid[f * points + p] = 0;
      }
    }
  return w;
}

TEST(Positions, GivenRigidGroupsThenReferencePredictorsChosenAndExact) {
  for (unsigned seed = 1; seed <= 3; ++seed) {
    SCOPED_TRACE(seed);
    WindowInts w = rigid_groups(200, 40, 5, 0, seed);
    std::vector<uint8_t> modes = positions_round_trip(w, 2);
    // Every group but its first point can follow another point of the group.
    EXPECT_GE(count_refs(modes), 20u);
  }
}

TEST(Positions, GivenGapsThenBothSchemesRoundTripExactly) {
  for (int scheme = 1; scheme <= 2; ++scheme) {
    SCOPED_TRACE(scheme);
    WindowInts w = rigid_groups(150, 30, 3, 0.05, 7);
    std::vector<uint8_t> modes = positions_round_trip(w, scheme);
    if (scheme == 1) {
      EXPECT_EQ(count_refs(modes), 0u);  // format 1.x has no references
    }
  }
}

TEST(Positions, GivenWrappingValuesAndFloat64LowBitsThenExact) {
  WindowInts w = rigid_groups(60, 12, 4, 0.02, 11);
  std::mt19937 rng(3);
  for (size_t i = 0; i < w.q.size(); i += 7) w.q[i] = static_cast<int32_t>(rng());
  w.lo.resize(w.q.size());
  for (uint32_t& v : w.lo) v = static_cast<uint32_t>(rng());
  positions_round_trip(w, 2, true);
}

TEST(Positions, GivenTinyWindowsThenExact) {
  for (size_t frames : {1, 2, 3}) {
    for (size_t points : {1, 2, 5}) {
      WindowInts w = rigid_groups(frames, points, 2, 0, 5);
      positions_round_trip(w, 2);
    }
  }
}

// Every predictor computed by the walk equals its definition in FORMAT.md 3.3, for a fixed
// mode and reference set (independent of the encoder's choices).
TEST(Positions, GivenFixedModesThenWalkPredictsAsSpecified) {
  WindowInts w = rigid_groups(6, 4, 4, 0, 9);
  w.valid[3 * 4 + 1] = 0;  // point 1 (a reference) missing at frame 3
  const std::vector<uint8_t> modes = {kPredLinear, kPredRefPrevious, kPredRefLinear,
                                      kPredRefLinear};
  const std::vector<uint32_t> ref = {0, 0, 1, 0};
  struct Recorder {
    const int32_t* q;
    std::vector<int32_t>* preds;
    int32_t operator()(size_t i, int32_t pred, int, int* tok) {
      (*preds)[i] = pred;
      *tok = 0;
      return q[i];
    }
  };
  std::vector<int32_t> q = w.q, preds(q.size(), 0);
  Recorder rec{w.q.data(), &preds};
  ResidualContexts ctx(2, 4);
  walk_window(6, 4, w.valid.data(), modes.data(), ref.data(), nullptr, q.data(), ctx, rec);
  auto Q = [&](size_t f, size_t p, int a) { return q[(f * 4 + p) * 3 + a]; };
  auto lin = [&](size_t f, size_t p, int a) {
    return f < 2 ? Q(f - 1, p, a) : 2 * Q(f - 1, p, a) - Q(f - 2, p, a);
  };
  for (size_t f = 1; f < 6; ++f)
    for (int a = 0; a < 3; ++a) {
      EXPECT_EQ(preds[(f * 4 + 0) * 3 + a], lin(f, 0, a));
      if (f != 3) {  // point 1 is a gap at frame 3
        EXPECT_EQ(preds[(f * 4 + 1) * 3 + a], Q(f - 1, 1, a) + Q(f, 0, a) - Q(f - 1, 0, a));
      }
      const int32_t ref_term = f == 3 ? 0 : Q(f, 1, a) - lin(f, 1, a);  // r = 1 is a gap at 3
      EXPECT_EQ(preds[(f * 4 + 2) * 3 + a], lin(f, 2, a) + ref_term);
      EXPECT_EQ(preds[(f * 4 + 3) * 3 + a], lin(f, 3, a) + Q(f, 0, a) - lin(f, 0, a));
    }
  EXPECT_EQ(Q(3, 1, 0), Q(2, 1, 0));  // the gap holds the previous frame's integers
}

// A POSW payload with the given modes, reference distances and an empty residual block.
std::vector<uint8_t> crafted(const std::vector<int32_t>& modes, const std::vector<uint32_t>& refs) {
  ByteWriter w;
  w.varint(0);  // no codec payload
  std::vector<uint8_t> m = encode_ints(modes);
  w.varint(m.size());
  w.bytes(m);
  if (!refs.empty()) {
    std::vector<uint8_t> r = encode_uints(refs);
    w.varint(r.size());
    w.bytes(r);
  }
  w.bytes(IntEncoder(1).finish());
  return std::move(w.buffer());
}

void expect_corrupt(const std::vector<uint8_t>& pos, int scheme, const char* needle) {
  WindowInts back;
  back.frames = 4;
  back.points = 3;
  back.valid.assign(12, 1);
  try {
    PositionsPayload pp = split_positions(pos.data(), pos.size(), "POSW");
    decode_positions(pp, {}, false, scheme, &back, "POSW");
    ADD_FAILURE() << "accepted";
  } catch (const Error& e) {
    EXPECT_EQ(e.code(), ErrorCode::kCorrupt);
    EXPECT_NE(std::string(e.what()).find(needle), std::string::npos) << e.what();
  }
}

TEST(Positions, GivenBadPredictorOrReferenceFieldsThenCorrupt) {
  expect_corrupt(crafted({0, 5, 0}, {1}), 2, "refers to point");      // r = 0 - 1
  expect_corrupt(crafted({0, 0, 6}, {2}), 2, "refers to point");      // r = 2 - 1 - 2
  expect_corrupt(crafted({5, 0, 0}, {0}), 2, "point 0");              // nothing to refer to
  expect_corrupt(crafted({0, 5, 0}, {0}), 1, "unknown predictor 5");  // not in format 1.x
  expect_corrupt(crafted({0, 7, 0}, {}), 2, "unknown predictor 7");
  expect_corrupt(crafted({0, 5, 6}, {0}), 2, "POSW");                 // one distance missing
}

}  // namespace
}  // namespace capz
