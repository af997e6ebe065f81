// LPC analysis stage: autocorrelation, Levinson-Durbin, quantisation and order choice.
#include <gtest/gtest.h>

#include <algorithm>
#include <cmath>
#include <cstring>
#include <random>
#include <vector>

#include "coding/analog/analog_cascade.h"
#include "coding/analog/analog_lpc.h"
#include "coding/analog/analog_simd.h"
#include "coding/entropy.h"

namespace capz {
namespace analog {
namespace {

TEST(AnalogLpc, GivenKnownAr2AutocorrelationWhenLevinsonThenExactCoefficients) {
  // x[i] = 1.2 x[i-1] - 0.5 x[i-2] + e: r from the Yule-Walker equations (r0 = 1).
  const double a1 = 1.2, a2 = -0.5;
  const double r1 = a1 / (1 - a2), r2 = a1 * r1 + a2;
  const double r3 = a1 * r2 + a2 * r1;
  std::vector<std::vector<double>> a;
  std::vector<double> err;
  EXPECT_EQ(levinson({1, r1, r2, r3}, 3, &a, &err), 3);
  EXPECT_NEAR(a[2][0], a1, 1e-12);
  EXPECT_NEAR(a[2][1], a2, 1e-12);
  EXPECT_NEAR(a[3][2], 0, 1e-12);  // order 3 adds nothing
  EXPECT_NEAR(err[3], err[2], 1e-12);
  EXPECT_LT(err[2], err[1]);
  EXPECT_LT(err[1], err[0]);
}

TEST(AnalogLpc, GivenSingularAutocorrelationWhenLevinsonThenStopsEarly) {
  std::vector<std::vector<double>> a;
  std::vector<double> err;
  EXPECT_EQ(levinson({0, 0, 0}, 2, &a, &err), 0);
  // A pure sinusoid is predicted exactly at order 2: the recursion stops there.
  std::vector<int32_t> x(2000);
  for (size_t i = 0; i < x.size(); ++i)
    x[i] = static_cast<int32_t>(std::lround(1e6 * std::sin(0.05 * i)));
  EXPECT_LE(levinson(autocorrelation(x.data(), x.size(), 8), 8, &a, &err), 8);
  EXPECT_LT(err.back(), err[0] * 1e-6);
}

TEST(AnalogLpc, GivenCoefficientsWhenQuantisedThenWithinPrecisionAndClose) {
  const double a[4] = {1.9, -0.93, 0.02, -0.0001};
  const LpcParams p = quantise_lpc(a, 4, kLpcPrecision);
  ASSERT_EQ(p.order, 4);
  for (int j = 0; j < 4; ++j) {
    EXPECT_LT(std::abs(p.q[j]), 1 << kLpcPrecision);
    EXPECT_NEAR(p.q[j] / std::ldexp(1.0, p.shift), a[j], 2.0 / std::ldexp(1.0, p.shift));
  }
  EXPECT_EQ(quantise_lpc(a, 0, kLpcPrecision).order, 0);
}

// 4096 samples of y[i] = a1 y[i-1] + a2 y[i-2] + e, e normal with sd 10, rounded.
std::vector<int32_t> ar2_signal(unsigned seed, double a1, double a2) {
  std::mt19937 rng(seed);
  std::normal_distribution<double> e(0, 10);
  std::vector<int32_t> x(4096);
  double x1 = 0, x2 = 0;
  for (auto& v : x) {
    const double y = a1 * x1 + a2 * x2 + e(rng);
    v = static_cast<int32_t>(std::lround(y));
    x2 = x1;
    x1 = y;
  }
  return x;
}

TEST(AnalogLpc, GivenAr2SignalWhenOrderChosenThenResidualNearInnovation) {
  const std::vector<int32_t> x = ar2_signal(1, 1.6, -0.8);
  const LpcParams p = choose_lpc(x.data(), x.size());
  EXPECT_GE(p.order, 2);
  EXPECT_LE(p.order, 8);
  double ss = 0;
  for (size_t i = 32; i < x.size(); ++i) {
    const double r = x[i] - lpc_predict(p, x.data() + i);
    ss += r * r;
  }
  EXPECT_LT(std::sqrt(ss / (x.size() - 32)), 12.0);  // innovation sd 10 (+ rounding)
}

// x after kMaxLpcOrder zeros, as T (lpc_predict and LpcKernel read before the first sample).
template <typename T>
std::vector<T> padded(const std::vector<int32_t>& x) {
  std::vector<T> xp(kMaxLpcOrder + x.size(), T(0));
  std::copy(x.begin(), x.end(), xp.begin() + kMaxLpcOrder);
  return xp;
}

// x[i] - lpc_predict(p) for i in [from, x.size()), the samples before x[0] being 0.
std::vector<int32_t> residuals_of(const std::vector<int32_t>& x, const LpcParams& p,
                                  size_t from = 0) {
  const std::vector<int32_t> xp = padded<int32_t>(x);
  std::vector<int32_t> r;
  for (size_t i = from; i < x.size(); ++i)
    r.push_back(static_cast<int32_t>(x[i] - lpc_predict(p, xp.data() + kMaxLpcOrder + i)));
  return r;
}

// Max |q| of p's coefficients: below 2^precision for the precision they were quantised at.
int32_t max_coefficient(const LpcParams& p) {
  int32_t m = 0;
  for (int32_t q : p.q) m = std::max(m, std::abs(q));
  return m;
}

// The residuals' estimated cost plus the coefficients' (choose_block_predictor's measure).
double estimated_bits(const std::vector<int32_t>& x, const LpcParams& p) {
  const std::vector<int32_t> r = residuals_of(x, p);
  return token_cost_bits(r.data(), r.size()) + coefficient_bits(p);
}

// On a noisy AR(2) block the coefficients' precision matters little against the residual, so
// choose_lpc codes them coarser than kLpcPrecision, and the block is estimated smaller so.
TEST(AnalogLpc, GivenNoisyAr2WhenOrderChosenThenCoarserCoefficientsAndFewerBits) {
  const std::vector<int32_t> x = ar2_signal(5, 1.6, -0.8);
  double full_bits = -1;
  const LpcParams p = choose_lpc(x.data(), x.size(), &full_bits);
  ASSERT_GE(p.order, 2);
  EXPECT_LT(max_coefficient(p), 1 << (kLpcPrecision - 2));
  // The same order at full precision, from the same analysis.
  std::vector<std::vector<double>> a;
  std::vector<double> err;
  ASSERT_GE(levinson(autocorrelation(x.data(), x.size(), p.order), p.order, &a, &err), p.order);
  const LpcParams full = quantise_lpc(a[p.order].data(), p.order, kLpcPrecision);
  EXPECT_GE(max_coefficient(full), 1 << (kLpcPrecision - 1));
  EXPECT_DOUBLE_EQ(full_bits, coefficient_bits(full));
  EXPECT_LT(estimated_bits(x, p), estimated_bits(x, full));
}

// A sinusoid of amplitude 2^14 with little noise is predicted to within a few counts, where a
// coarse coefficient would add far more error than its bits save: the precision stays fine.
TEST(AnalogLpc, GivenNearlyExactSignalWhenOrderChosenThenFinePrecisionKept) {
  std::mt19937 rng(6);
  std::normal_distribution<double> e(0, 1);
  std::vector<int32_t> x(4096);
  for (size_t i = 0; i < x.size(); ++i)
    x[i] = static_cast<int32_t>(std::lround(16384 * std::sin(0.05 * i) + e(rng)));
  const LpcParams p = choose_lpc(x.data(), x.size());
  ASSERT_GE(p.order, 2);
  EXPECT_GE(max_coefficient(p), 1 << (kLpcPrecision - 2));
}

// A held signal (a slow channel repeated up to the analog rate: long runs of one value, then a
// jump) has mostly-zero first differences, which the autocorrelation's choice does not find:
// the block's predictor, chosen by estimated coded cost, is the first difference, its
// residuals are written out, and they cost less than choose_lpc's.
TEST(AnalogLpc, GivenHeldSignalWhenBlockPredictorChosenThenFirstDifferenceAndSmaller) {
  std::mt19937 rng(3);
  std::normal_distribution<double> e(0, 300);
  std::vector<int32_t> x(4096);
  int32_t v = 0;
  for (size_t i = 0; i < x.size(); ++i) {
    if (i % 13 == 0) v = static_cast<int32_t>(std::lround(0.9 * v + e(rng)));
    x[i] = v;
  }
  const std::vector<double> xd = padded<double>(x);
  std::vector<int32_t> r(x.size());
  const LpcParams p =
      choose_block_predictor(x.data(), xd.data() + kMaxLpcOrder, x.size(), r.data());
  ASSERT_EQ(p.order, 1);
  EXPECT_EQ(p.q[0], 1 << p.shift);
  EXPECT_EQ(r, residuals_of(x, p));
  const std::vector<int32_t> rl = residuals_of(x, choose_lpc(x.data(), x.size()));
  EXPECT_LT(token_cost_bits(r.data(), r.size()), 0.8 * token_cost_bits(rl.data(), rl.size()));
}

// With allow_constant, uniform noise around 5000 is predicted by its rounded mean (FORMAT.md
// 9.3): the residuals are x - mean, cheaper than order 0's or a difference's; without, it is not.
TEST(AnalogLpc, GivenNoiseAroundALevelWhenConstantAllowedThenMeanPredicts) {
  std::mt19937 rng(8);
  std::uniform_int_distribution<int> noise(-100, 100);
  std::vector<int32_t> x(4096);
  for (auto& v : x) v = 5000 + noise(rng);
  const std::vector<double> xd = padded<double>(x);
  std::vector<int32_t> r(x.size());
  int64_t sum = 0;
  for (int32_t v : x) sum += v;
  const LpcParams c =
      choose_block_predictor(x.data(), xd.data() + kMaxLpcOrder, x.size(), r.data(), true);
  EXPECT_EQ(c.order, 0);
  EXPECT_EQ(c.constant, std::llround(static_cast<double>(sum) / static_cast<double>(x.size())));
  const std::vector<int32_t> xp = padded<int32_t>(x);
  for (size_t i = 0; i < x.size(); ++i) {
    ASSERT_EQ(r[i], x[i] - c.constant) << i;
    ASSERT_EQ(lpc_predict(c, xp.data() + kMaxLpcOrder + i), c.constant) << i;
  }
  std::vector<int32_t> r0(x.size());
  const LpcParams p =
      choose_block_predictor(x.data(), xd.data() + kMaxLpcOrder, x.size(), r0.data(), false);
  EXPECT_EQ(p.constant, 0);
  EXPECT_LT(token_cost_bits(r.data(), r.size()) + 40, token_cost_bits(r0.data(), r0.size()));
}

// On an AR(2) signal the autocorrelation's choice stays (it beats the fixed differences).
TEST(AnalogLpc, GivenAr2SignalWhenBlockPredictorChosenThenLevinsonKept) {
  const std::vector<int32_t> x = ar2_signal(4, 1.2, -0.7);
  const std::vector<double> xd = padded<double>(x);
  std::vector<int32_t> r(x.size());
  const LpcParams p =
      choose_block_predictor(x.data(), xd.data() + kMaxLpcOrder, x.size(), r.data());
  const LpcParams l = choose_lpc(x.data(), x.size());
  EXPECT_EQ(p.order, l.order);
  EXPECT_EQ(p.q, l.q);
}

// token_cost_bits: n equal values cost nothing; two equiprobable small tokens one bit each; a
// value with raw bits adds them.
TEST(AnalogLpc, GivenKnownResidualsWhenTokenCostThenOrderZeroEntropyPlusRawBits) {
  const std::vector<int32_t> same(100, 7);
  EXPECT_DOUBLE_EQ(token_cost_bits(same.data(), same.size()), 100.0 * 2);  // zigzag 14: 2 raw bits
  std::vector<int32_t> two(100);
  for (size_t i = 0; i < two.size(); ++i) two[i] = i % 2 ? 1 : 0;  // zigzag 2 and 0: tokens 2, 0
  EXPECT_NEAR(token_cost_bits(two.data(), two.size()), 100.0, 1e-9);
}

// token_cost_bits counts tokens through the exponent of |2 v + 1/2| (analog_lpc.cpp): it
// equals the entropy of a histogram counted with token_of, over the whole int32 range and odd
// lengths.
TEST(AnalogLpc, GivenAnyInt32ResidualsWhenTokenCostThenAsTokenOfHistogram) {
  std::mt19937 rng(11);
  std::vector<int32_t> special = {0,
                                  1,
                                  -1,
                                  2,
                                  -2,
                                  3,
                                  -3,
                                  4,
                                  -4,
                                  5,
                                  INT32_MAX,
                                  INT32_MIN,
                                  INT32_MIN + 1,
                                  1 << 28,
                                  -(1 << 28),
                                  (1 << 29) + 1};
  for (int b = 2; b < 31; ++b)
    for (int d = -1; d <= 1; ++d) {
      special.push_back((1 << b) + d);
      special.push_back(-(1 << b) + d);
    }
  for (size_t n : {size_t{1}, size_t{2}, size_t{7}, size_t{1000}, size_t{4097}}) {
    std::vector<int32_t> r(n);
    for (size_t i = 0; i < n; ++i) {
      const int kind = static_cast<int>(rng() % 3);
      r[i] = kind == 0   ? special[rng() % special.size()]
             : kind == 1 ? static_cast<int32_t>(rng() % 41) - 20
                         : static_cast<int32_t>(rng());
    }
    uint32_t count[64] = {};
    uint64_t raw = 0;
    for (int32_t v : r) {
      int extra;
      ++count[token_of(zigzag(v), &extra)];
      raw += static_cast<uint64_t>(extra);
    }
    double want = static_cast<double>(raw);
    for (int t = 0; t < 64; ++t)
      if (count[t]) want -= count[t] * std::log2(count[t] / static_cast<double>(n));
    EXPECT_EQ(token_cost_bits(r.data(), n), want) << n;
  }
}

// Whichever predictor a block gets (LPC, none, first or second difference, the latter near the
// clamp), the residuals written are x - lpc_predict of it, the samples before the block being
// the channel's earlier ones.
TEST(AnalogLpc, GivenVariedBlocksWhenBlockPredictorChosenThenResidualsMatchIt) {
  std::mt19937 rng(5);
  std::normal_distribution<double> e(0, 1);
  int seen[3] = {0, 0, 0};  // orders 0, 1, 2 chosen
  for (int kind = 0; kind < 5; ++kind) {
    const size_t head = 37, n = 1001;  // odd block length
    std::vector<int32_t> x(head + n);
    double v = 0, w = 0;
    for (size_t i = 0; i < x.size(); ++i) {
      if (kind == 0) v = 1000 * e(rng);                // white: none
      if (kind == 1 && i % 7 == 0) v += 500 * e(rng);  // held steps: first difference
      if (kind == 2) v += (w += 3 * e(rng));           // integrated walk: second difference
      if (kind == 3) v = (1 << 28) - std::fabs(v - (1 << 28) + (w += 50 * e(rng)));  // at the clamp
      if (kind == 4) v = 0.9 * v + 100 * e(rng);                                     // AR(1): LPC
      v = std::max<double>(-(1 << 28), std::min<double>(1 << 28, v));
      x[i] = static_cast<int32_t>(std::lround(v));
    }
    const std::vector<double> xd = padded<double>(x);
    std::vector<int32_t> r(n);
    const LpcParams p =
        choose_block_predictor(x.data() + head, xd.data() + kMaxLpcOrder + head, n, r.data());
    if (p.order <= 2 && (p.order == 0 || p.q[0] == 1 << p.shift || p.shift == 12)) ++seen[p.order];
    EXPECT_EQ(r, residuals_of(x, p, head)) << kind;
  }
  EXPECT_GT(seen[0], 0);
  EXPECT_GT(seen[1], 0);
  EXPECT_GT(seen[2], 0);
}

// The tally of the chosen residuals' tokens, kept across blocks and corrected where residuals
// are replaced (the window's head, as the encoder's LPC stage does), gives token_cost_bits of
// the final residuals, the same double: the encoder uses it in place of a pass. Kind 5 (noise
// around a level) takes 9.1's constant predictor, whose residuals are tallied too.
TEST(AnalogLpc, GivenBlocksWithTallyWhenResidualsReplacedThenTokenCostBitsExactly) {
  std::mt19937 rng(31);
  std::normal_distribution<double> e(0, 1);
  int picks[3] = {0, 0, 0}, constants = 0;
  for (int kind = 0; kind < 6; ++kind) {
    const size_t n = 4096 * 2 + 777, block = 4096;
    std::vector<int32_t> x(n);
    double v = 0, w = 0;
    for (size_t i = 0; i < n; ++i) {
      const int k = kind != 4 ? kind : static_cast<int>(i / block);  // kind 4: a mix by block
      if (k == 0) v = 1000 * e(rng);
      if (k == 1 && i % 7 == 0) v += 500 * e(rng);
      if (k == 2) v += (w += 3 * e(rng));
      if (k == 3) v = 0.9 * v + 100 * e(rng);
      if (k == 5) v = 5000 + 100 * e(rng);
      v = std::max<double>(-(1 << 28), std::min<double>(1 << 28, v));
      x[i] = static_cast<int32_t>(std::lround(v));
    }
    std::vector<double> xd(kMaxLpcOrder + n, 0.0);
    std::copy(x.begin(), x.end(), xd.begin() + kMaxLpcOrder);
    std::vector<int32_t> r(n);
    TokenTally tally;
    for (size_t b0 = 0; b0 < n; b0 += block) {
      const size_t b1 = std::min(n, b0 + block);
      const LpcParams p = choose_block_predictor(x.data() + b0, xd.data() + kMaxLpcOrder + b0,
                                                 b1 - b0, r.data() + b0, true, &tally);
      ++picks[std::min(p.order, 2)];
      constants += p.constant != 0;
      ASSERT_EQ(tally.bits(b1), token_cost_bits(r.data(), b1)) << kind << " block at " << b0;
    }
    // The first 32 residuals replaced (by x[i], say), one by one.
    for (size_t i = 0; i < 32; ++i) {
      tally.remove(r[i]);
      r[i] = x[i];
      tally.add(r[i]);
    }
    EXPECT_EQ(tally.bits(n), token_cost_bits(r.data(), n)) << kind;
  }
  EXPECT_GT(picks[0], 0);
  EXPECT_GT(picks[1], 0);
  EXPECT_GT(picks[2], 0);
  EXPECT_GT(constants, 0);
}

TEST(AnalogLpc, GivenWhiteNoiseWhenOrderChosenThenNoPrediction) {
  std::mt19937 rng(2);
  std::vector<int32_t> x(4096);
  for (auto& v : x) v = static_cast<int32_t>(rng() % 1000) - 500;
  EXPECT_EQ(choose_lpc(x.data(), x.size()).order, 0);
}

TEST(AnalogLpc, GivenExtremeInputsWhenPredictedThenClampedToSampleRange) {
  LpcParams p;
  p.order = 2;
  p.shift = 0;
  p.q = {(1 << kLpcPrecision) - 1, (1 << kLpcPrecision) - 1};
  const int32_t x[3] = {kMaxSample, kMaxSample, 0};
  EXPECT_EQ(lpc_predict(p, x + 2), kMaxSample);
}

}  // namespace
}  // namespace analog
}  // namespace capz

namespace capz {
namespace analog {
namespace {

// The cascade learns what LPC left: a residual that is itself predictable shrinks.
TEST(AnalogCascade, GivenCorrelatedResidualWhenAdaptedThenOutputSmaller) {
  std::mt19937 rng(3);
  std::normal_distribution<double> e(0, 50);
  SignLms lms;
  double x1 = 0, in_ss = 0, out_ss = 0;
  for (int i = 0; i < 20000; ++i) {
    const double y = 0.9 * x1 + e(rng);
    x1 = y;
    const int64_t in = std::lround(y);
    const int64_t out = in - lms.predict();
    lms.update(in, out);
    if (i >= 10000) {
      in_ss += static_cast<double>(in) * in;
      out_ss += static_cast<double>(out) * out;
    }
  }
  EXPECT_LT(out_ss, 0.4 * in_ss);  // an AR(1) with 0.9: innovation power 0.19 of the total
}

TEST(AnalogCascade, GivenExtremeInputsThenPredictionStaysInSampleRange) {
  SignLms lms;
  for (int i = 0; i < 5000; ++i) {
    const int64_t in = (i & 1) ? kMaxSample : -kMaxSample;
    const int64_t p = lms.predict();
    EXPECT_LE(p, kMaxSample);
    EXPECT_GE(p, -kMaxSample);
    lms.update(in, in - p);
  }
}

// The integer sign-LMS of analog_cascade.h's comment, step by step in int64 (the reference the
// double-lane SignLms and sign_lms_residuals must match exactly).
class IntSignLms {
 public:
  int64_t predict() const {
    int64_t s = 0;
    for (int j = 0; j < SignLms::kTaps; ++j) s += static_cast<int64_t>(w_[j]) * h_[j];
    s = (s + (int64_t{1} << (SignLms::kShift - 1))) >> SignLms::kShift;
    return s > kMaxSample ? kMaxSample : s < -kMaxSample ? -kMaxSample : s;
  }
  void update(int64_t in, int64_t out) {
    const int32_t d = out > 0 ? SignLms::kStep : out < 0 ? -SignLms::kStep : 0;
    for (int j = 0; j < SignLms::kTaps && d != 0; ++j) {
      const int32_t w = w_[j] + (h_[j] > 0 ? d : h_[j] < 0 ? -d : 0);
      w_[j] = std::max(-SignLms::kMaxWeight, std::min(SignLms::kMaxWeight, w));
    }
    for (int j = SignLms::kTaps - 1; j > 0; --j) h_[j] = h_[j - 1];
    h_[0] = static_cast<int32_t>(std::max<int64_t>(-kMaxSample, std::min<int64_t>(kMaxSample, in)));
  }

 private:
  int32_t w_[SignLms::kTaps] = {};
  int32_t h_[SignLms::kTaps] = {};
};

std::vector<std::vector<int32_t>> cascade_inputs() {
  std::vector<std::vector<int32_t>> seqs;
  std::mt19937 rng(11);
  std::normal_distribution<double> e(0, 300);
  std::vector<int32_t> ar, extreme, flat, steps;
  double x1 = 0;
  for (int i = 0; i < 30000; ++i) {
    x1 = 0.95 * x1 + e(rng);
    ar.push_back(static_cast<int32_t>(std::lround(x1)));
    extreme.push_back((i % 3) ? kMaxSample : -kMaxSample);
    flat.push_back(i < 15000 ? (1 << 30) : -(1 << 30));  // beyond the history clamp
    steps.push_back(((i / 700) % 2 ? 1 : -1) * (i % 7) * 40000);
  }
  // Residuals of every size in one sequence: any value an LPC residual takes (|r| < 2^29, so
  // that the outputs fit int32), runs at the clamp of either
  // sign, and stretches of the AR(1) series scaled to large values.
  std::vector<int32_t> wild;
  for (int i = 0; i < 30000; ++i) {
    const int k = static_cast<int>(rng() % 8);
    const int32_t sign = (i / 50) % 2 ? 1 : -1;
    wild.push_back(k == 0   ? static_cast<int32_t>(rng() % (1u << 30)) - (1 << 29)
                   : k == 1 ? sign * (kMaxSample + static_cast<int32_t>(rng() % 3) - 1)
                            : ar[i] * ((i / 3000) % 3 ? 1 : 20000));
  }
  std::vector<int32_t> odd(ar.begin(), ar.begin() + 1001);  // an odd count: the scalar tail
  odd.push_back(-(1 << 30));
  odd.push_back(1 << 29);
  seqs = {ar, extreme, flat, steps, odd, wild, {}, {7}};
  return seqs;
}

// sign_lms_run on int32 outputs runs its AVX2 kernel where the CPU has AVX2, the portable one
// otherwise or when switched off; int64 outputs run the portable one: each matches exactly.
TEST(AnalogCascade, GivenInputsWhenRunAsDoublesThenExactlyTheIntegerFilter) {
  for (bool avx2 : {true, false})
    for (const std::vector<int32_t>& in : cascade_inputs()) {
      allow_avx2(avx2);
      IntSignLms ref;
      SignLms lms;
      std::vector<int64_t> batch(in.size());
      sign_lms_residuals(in.data(), in.size(), batch.data());
      std::vector<int32_t> batch32(in.size());
      const auto sums = sign_lms_run(in.data(), in.size(), batch32.data());
      auto bit_length = [](int64_t v) {
        const uint64_t u = (static_cast<uint64_t>(v) << 1) ^ static_cast<uint64_t>(v >> 63);
        int b = 0;
        while (b < 64 && (u >> b) != 0) ++b;
        return static_cast<uint64_t>(b);
      };
      uint64_t bits_in = 0, bits_out = 0;
      for (size_t i = 0; i < in.size(); ++i) {
        const int64_t want = in[i] - ref.predict();
        ref.update(in[i], want);
        const int64_t got = in[i] - lms.predict();
        lms.update(in[i], got);
        ASSERT_EQ(got, want) << "sample " << i;
        ASSERT_EQ(batch[i], want) << "sample " << i;
        ASSERT_EQ(batch32[i], want) << "sample " << i;
        bits_in += bit_length(in[i]);
        bits_out += bit_length(want);
      }
      EXPECT_EQ(sums.first, bits_in);
      EXPECT_EQ(sums.second, bits_out);
      allow_avx2(true);
    }
}

TEST(AnalogLpc, GivenCoefficientsWhenKernelPredictsThenExactlyLpcPredict) {
  std::mt19937 rng(5);
  std::uniform_int_distribution<int32_t> q(-(1 << kLpcPrecision) + 1, (1 << kLpcPrecision) - 1);
  std::uniform_int_distribution<int32_t> x(-kMaxSample, kMaxSample);
  std::vector<int32_t> xs(200);
  for (int32_t& v : xs) v = x(rng);
  std::vector<double> xd(kMaxLpcOrder, 0.0);
  for (int32_t v : xs) xd.push_back(v);
  for (int order = 1; order <= kMaxLpcOrder; ++order)
    for (int shift : {0, 7, kMaxLpcShift}) {
      LpcParams p;
      p.order = order;
      p.shift = shift;
      for (int j = 0; j < order; ++j) p.q.push_back(q(rng));
      const LpcKernel k(p);
      for (size_t i = static_cast<size_t>(order); i < xs.size(); ++i)
        ASSERT_EQ(k.predict(xd.data() + kMaxLpcOrder + i), lpc_predict(p, xs.data() + i))
            << "order " << order << " shift " << shift << " sample " << i;
    }
}

TEST(AnalogLpc, GivenBlocksWhenAutocorrelatedThenBitForBitThePlainLoop) {
  std::mt19937 rng(9);
  std::uniform_int_distribution<int32_t> x(-kMaxSample, kMaxSample);
  for (size_t n : {1, 7, 33, 100, 256, 257, 1001, 4096})
    for (int max_lag : {32, 31, 20, 17, 16, 9, 8, 5, 1, 0}) {
      std::vector<int32_t> xs(n);
      for (int32_t& v : xs) v = x(rng);
      // The plain loop: Tukey(0.5) window, then each lag summed in increasing i.
      std::vector<double> w(n);
      const double taper = 0.25 * static_cast<double>(n);
      for (size_t i = 0; i < n; ++i) {
        const double d = std::min<double>(static_cast<double>(i), static_cast<double>(n - 1 - i));
        const double g = d < taper ? 0.5 - 0.5 * std::cos(M_PI * (d + 0.5) / taper) : 1.0;
        w[i] = g * xs[i];
      }
      const std::vector<double> r = autocorrelation(xs.data(), n, max_lag);
      ASSERT_EQ(r.size(), static_cast<size_t>(max_lag) + 1);
      for (int k = 0; k <= max_lag; ++k) {
        double s = 0;
        for (size_t i = static_cast<size_t>(k); i < n; ++i) s += w[i] * w[i - k];
        EXPECT_EQ(r[k], s) << "n " << n << " lag " << k << " of " << max_lag;
      }
    }
}

// The AVX2 kernels (analog_simd.h) against the portable path: the same autocorrelation bits
// (max_lag 32, the AVX2 pass) and the same LPC residuals, on random blocks of edge lengths,
// full-range and small samples, every order. Where the CPU has no AVX2 both runs take the
// portable path (the test then checks only that the switch changes nothing).
TEST(AnalogSimd, GivenRandomBlocksWhenAvx2OnOrOffThenSameBits) {
  std::mt19937 rng(21);
  std::uniform_int_distribution<int32_t> full(-kMaxSample, kMaxSample), small(-40, 40);
  for (size_t n : {1, 3, 4, 5, 8, 255, 256, 257, 259, 1000, 4095, 4096}) {
    for (int range = 0; range < 2; ++range) {
      std::vector<int32_t> x(kMaxLpcOrder + n);
      for (int32_t& v : x) v = range ? full(rng) : small(rng);
      std::vector<double> xd(x.begin(), x.end());
      const int32_t* xs = x.data() + kMaxLpcOrder;
      allow_avx2(false);
      const std::vector<double> plain = autocorrelation(xs, n, 32);
      allow_avx2(true);
      const std::vector<double> fast = autocorrelation(xs, n, 32);
      ASSERT_EQ(plain.size(), fast.size());
      for (size_t k = 0; k < plain.size(); ++k)
        ASSERT_EQ(std::memcmp(&plain[k], &fast[k], sizeof(double)), 0) << n << " lag " << k;
      for (int order = 0; order <= kMaxLpcOrder; ++order) {
        LpcParams p;
        p.order = order;
        p.shift = static_cast<int>(rng() % (kMaxLpcShift + 1));
        for (int j = 0; j < order; ++j)
          p.q.push_back(static_cast<int32_t>(rng() % (2 << kLpcPrecision)) - (1 << kLpcPrecision) +
                        1);
        const LpcKernel lpc(p);
        std::vector<int32_t> r0(n), r1(n);
        allow_avx2(false);
        lpc_residuals(lpc, xs, xd.data() + kMaxLpcOrder, n, r0.data());
        allow_avx2(true);
        lpc_residuals(lpc, xs, xd.data() + kMaxLpcOrder, n, r1.data());
        ASSERT_EQ(r0, r1) << n << " order " << order;
        for (size_t i = 0; i < n; ++i)
          ASSERT_EQ(r0[i], xs[i] - lpc_predict(p, xs + i)) << n << " order " << order << " " << i;
      }
    }
  }
}

}  // namespace
}  // namespace analog
}  // namespace capz
