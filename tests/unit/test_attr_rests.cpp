// The scan encoder's memory of the fields' trials from window to window (FieldTrials):
// - lzma_rest: a field whose predictive coding beat LZMA by the margin skips the trials for the
//   next kLzmaRest windows (the same bytes while the predictive coding stays the smaller); a
//   field that LZMA codes smaller keeps its trial every window; a resting field still decodes;
// - near: the answer of the neighbour predictors' trial is taken without the trial for the next
//   kNearRest windows; a resting answer that they do not pay codes without them, and decodes.
#include <gtest/gtest.h>

#include <cstring>
#include <random>
#include <vector>

#include "coding/attributes.h"
#include "test_util.h"

namespace capz {
namespace {

// One ragged window of n points: a drift (U4, a random walk of unit steps: the predictive
// coding's) and a byte pattern repeating every 4096 points (random within it: LZMA's).
struct Window {
  std::vector<AttrSpec> specs = {capz_test::field_spec("drift", 'U', 4),
                                 capz_test::field_spec("pattern", 'U', 1)};
  std::vector<std::vector<uint8_t>> data = std::vector<std::vector<uint8_t>>(2);
  std::vector<uint8_t> valid;
  size_t n = 0;
};

Window window(size_t n, uint32_t start) {
  Window w;
  w.n = n;
  w.valid.assign(n, 1);
  std::mt19937 rng(5);
  std::vector<uint8_t> period(4096);
  for (uint8_t& b : period) b = static_cast<uint8_t>(rng());
  rng.seed(start);
  uint32_t v = start;
  for (size_t i = 0; i < n; ++i) {
    v = v + static_cast<uint32_t>(rng() % 3) - 1;
    for (int k = 0; k < 4; ++k) w.data[0].push_back(static_cast<uint8_t>(v >> (8 * k)));
    w.data[1].push_back(period[i % period.size()]);
  }
  return w;
}

std::vector<uint8_t> encode(const Window& w, FieldTrials* trials) {
  RaggedFields rf;
  rf.trials = trials;
  return encode_attributes(w.specs, w.data, w.valid.data(), 1, w.n, w.n, nullptr, true, &rf);
}

std::vector<std::vector<uint8_t>> decode(const Window& w, const std::vector<uint8_t>& e) {
  RaggedFields rf;
  std::vector<std::vector<uint8_t>> back;
  decode_attributes(e.data(), e.size(), w.specs, w.valid.data(), 1, w.n, w.n, &back, "test",
                    nullptr, &rf);
  return back;
}

TEST(AttrLzmaRest, TheTrialRestsWhilePredictionWins) {
  const Window w = window(40000, 100000);
  const std::vector<uint8_t> alone = encode(w, nullptr);
  FieldTrials trials;
  const std::vector<uint8_t>& rest = trials.lzma_rest;
  // The first window tries every transform: the bytes of a coding without the memory.
  EXPECT_EQ(encode(w, &trials), alone);
  ASSERT_EQ(rest.size(), 2u);
  EXPECT_EQ(rest[0], kLzmaRest);  // the drift: predicted far below LZMA
  EXPECT_EQ(rest[1], 0);          // the pattern: LZMA's, tried again
  // The next windows skip the drift's trials and count down; the bytes stay the same.
  for (int k = 1; k <= kLzmaRest; ++k) {
    EXPECT_EQ(encode(w, &trials), alone) << k;
    EXPECT_EQ(rest[0], kLzmaRest - k);
    EXPECT_EQ(rest[1], 0);
  }
  // The eighth tries them again.
  EXPECT_EQ(encode(w, &trials), alone);
  EXPECT_EQ(rest[0], kLzmaRest);
}

TEST(AttrLzmaRest, ASkippedFieldIsCodedPredictivelyAndDecodes) {
  const Window w = window(40000, 700000);
  const std::vector<uint8_t> alone = encode(w, nullptr);
  // The pattern's trial resting (as if an earlier window had been predictable): not LZMA.
  FieldTrials trials;
  trials.lzma_rest = {0, 3};
  const std::vector<uint8_t>& rest = trials.lzma_rest;
  const std::vector<uint8_t> skipped = encode(w, &trials);
  EXPECT_EQ(rest[1], 2);
  EXPECT_GT(skipped.size(), alone.size() + 1000);
  EXPECT_EQ(decode(w, skipped), w.data);
  EXPECT_EQ(decode(w, alone), w.data);
}

// One frame of 6000 points at random grid positions with an intensity smooth in space (in the
// points' random order only a neighbour predicts it).
struct Spatial {
  std::vector<AttrSpec> specs = {capz_test::field_spec("intensity", 'F', 4)};
  std::vector<std::vector<uint8_t>> data = std::vector<std::vector<uint8_t>>(1);
  std::vector<uint8_t> valid;
  std::vector<int32_t> q;
  size_t n = 6000;
  Spatial() {
    std::mt19937 rng(3);
    valid.assign(n, 1);
    for (size_t i = 0; i < n; ++i) {
      for (int a = 0; a < 3; ++a) q.push_back(static_cast<int32_t>(rng() % (a == 2 ? 50 : 4000)));
      const float v = 0.25f + 0.0002f * static_cast<float>(q[3 * i]) +
                      0.0001f * static_cast<float>(q[3 * i + 1]);
      uint8_t b[4];
      std::memcpy(b, &v, 4);
      data[0].insert(data[0].end(), b, b + 4);
    }
  }
  std::vector<uint8_t> encode(FieldTrials* trials) const {
    RaggedFields rf;
    rf.trials = trials;
    return encode_attributes(specs, data, valid.data(), 1, n, n, q.data(), true, &rf);
  }
  std::vector<std::vector<uint8_t>> decode(const std::vector<uint8_t>& e) const {
    RaggedFields rf;
    std::vector<std::vector<uint8_t>> back;
    decode_attributes(e.data(), e.size(), specs, valid.data(), 1, n, n, &back, "test", q.data(),
                      &rf);
    return back;
  }
};

TEST(AttrNearRest, TheAnswerRestsAndIsTakenWithoutTheTrial) {
  const Spatial s;
  const std::vector<uint8_t> alone = s.encode(nullptr);
  FieldTrials trials;
  const FieldTrials::Near& m = trials.near;
  EXPECT_EQ(s.encode(&trials), alone);  // the trial's window: a coding without the memory's bytes
  EXPECT_EQ(m.rest, kNearRest);
  EXPECT_TRUE(m.pays);
  for (int k = 1; k <= kNearRest; ++k) {
    EXPECT_EQ(s.encode(&trials), alone) << k;
    EXPECT_EQ(m.rest, kNearRest - k);
    EXPECT_TRUE(m.pays);
  }
  EXPECT_EQ(s.decode(alone), s.data);
}

TEST(AttrNearRest, ARestingNoCodesWithoutTheNeighboursAndDecodes) {
  const Spatial s;
  const std::vector<uint8_t> alone = s.encode(nullptr);
  FieldTrials trials;
  trials.near = FieldTrials::Near{3, false};
  const FieldTrials::Near& m = trials.near;
  const std::vector<uint8_t> without = s.encode(&trials);
  EXPECT_EQ(m.rest, 2);
  EXPECT_GT(without.size(), alone.size());
  EXPECT_EQ(s.decode(without), s.data);
}

}  // namespace
}  // namespace capz
