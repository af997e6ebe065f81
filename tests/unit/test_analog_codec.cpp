// Analog window codec: every representation round-trips bit for bit, representations change
// between windows, corrupt payloads throw kCorrupt, and the real shared takes round-trip.
#include <gtest/gtest.h>

#include <cmath>
#include <cstring>
#include <limits>
#include <random>

#include "analog_window.h"
#include "capz/error.h"
#include "capz/io.h"
#include "coding/analog/analog_codec.h"
#include "coding/analog/analog_entropy.h"
#include "coding/analog/analog_float.h"
#include "coding/analog/analog_lpc.h"
#include "coding/analog/analog_pick.h"
#include "coding/analog/analog_repr.h"
#include "coding/analog/analog_round.h"
#include "coding/analog/analog_simd.h"

namespace capz {
namespace {

using analog::Kind;

uint64_t bits(double v) {
  uint64_t b;
  std::memcpy(&b, &v, 8);
  return b;
}
double nan_with_payload(uint64_t payload, bool negative = false) {
  const uint64_t b = (negative ? uint64_t{1} << 63 : 0) | 0x7FF0000000000000ull | payload;
  double v;
  std::memcpy(&v, &b, 8);
  return v;
}

// Encodes, decodes and compares bit patterns; returns the payload size.
size_t round_trip(const std::vector<double>& rows, int channels, const AnalogHints& hints = {}) {
  return capz_test::window_round_trip(rows, static_cast<size_t>(channels), kAnalogWindowsSince,
                                      hints)
      .size();
}

Kind kind_of(const std::vector<double>& col, const analog::ChannelHint& hint = {}) {
  return analog::choose_representation(col.data(), 1, col.size(), hint).kind;
}

std::vector<double> sine(size_t n, double amp, double step, double offset, uint32_t seed) {
  std::mt19937 rng(seed);
  std::normal_distribution<double> noise(0, 2);
  std::vector<double> v(n);
  for (size_t i = 0; i < n; ++i)
    v[i] = std::round(amp * std::sin(0.01 * i) + noise(rng)) * step + offset;
  return v;
}

TEST(AnalogCodec, GivenInt16CountsWhenCodedThenExactIntKindAndSmall) {
  std::vector<double> v = sine(5000, 3000, 1, 0, 1);
  v[10] = -32768;
  v[11] = 32767;
  v[12] = 0;
  EXPECT_EQ(kind_of(v), Kind::kInt);
  const size_t bytes = round_trip(v, 1);
  EXPECT_LT(bytes, v.size() * 2 / 2);  // well below 16 bits a sample
}

// FORMAT.md 11.8: white noise around a level far from 0 (an offset ADC channel, rank indices)
// is predicted by a constant in a 9.1 window, which decodes exactly and codes smaller than
// 9.0's order 0 or first difference; a 9.0 decoder refuses the order code (corrupt).
TEST(AnalogCodec, GivenNoiseAroundALevelWhen91ThenConstantPredictorSmallerAndExact) {
  std::mt19937 rng(7);
  std::uniform_int_distribution<int> noise(-40, 40);
  const size_t n = 6000;  // two LPC blocks
  std::vector<double> v(n);
  for (size_t i = 0; i < n; ++i) v[i] = 9000 + noise(rng);
  ASSERT_EQ(kind_of(v), Kind::kInt);
  const std::vector<uint8_t> w90 = encode_analog_window(v.data(), n, 1, {}, 0, kAnalogFloat9Since);
  const std::vector<uint8_t> w91 =
      encode_analog_window(v.data(), n, 1, {}, 0, kAnalogConstantSince);
  EXPECT_LT(w91.size() * 100, w90.size() * 97) << w91.size() << " against " << w90.size();
  std::vector<double> back(n);
  decode_analog_window(w91.data(), w91.size(), n, 1, back.data(), "9.1 window", 0,
                       kAnalogConstantSince);
  for (size_t i = 0; i < n; ++i) ASSERT_EQ(bits(back[i]), bits(v[i])) << i;
  try {
    decode_analog_window(w91.data(), w91.size(), n, 1, back.data(), "as 9.0", 0,
                         kAnalogFloat9Since);
    ADD_FAILURE() << "a 9.1 constant predictor decoded as 9.0";
  } catch (const Error& e) {
    EXPECT_EQ(e.code(), ErrorCode::kCorrupt);
    EXPECT_NE(std::string(e.what()).find("LPC order above 32"), std::string::npos) << e.what();
  }
  // A 9.0 window decodes the same in 9.1 (the order code is new, nothing else changes).
  decode_analog_window(w90.data(), w90.size(), n, 1, back.data(), "9.0 window", 0,
                       kAnalogConstantSince);
  for (size_t i = 0; i < n; ++i) ASSERT_EQ(bits(back[i]), bits(v[i])) << i;
}

// A 9.1 window of one integer channel of n rows whose entropy block is replaced by one that
// codes no cascade, no reference and a constant predictor c, then n zero residuals: decoded.
void decode_with_constant(int64_t c, size_t n, std::vector<double>* back) {
  std::vector<double> v(n, 1.0);
  for (size_t i = 0; i < n; ++i) v[i] = 9000 + static_cast<double>(i % 7);
  const std::vector<uint8_t> w = encode_analog_window(v.data(), n, 1, {}, 0, kAnalogConstantSince);
  size_t at = 1, head = 0;
  for (int shift = 0;; shift += 7) {  // the header's size, a varint
    head |= static_cast<size_t>(w[at] & 0x7F) << shift;
    if (!(w[at++] & 0x80)) break;
  }
  std::vector<uint8_t> crafted(w.begin(), w.begin() + static_cast<long>(at + head));
  IntEncoder enc(analog::kAnalogContexts);
  IntEncoder::Cursor cur = enc.cursor();
  cur.put(0, analog::kParamContext);  // no cascade
  cur.put(0, analog::kParamContext);  // no reference
  cur.put(analog::kLpcConstantOrder, analog::kParamContext);
  cur.put_signed(static_cast<int32_t>(c), analog::kCoefContext);
  analog::Magnitude mag;
  for (size_t i = 0; i < n; ++i) analog::put_residual(&cur, &mag, 0);
  enc.commit(cur);
  const std::vector<uint8_t> block = enc.finish();
  crafted.insert(crafted.end(), block.begin(), block.end());
  back->assign(n, 0.0);
  decode_analog_window(crafted.data(), crafted.size(), n, 1, back->data(), "crafted window", 0,
                       kAnalogConstantSince);
}

TEST(AnalogCodec, GivenConstantPredictorsWhenDecodedThenTheConstantOrCorruptBeyond2To28) {
  std::vector<double> back;
  decode_with_constant(-(int64_t{1} << 28), 100, &back);
  for (double x : back) ASSERT_EQ(x, -268435456.0);
  decode_with_constant(123, 100, &back);
  for (double x : back) ASSERT_EQ(x, 123.0);
  for (const int64_t c : {(int64_t{1} << 28) + 1, -(int64_t{1} << 28) - 1}) {
    try {
      decode_with_constant(c, 100, &back);
      ADD_FAILURE() << "constant " << c << " decoded";
    } catch (const Error& e) {
      EXPECT_EQ(e.code(), ErrorCode::kCorrupt);
      EXPECT_NE(std::string(e.what()).find("constant prediction out of range"), std::string::npos)
          << e.what();
      EXPECT_NE(std::string(e.what()).find("crafted window"), std::string::npos) << e.what();
    }
  }
}

TEST(AnalogCodec, GivenUnsignedCountsWhenCodedThenExact) {
  std::vector<double> v = sine(3000, 30000, 1, 32768, 2);
  v[0] = 0;
  v[1] = 65535;
  EXPECT_EQ(kind_of(v), Kind::kInt);
  round_trip(v, 1);
}

// EMG counts stored times 20 (btkdata ADemo1, Codamotion 1997): integers whose distances share
// a step. They are coded as kScaled with that step and the offset below it, exactly, and in
// fewer bytes than the same integers with an odd one among them (step 1, kInt).
TEST(AnalogCodec, GivenIntegersSharingAStepWhenCodedThenScaledByTheStepExactAndSmaller) {
  std::vector<double> v = sine(4000, 300, 20, -7, 4);  // -7 + 20 k: negative and positive
  EXPECT_EQ(kind_of(v), Kind::kScaled);
  const analog::ChannelRepr r = analog::choose_representation(v.data(), 1, v.size(), {});
  EXPECT_EQ(r.step, 20.0);
  EXPECT_EQ(r.offset, 13.0);  // -7 mod 20
  EXPECT_TRUE(r.exc_index.empty());
  double step = 0, offset = 0;
  ASSERT_TRUE(analog::sample_lattice(v.data(), 1, v.size(), {}, &step, &offset));
  EXPECT_EQ(step, 20.0);
  EXPECT_EQ(offset, 13.0);
  const size_t scaled = round_trip(v, 1);
  std::vector<double> odd = v;
  odd[2000] += 1;  // the common step is now 1
  EXPECT_EQ(kind_of(odd), Kind::kInt);
  const size_t plain = round_trip(odd, 1);
  EXPECT_LT(static_cast<double>(scaled), 0.8 * static_cast<double>(plain));
  // Large counts (beyond float32's exact integers) with a step, and a step of 2^20.
  std::vector<double> big = sine(3000, 100, 6, (1 << 26) + 1, 5), wide(500);
  for (size_t i = 0; i < wide.size(); ++i) wide[i] = static_cast<double>(i % 7) * (1 << 20) - 3;
  round_trip(big, 1);
  round_trip(wide, 1);
}

TEST(AnalogCodec, GivenScaledFloat32CountsWhenCodedThenScaledKind) {
  const double step = 0.0048828125 * 1.1;  // not a power of two
  std::vector<double> v = sine(4000, 200, step, 0.37, 3);
  for (double& x : v) x = static_cast<float>(x);
  EXPECT_EQ(kind_of(v), Kind::kScaled);
  const size_t bytes = round_trip(v, 1);
  EXPECT_LT(bytes, v.size());  // a float32 channel in under 8 bits a sample
}

// Averages of q counts (MotionMonitor writes k / 49 as float32) over a range wide enough that
// float32 rounding makes adjacent values closer than the step, and with one sum that came out
// as 1e-12 instead of 0: the step found is exactly 1 / 49, with only the outliers as exceptions.
TEST(AnalogCodec, GivenAveragedCountsOverAWideRangeThenScaledKindWithTheExactStep) {
  std::vector<double> v = sine(6000, 1000, 1, 0, 7);
  for (size_t i = 3000; i < 3300; ++i) v[i] += 60000;  // a burst far out: sparse, large k
  for (double& x : v) x = static_cast<float>(x / 49.0);
  v[100] = static_cast<float>(1.3642420526593924e-12);
  v[200] = static_cast<float>(-2.7e-12);
  const analog::ChannelRepr r = analog::choose_representation(v.data(), 1, v.size(), {});
  ASSERT_EQ(r.kind, Kind::kScaled);
  EXPECT_EQ(r.step, 1.0 / 49.0);
  EXPECT_LE(r.exc_index.size(), 2u);
  const size_t bytes = round_trip(v, 1);
  EXPECT_LT(bytes, v.size() * 2);  // the counts' noise, not the float32 bits
}

TEST(AnalogCodec, GivenScaleHintWhenDataAloneCannotFindTheStepThenScaledKind) {
  // Only even multiples of the step occur: the data suggest twice the step, which also works;
  // the hint must not make it worse.
  std::vector<double> v = sine(2000, 100, 0.25, 0, 4);
  for (double& x : v) x = static_cast<float>(x * 2 + 0.1);
  analog::ChannelHint hint;
  hint.scale = 0.5;
  EXPECT_EQ(kind_of(v, hint), Kind::kScaled);
  AnalogHints h;
  h.channel.push_back(hint);
  round_trip(v, 1, h);
}

TEST(AnalogCodec, GivenFewDistinctValuesWhenCodedThenRankKind) {
  std::mt19937 rng(5);
  const double table[5] = {-1.0 / 3, 0.1, M_PI, 1e10, 7.5e-300};
  std::vector<double> v(3000);
  for (double& x : v) x = table[rng() % 5];
  EXPECT_EQ(kind_of(v), Kind::kRank);
  round_trip(v, 1);
}

TEST(AnalogCodec, GivenArbitraryFloatsWhenCodedThenFloatKindsExact) {
  std::mt19937 rng(6);
  std::uniform_real_distribution<double> u(-1000, 1000);
  std::vector<double> f32(2000), f64(2000);
  for (size_t i = 0; i < f32.size(); ++i) {
    f64[i] = std::sin(i * 0.003) * 50 + u(rng) * 1e-6;
    f32[i] = static_cast<float>(f64[i] * 3.3 + 1e-3 * u(rng));
  }
  f64[5] = std::numeric_limits<double>::denorm_min();
  f64[6] = -std::numeric_limits<double>::max();
  f64[7] = -0.0;
  f32[8] = std::numeric_limits<float>::denorm_min();
  f32[9] = -0.0;
  f32[10] = std::numeric_limits<float>::max();
  EXPECT_EQ(kind_of(f32), Kind::kFloat32);
  EXPECT_EQ(kind_of(f64), Kind::kFloat64);
  std::vector<double> rows;
  for (size_t i = 0; i < f32.size(); ++i) {
    rows.push_back(f32[i]);
    rows.push_back(f64[i]);
  }
  round_trip(rows, 2);
}

TEST(AnalogCodec, GivenNonFiniteSamplesWhenCodedThenGapListKeepsTheirBits) {
  std::vector<double> v = sine(3000, 400, 0.01, 0, 7);
  for (double& x : v) x = static_cast<float>(x);
  for (size_t i = 100; i < 400; ++i) v[i] = std::numeric_limits<double>::quiet_NaN();
  v[0] = nan_with_payload(0x12345, true);
  v[999] = std::numeric_limits<double>::infinity();
  v[1000] = -std::numeric_limits<double>::infinity();
  v[2999] = nan_with_payload(1);  // signalling NaN pattern
  const analog::ChannelRepr r = analog::choose_representation(v.data(), 1, v.size(), {});
  EXPECT_EQ(r.kind, Kind::kScaled);  // the finite samples keep their representation
  EXPECT_EQ(r.gap_index.size(), 304u);
  const size_t bytes = round_trip(v, 1);
  EXPECT_LT(bytes, v.size());
}

TEST(AnalogCodec, GivenAllNaNOrConstantChannelsWhenCodedThenNearlyFree) {
  std::vector<double> rows;
  for (int i = 0; i < 5000; ++i) {
    rows.push_back(std::numeric_limits<double>::quiet_NaN());
    rows.push_back(-0.0);
    rows.push_back(2.5);
  }
  EXPECT_LT(round_trip(rows, 3), 64u);
}

TEST(AnalogCodec, GivenChannelsChangingRepresentationBetweenWindowsThenEachWindowExact) {
  std::vector<double> a = sine(1500, 1000, 1, 0, 8);    // integers
  std::vector<double> b = sine(1500, 1000, 0.1, 0, 9);  // scaled (double, not float)
  std::vector<double> c(1500, 4.0);                     // constant
  std::vector<double> d(1500);                          // arbitrary float64
  for (size_t i = 0; i < d.size(); ++i) d[i] = std::exp(std::sin(i * 0.01));
  const std::vector<double>* order[4][2] = {{&a, &b}, {&b, &c}, {&c, &d}, {&d, &a}};
  for (const auto& w : order) {
    std::vector<double> rows;
    for (size_t i = 0; i < 1500; ++i) {
      rows.push_back((*w[0])[i]);
      rows.push_back((*w[1])[i]);
    }
    round_trip(rows, 2);
  }
}

TEST(AnalogCodec, GivenCorrelatedChannelsWhenCodedTogetherThenSmallerThanApart) {
  // Two force channels seeing the same load with independent noise: the second channel's LPC
  // residual is mostly the first one's (inter-channel stage).
  std::mt19937 rng(13);
  std::normal_distribution<double> load(0, 300), noise(0, 3);
  std::vector<double> a(4000), b(4000), rows;
  double l = 0;
  for (size_t i = 0; i < a.size(); ++i) {
    l = 0.5 * l + load(rng);
    a[i] = std::round(l + noise(rng));
    b[i] = std::round(-0.7 * l + noise(rng));
    rows.push_back(a[i]);
    rows.push_back(b[i]);
  }
  const size_t together = round_trip(rows, 2);
  const size_t apart = round_trip(a, 1) + round_trip(b, 1);
  EXPECT_LT(together, apart * 8 / 10);
}

TEST(AnalogCodec, GivenEmptyAndTinyWindowsThenExact) {
  round_trip({}, 3);
  round_trip({1.5}, 1);
  round_trip({1, 2, 3, 4, 5, 6}, 6);
  round_trip({1, 2, 3, 4, 5, 7}, 1);
}

TEST(AnalogCodec, GivenCorruptPayloadsThenKCorruptNeverCrash) {
  std::vector<double> rows;
  std::vector<double> a = sine(700, 1000, 1, 0, 10), b = sine(700, 100, 0.013, 0, 11);
  for (size_t i = 0; i < 700; ++i) {
    rows.push_back(a[i]);
    rows.push_back(static_cast<float>(b[i]));
    rows.push_back(i % 3 ? 1.0 / 3 : std::nan(""));
    rows.push_back(std::sin(i * 0.1));
  }
  const std::vector<uint8_t> p = encode_analog_window(rows.data(), 700, 4, {});
  std::vector<double> out(rows.size());
  std::mt19937 rng(12);
  int corrupt = 0;
  for (int trial = 0; trial < 3000; ++trial) {
    std::vector<uint8_t> q = p;
    if (trial < static_cast<int>(p.size())) {
      q.resize(trial);  // every truncation
    } else {
      for (int k = 0; k < 1 + trial % 4; ++k)
        q[rng() % q.size()] ^= static_cast<uint8_t>(1 + rng() % 255);
    }
    try {
      decode_analog_window(q.data(), q.size(), 700, 4, out.data(), "corrupt window");
    } catch (const Error& e) {
      EXPECT_EQ(e.code(), ErrorCode::kCorrupt);
      EXPECT_NE(std::string(e.what()).find("corrupt window"), std::string::npos) << e.what();
      ++corrupt;
    }
  }
  EXPECT_GT(corrupt, 1000);
}

TEST(AnalogCodec, GivenSharedTakesWhenCodedThenExactAndSmallerThanRaw) {
  const std::string dir = std::string(CAPZ_SHARED_DATA) + "/c3d/";
  const char* files[] = {"btkdata/others/1123x01EMG.c3d", "c3dorg/sample_30/emgwl.c3d",
                         "btkdata/PiG/PiG_Motion3_FF.c3d", "c3dorg/sample_09/PlugInC3D.c3d"};
  int seen = 0;
  for (const char* f : files) {
    Take t;
    try {
      t = read_take(dir + f);
    } catch (const Error&) {
      continue;
    }
    ++seen;
    const size_t bytes = round_trip(t.analog.values, t.analog.channels);
    EXPECT_LT(bytes, t.analog.values.size() * 4 / 2) << f;
  }
  if (seen == 0) GTEST_SKIP() << "shared data not found under " << dir;
}

// The float predictors' costs as analog_float.h defines them, one sample at a time in integers.
void plain_predictor_costs(const std::vector<double>& x, bool f32, uint64_t cost[2]) {
  cost[0] = cost[1] = 0;
  for (size_t i = 0; i < x.size(); ++i) {
    const double a = i > 0 ? x[i - 1] : 0, b = i > 1 ? x[i - 2] : 0;
    for (int k = 0; k < 2; ++k) {
      double p = k == 0 ? a : a + (a - b);
      if (f32) p = analog::round_to_float32(p);
      const int64_t d = f32 ? static_cast<int64_t>(analog::ordered_f32(x[i])) -
                                  static_cast<int64_t>(analog::ordered_f32(p))
                            : static_cast<int64_t>(analog::ordered_bits(bits(x[i])) -
                                                   analog::ordered_bits(bits(p)));
      const uint64_t u = (static_cast<uint64_t>(d) << 1) ^ static_cast<uint64_t>(d >> 63);
      cost[k] += u == 0 ? 0 : 64 - __builtin_clzll(u);
    }
  }
}

TEST(AnalogFloat, GivenFloat32SamplesWhenPredictorCostsThenThoseOfThePlainLoop) {
  const float kMax = std::numeric_limits<float>::max();
  const float kTiny = std::numeric_limits<float>::denorm_min();
  std::mt19937 rng(17);
  std::normal_distribution<float> walk(0, 3);
  std::uniform_int_distribution<uint32_t> any(0, 0xFFFFFFFFu);
  std::vector<std::vector<double>> seqs;
  std::vector<double> smooth, wild, edges;
  float v = 0;
  for (int i = 0; i < 5001; ++i) {
    v += walk(rng);
    smooth.push_back(v);
    uint32_t b = any(rng);
    if ((b & 0x7F800000u) == 0x7F800000u) b &= ~0x00800000u;  // finite
    float f;
    std::memcpy(&f, &b, 4);
    wild.push_back(f);
  }
  // Near the float range (predictions beyond it are clamped), zeros of both signs, subnormals.
  for (double e : {0.0, -0.0, 0.0, static_cast<double>(kMax), static_cast<double>(kMax),
                   static_cast<double>(-kMax), static_cast<double>(kMax), 0.0, -0.0, -0.0,
                   static_cast<double>(kTiny), static_cast<double>(-kTiny), 1.0, -1.0,
                   static_cast<double>(-kMax), static_cast<double>(-kMax), 3.0})
    edges.push_back(e);
  seqs = {smooth, wild, edges, {}, {1.5}, {1.5, -2.25}, {1.5, -2.25, 7.0}};
  for (const std::vector<double>& x : seqs)
    for (bool f32 : {true, false}) {
      uint64_t want[2], got[2];
      plain_predictor_costs(x, f32, want);
      analog::float_predictor_costs(x, f32, got);
      EXPECT_EQ(got[0], want[0]) << x.size() << " samples, f32 " << f32;
      EXPECT_EQ(got[1], want[1]) << x.size() << " samples, f32 " << f32;
    }
}

// The trials' order follows the estimate, but the pick is always the first of the smallest, and
// a trial only stops (SIZE_MAX) when its size is at least the bound it was given.
TEST(AnalogPick, GivenAnyEstimateWhenPickingThenTheFirstSmallestAndTrialsStopOnlyWhenLosing) {
  std::mt19937 rng(5);
  for (int round = 0; round < 2000; ++round) {
    const size_t n = 2 + rng() % 4;
    std::vector<size_t> size(n);
    for (size_t& v : size) v = 10 + rng() % 6;  // ties are common
    std::vector<double> estimate(n);
    for (size_t k = 0; k < n; ++k)
      estimate[k] = round % 3 == 0 ? static_cast<double>(size[k]) : static_cast<double>(rng() % 8);
    size_t want = 0;
    for (size_t k = 1; k < n; ++k)
      if (size[k] < size[want]) want = k;
    std::vector<size_t> order;
    const size_t got = analog::pick_smallest(estimate, [&](size_t k, size_t bound) {
      order.push_back(k);
      // A coder may stop anywhere once its size reaches the bound; here it does when told to.
      return size[k] >= bound && rng() % 2 ? SIZE_MAX : size[k];
    });
    EXPECT_EQ(got, want) << "round " << round;
    ASSERT_EQ(order.size(), n);
    for (size_t j = 1; j < n; ++j)
      EXPECT_LE(estimate[order[j - 1]], estimate[order[j]]) << "round " << round;
  }
}

// With the sizes themselves as the estimate, the first trial is the smallest and every later
// one is bounded by it: none needs to run to its end unless it ties.
TEST(AnalogPick, GivenExactEstimatesWhenPickingThenLaterTrialsAreBoundedByTheBest) {
  const std::vector<size_t> size = {40, 25, 31, 25};
  std::vector<double> estimate(size.begin(), size.end());
  std::vector<std::pair<size_t, size_t>> calls;
  const size_t got = analog::pick_smallest(estimate, [&](size_t k, size_t bound) {
    calls.push_back({k, bound});
    return size[k] >= bound ? SIZE_MAX : size[k];
  });
  EXPECT_EQ(got, 1u);
  ASSERT_EQ(calls.size(), 4u);
  EXPECT_EQ(calls[0], std::make_pair(size_t{1}, SIZE_MAX));
  EXPECT_EQ(calls[1], std::make_pair(size_t{3}, size_t{25}));  // after the pick: must beat it
  EXPECT_EQ(calls[2], std::make_pair(size_t{2}, size_t{25}));
  EXPECT_EQ(calls[3], std::make_pair(size_t{0}, size_t{26}));  // before the pick: may tie
}

// The quotient rounder is round_half_away of the divided quotient bit for bit (zero signs
// too), on quotients near half-integers (where the product rounds differently), near integers,
// random ones, large ones, and steps of every magnitude.
TEST(AnalogRound, GivenQuotientsWhenRoundedWithoutDividingThenTheDividedResultBitForBit) {
  std::mt19937_64 rng(3);
  std::uniform_real_distribution<double> unit(-1, 1);
  const double steps[] = {1.0 / 3, 1.0 / 7,  0.1,       1e-3, 3.0517578125e-05, 2.5, 1e-300,
                          1e300,   4.9e-324, 0.0078125, 1e-9, 123456.789};
  // pair() on (the previous d, d): when it answers, both lanes bit for bit; it must answer for
  // a good part of the pairs.
  double prev = 0;
  size_t pairs = 0, answered = 0;
  auto check = [&](double s, double d) {
    const analog::QuotientRounder q(s);
    const double want = analog::round_half_away(d / s), got = q(d);
    ASSERT_EQ(bits(got), bits(want)) << "d " << d << " s " << s;
    analog::QuotientRounder::Lanes k;
    ++pairs;
    if (q.pair(analog::QuotientRounder::Lanes{prev, d}, &k)) {
      ++answered;
      ASSERT_EQ(bits(k[0]), bits(analog::round_half_away(prev / s))) << "d " << prev << " s " << s;
      ASSERT_EQ(bits(k[1]), bits(want)) << "d " << d << " s " << s;
    }
    prev = d;
  };
  for (double s : steps) {
    for (int i = 0; i < 20000; ++i) {
      const double k = std::round(unit(rng) * (i % 2 ? 1e3 : 1e8));
      const double h = k + 0.5, u = std::ldexp(unit(rng), -static_cast<int>(rng() % 60));
      check(s, h * s);        // at a half-integer
      check(s, (h + u) * s);  // a hair either side
      check(s, std::nextafter(h * s, 0.0));
      check(s, std::nextafter(h * s, 1e308));
      check(s, (k + u) * s);          // near an integer
      check(s, unit(rng) * s * 3);    // small, zero signs
      check(s, unit(rng) * s * 2e7);  // around 2^23 and 2^24
    }
    check(s, 0.0);
    check(s, -0.0);
    check(s, 1e308);
    check(s, std::numeric_limits<double>::infinity());
    check(s, std::nan(""));
  }
  EXPECT_GT(answered, pairs / 10);  // most inputs here sit near half-integers on purpose
}

// The scaled fits (find_scaled, fit_scaled) run four samples a step with AVX2 where the CPU has
// it: the candidates, their steps, offsets, exceptions and k are those of the two-lane path, bit
// for bit, on float32 and float64 lattices with exceptions, averaged counts, k near 2^23
// (quotients that need the division) and odd lengths.
TEST(AnalogSimd, GivenScaledChannelsWhenFittedWithAvx2OnOrOffThenTheSameCandidates) {
  std::mt19937 rng(21);
  std::uniform_real_distribution<double> unit(-1, 1);
  std::vector<std::vector<double>> cols;
  for (size_t n : {size_t{7}, size_t{1001}, size_t{4096}}) {
    std::vector<double> f32(n), f64(n), avg(n), big(n), walk(n);
    double w = 0;
    for (size_t i = 0; i < n; ++i) {
      const double k = std::round(unit(rng) * 3000);
      f32[i] = static_cast<float>(k * 0.0030517578125 - 1.25);
      f64[i] = i % 37 == 5 ? unit(rng) : k * 0.1 + 0.3;  // exceptions every 37th sample
      avg[i] = static_cast<float>(k / 7.0);
      big[i] = std::round(unit(rng) * 8388600) * 1e-3;
      w += std::round(unit(rng) * 4);
      walk[i] = static_cast<float>(w * (20.0 / 65535.0));
    }
    for (auto* c : {&f32, &f64, &avg, &big, &walk}) cols.push_back(*c);
  }
  auto same = [](const analog::ChannelRepr& a, const analog::ChannelRepr& b) {
    return a.kind == b.kind && bits(a.step) == bits(b.step) && bits(a.offset) == bits(b.offset) &&
           a.round_f32 == b.round_f32 && a.exc_index == b.exc_index && a.exc_delta == b.exc_delta &&
           a.ints == b.ints;
  };
  size_t scaled = 0;
  for (const std::vector<double>& c : cols) {
    analog::allow_avx2(false);
    const auto plain = analog::candidate_representations(c.data(), 1, c.size(), {});
    analog::allow_avx2(true);
    const auto fast = analog::candidate_representations(c.data(), 1, c.size(), {});
    ASSERT_EQ(plain.size(), fast.size());
    for (size_t k = 0; k < plain.size(); ++k) {
      EXPECT_TRUE(same(plain[k], fast[k])) << "column of " << c.size() << ", candidate " << k;
      scaled += plain[k].kind == Kind::kScaled;
    }
  }
  EXPECT_GE(scaled, 6u);  // the lattices were found
}

// With a margin, candidates estimated far above the smallest estimate are never tried, and a
// lone survivor is picked without a trial; among those tried, the first smallest still wins.
TEST(AnalogPick, GivenAMarginWhenEstimatesAreFarApartThenOnlyTheCloseOnesAreTried) {
  const std::vector<size_t> size = {30, 50, 29, 100};
  std::vector<size_t> tried;
  auto trial = [&](size_t k, size_t) {
    tried.push_back(k);
    return size[k];
  };
  EXPECT_EQ(analog::pick_smallest({30, 50, 31, 100}, trial, 1.2), 2u);  // 29 < 30: measured
  EXPECT_EQ(tried, (std::vector<size_t>{0, 2}));
  tried.clear();
  EXPECT_EQ(analog::pick_smallest({30, 50, 40, 100}, trial, 1.2), 0u);  // 2 is out: no trial
  EXPECT_TRUE(tried.empty());
  EXPECT_EQ(analog::pick_smallest({30, 50, 40, 100}, trial, 2.0), 2u);
  EXPECT_EQ(tried, (std::vector<size_t>{0, 2, 1}));
}

}  // namespace
}  // namespace capz
