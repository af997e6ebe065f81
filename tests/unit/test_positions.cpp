// The POSW position coder alone (docs/FORMAT.md 3.3): every predictor, the reference predictors
// 5/6 and the smooth and period predictors 7-9 round-trip
// exactly, the encoder's choices decode to the same integers, and malformed predictor /
// reference / period fields are rejected.
#include <gtest/gtest.h>

#include <algorithm>
#include <cmath>
#include <random>

#include "capz/error.h"
#include "coding/bytes.h"
#include "coding/entropy.h"
#include "coding/positions.h"
#include "coding/predict.h"
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
    std::vector<uint8_t> modes = positions_round_trip(w);
    // Every group but its first point can follow another point of the group.
    EXPECT_GE(count_refs(modes), 20u);
  }
}

TEST(Positions, GivenGapsThenRoundTripsExactly) {
  WindowInts w = rigid_groups(150, 30, 3, 0.05, 7);
  positions_round_trip(w);
}

TEST(Positions, GivenWrappingValuesAndFloat64LowBitsThenExact) {
  WindowInts w = rigid_groups(60, 12, 4, 0.02, 11);
  std::mt19937 rng(3);
  for (size_t i = 0; i < w.q.size(); i += 7) w.q[i] = static_cast<int32_t>(rng());
  w.lo.resize(w.q.size());
  for (uint32_t& v : w.lo) v = static_cast<uint32_t>(rng());
  positions_round_trip(w, true);
}

TEST(Positions, GivenTinyWindowsThenExact) {
  for (size_t frames : {1, 2, 3}) {
    for (size_t points : {1, 2, 5}) {
      WindowInts w = rigid_groups(frames, points, 2, 0, 5);
      positions_round_trip(w);
    }
  }
}

// A walk's coder that records each prediction and returns the true integers (token 0).
struct Recorder {
  const int32_t* q;
  std::vector<int32_t>* preds;
  int32_t operator()(size_t i, int32_t pred, int, int* tok) {
    (*preds)[i] = pred;
    *tok = 0;
    return q[i];
  }
};

// Every predictor computed by the walk equals its definition in FORMAT.md 8, for a fixed
// mode and reference set (independent of the encoder's choices).
TEST(Positions, GivenFixedModesThenWalkPredictsAsSpecified) {
  WindowInts w = rigid_groups(6, 4, 4, 0, 9);
  w.valid[3 * 4 + 1] = 0;  // point 1 (a reference) missing at frame 3
  const std::vector<uint8_t> modes = {kPredLinear, kPredRefPrevious, kPredRefLinear,
                                      kPredRefLinear};
  const std::vector<uint32_t> ref = {0, 0, 1, 0};
  std::vector<int32_t> q = w.q, preds(q.size(), 0);
  Recorder rec{w.q.data(), &preds};
  ResidualContexts ctx(4);
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

// Predictors 7-9 as computed by the walk equal their definitions in FORMAT.md 8 (integer
// least-squares line with its rounding rule, one period back), including wrapping histories.
TEST(Positions, GivenSmoothAndPeriodModesThenWalkPredictsAsSpecified) {
  const size_t F = 12, N = 3, T = 4;
  WindowInts w = rigid_groups(F, N, 1, 0, 13);
  w.q[(2 * N + 0) * 3 + 1] = INT32_MAX - 3;  // wraps against its neighbours' values
  w.valid[5 * N + 1] = 0;                    // a gap: the walk holds frame 4's integers
  const std::vector<uint8_t> modes = {kPredSmooth, kPredPeriod, kPredPeriodPrevious};
  const std::vector<uint32_t> ref(N, 0);
  std::vector<int32_t> q = w.q, preds(q.size(), 0);
  Recorder rec{w.q.data(), &preds};
  ResidualContexts ctx(N);
  walk_window(F, N, w.valid.data(), modes.data(), ref.data(), nullptr, q.data(), ctx, rec, T);
  auto Q = [&](size_t f, size_t p, int a) -> int64_t { return q[(f * N + p) * 3 + a]; };
  auto wrap = [](int64_t v) { return static_cast<int32_t>(static_cast<uint32_t>(v)); };
  for (size_t f = 1; f < F; ++f)
    for (int a = 0; a < 3; ++a) {
      // Smooth: the least-squares line through the last K = min(6, f) values, at frame f.
      const int64_t K = std::min<int64_t>(6, static_cast<int64_t>(f));
      int64_t expect = Q(f - 1, 0, a);
      if (K >= 2) {
        int64_t n = 0;
        for (int64_t j = 2; j <= K; ++j) {
          const int64_t d = wrap(Q(f - static_cast<size_t>(j), 0, a) - Q(f - 1, 0, a));
          n += (4 * K + 2 - 6 * j) * d;
        }
        const int64_t D = K * (K - 1);
        const double exact = static_cast<double>(n) / static_cast<double>(D);
        const int64_t r = static_cast<int64_t>(std::llround(exact));  // halves away from zero
        EXPECT_LE(std::fabs(static_cast<double>(r) - exact), 0.5);
        expect = Q(f - 1, 0, a) + r;
      }
      EXPECT_EQ(preds[(f * N + 0) * 3 + a], wrap(expect)) << f;
      if (f != 5) {  // point 1 is a gap at frame 5
        EXPECT_EQ(preds[(f * N + 1) * 3 + a], wrap(f < T ? Q(f - 1, 1, a) : Q(f - T, 1, a)));
      }
      EXPECT_EQ(
          preds[(f * N + 2) * 3 + a],
          wrap(f < T + 1 ? Q(f - 1, 2, a) : Q(f - 1, 2, a) + Q(f - T, 2, a) - Q(f - T - 1, 2, a)));
    }
}

// The smooth predictor's rounding: halves go away from zero on both sides.
TEST(Positions, GivenHalfwayLinesThenSmoothRoundsAwayFromZero) {
  const size_t stride = 1;
  // K = 2 (f = 2) is linear; K = 4: weights 1, 1/2, 0, -1/2 -> q1 + (q2 - q1) / 2 - (q4 - q1) / 2.
  const int32_t up[5] = {0, 0, 1, 1, 0};  // q4..q1 = 0, 0, 1, 1 -> 1 + (1 - 1) / 2 + 1 / 2
  const int32_t down[5] = {0, 0, -1, -1, 0};
  EXPECT_EQ(predict_smooth(4, up + 4, stride), 2);     // 1.5 -> 2
  EXPECT_EQ(predict_smooth(4, down + 4, stride), -2);  // -1.5 -> -2
  const int32_t lin[3] = {3, 5, 0};
  EXPECT_EQ(predict_smooth(2, lin + 2, stride), 7);
  EXPECT_EQ(predict_smooth(1, lin + 1, stride), 3);
}

// A take whose motion repeats every `period` frames (a looped animation), with a little noise
// in the repeats when `noise` is set: one integer in 10 of a repeat differs by 1.
WindowInts looped(size_t frames, size_t points, size_t period, bool noise, unsigned seed) {
  WindowInts cycle = rigid_groups(period, points, 4, 0, seed);
  WindowInts w;
  w.frames = frames;
  w.points = points;
  w.valid.assign(frames * points, 1);
  w.q.resize(frames * points * 3);
  std::mt19937 rng(seed + 100);
  for (size_t f = 0; f < frames; ++f)
    for (size_t k = 0; k < points * 3; ++k)
      w.q[f * points * 3 + k] =
          cycle.q[(f % period) * points * 3 + k] +
          (noise && f >= period && rng() % 10 == 0 ? static_cast<int32_t>(rng() % 2) * 2 - 1 : 0);
  return w;
}

TEST(Positions, GivenLoopedMotionThenPeriodPredictorsChosen) {
  for (bool noise : {false, true}) {
    SCOPED_TRACE(noise);
    const WindowInts w = looped(96, 40, 24, noise, 21);
    const std::vector<uint8_t> modes = positions_round_trip(w);
    size_t periodic = 0;
    for (uint8_t m : modes) periodic += uses_period(m) ? 1 : 0;
    EXPECT_GE(periodic, 30u);  // a few points may follow a rigid neighbour instead
    // The stream holds the period, 24 frames, after the reference block if there is one.
    std::vector<uint8_t> pos = encode_positions(w, {}, {}, false);
    PositionsPayload pp = split_positions(pos.data(), pos.size(), "test");
    ByteReader r(pp.residuals, pp.residuals_size, "test");
    if (count_refs(modes) > 0) r.bytes(static_cast<size_t>(r.varint()));
    EXPECT_EQ(r.varint(), 24u);
  }
}

// Noisy sines a few grid steps a frame fast (a coarse grid's staircase): the smooth predictor
// is chosen for most points.
TEST(Positions, GivenStaircasesThenSmoothPredictorChosen) {
  WindowInts w;
  w.frames = 600;
  w.points = 12;
  w.valid.assign(w.frames * w.points, 1);
  w.q.resize(w.frames * w.points * 3);
  std::mt19937 rng(5);
  std::normal_distribution<double> n(0, 1);
  for (size_t k = 0; k < w.points * 3; ++k) {
    const double amp = 40 * (1 + 0.3 * n(rng)), freq = 0.03 * (1 + 0.2 * n(rng)), ph = n(rng);
    for (size_t f = 0; f < w.frames; ++f)
      w.q[f * w.points * 3 + k] = static_cast<int32_t>(
          std::lround(amp * std::sin(freq * static_cast<double>(f) + ph) + 0.1 * n(rng)));
  }
  const std::vector<uint8_t> modes = positions_round_trip(w);
  EXPECT_GE(std::count(modes.begin(), modes.end(), kPredSmooth), 9);
}

// A POSW payload with the given modes, reference distances and an empty residual block.
std::vector<uint8_t> crafted(const std::vector<int32_t>& modes, const std::vector<uint32_t>& refs,
                             int64_t period = -1) {
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
  if (period >= 0) w.varint(static_cast<uint64_t>(period));
  w.bytes(IntEncoder(1).finish());
  return std::move(w.buffer());
}

void expect_corrupt(const std::vector<uint8_t>& pos, const char* needle) {
  WindowInts back;
  back.frames = 4;
  back.points = 3;
  back.valid.assign(12, 1);
  try {
    PositionsPayload pp = split_positions(pos.data(), pos.size(), "POSW");
    decode_positions(pp, {}, false, &back, "POSW");
    ADD_FAILURE() << "accepted";
  } catch (const Error& e) {
    EXPECT_EQ(e.code(), ErrorCode::kCorrupt);
    EXPECT_NE(std::string(e.what()).find(needle), std::string::npos) << e.what();
  }
}

TEST(Positions, GivenBadPredictorOrReferenceFieldsThenCorrupt) {
  expect_corrupt(crafted({0, 5, 0}, {1}), "refers to point");       // r = 0 - 1
  expect_corrupt(crafted({0, 0, 6}, {2}), "refers to point");       // r = 2 - 1 - 2
  expect_corrupt(crafted({5, 0, 0}, {0}), "point 0");               // nothing to refer to
  expect_corrupt(crafted({0, 10, 0}, {}), "unknown predictor 10");  // no ray rule given
  expect_corrupt(crafted({0, 11, 0}, {}), "unknown predictor 11");
  expect_corrupt(crafted({0, 5, 6}, {0}), "POSW");  // one distance missing
}

TEST(Positions, GivenBadPeriodFieldThenCorrupt) {
  // The window has 4 frames: 1 <= T <= 3.
  expect_corrupt(crafted({0, 8, 0}, {}, 0), "period of 0 frames");
  expect_corrupt(crafted({9, 0, 0}, {}, 4), "period of 4 frames");
  expect_corrupt(crafted({0, 5, 9}, {0}, int64_t{1} << 40), "period of");
  expect_corrupt(crafted({0, 0, 8}, {}), "POSW");  // the period is missing (truncated)
}

// encode_positions_bound (the one-sweep choice's cheapest size bound of the fixed stream): the
// payload encode_positions writes, its residual block cut to the raw bits' bytes at its end (the
// range coder's bytes and their varint left out), so never larger; in mode 3 with the low words.
TEST(Positions, GivenWindowThenBoundIsThePayloadLessTheRangeCodersBytes) {
  for (bool float64 : {false, true}) {
    for (unsigned seed = 1; seed <= 3; ++seed) {
      WindowInts w = rigid_groups(6, 40, seed == 1 ? 40 : 5, seed == 3 ? 0.1 : 0, seed);
      if (float64) w.lo.assign(w.q.size(), 0x12345678u);
      const std::vector<uint8_t> real = encode_positions(w, {}, {}, float64);
      const std::vector<uint8_t> bound = encode_positions_bound(w, {}, {}, float64);
      const PositionsPayload pp = split_positions(real.data(), real.size(), "test");
      // After the predictors: the references' block and the period when a point uses them, then
      // the residual block: the range coder's bytes after their count, then the raw bits'.
      const std::vector<uint8_t> modes = decode_modes(pp, w.points, "test");
      ByteReader r(pp.residuals, pp.residuals_size, "test");
      if (std::any_of(modes.begin(), modes.end(), [](uint8_t m) { return uses_ref(m); }))
        r.bytes(static_cast<size_t>(r.varint()));
      if (std::any_of(modes.begin(), modes.end(), [](uint8_t m) { return uses_period(m); }))
        r.varint();
      const size_t head = static_cast<size_t>(pp.residuals - real.data()) + r.offset();
      const uint64_t rc = r.varint();
      const size_t raw = r.remaining() - static_cast<size_t>(rc);
      const size_t valid = static_cast<size_t>(std::count(w.valid.begin(), w.valid.end(), 1));
      EXPECT_GE(raw, float64 ? 12 * valid : 1u);  // mode 3: a low word a coordinate
      ASSERT_EQ(bound.size(), head + raw) << float64 << " " << seed;
      EXPECT_TRUE(std::equal(bound.begin(), bound.begin() + static_cast<long>(head), real.begin()));
      EXPECT_LT(bound.size(), real.size());
    }
  }
}

}  // namespace
}  // namespace capz
