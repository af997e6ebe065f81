// Interpolated analog samples (docs/FORMAT.md 11.4): channels whose samples between anchors are
// the linear interpolation of them round-trip bit for bit with an interpolation field, which is
// written only in 9.x windows and only where it codes smaller; exceptions, the tail, NaN
// anchors, float32 and float64 channels and references between channels follow the format;
// damaged fields throw kCorrupt; Codamotion's take (every second sample the mean of its
// neighbours) goes C3D -> capz 9.0 -> C3D exactly and smaller.
#include <gtest/gtest.h>

#include <algorithm>
#include <cmath>
#include <cstring>
#include <limits>
#include <random>

#include "analog_window.h"
#include "capz/codec.h"
#include "capz/error.h"
#include "capz/io.h"
#include "capz/version.h"
#include "coding/analog/analog_codec.h"
#include "coding/analog/analog_interp.h"
#include "coding/analog/analog_repr.h"
#include "coding/bytes.h"
#include "test_util.h"

namespace capz {
namespace {

using analog::bits_of;
using analog::Interp;

// n samples of a noisy walk on a 0.5 lattice (counts as Codamotion's), then every sample
// between anchors (every P-th) made their interpolation, f32 rounding when asked.
std::vector<double> interpolated(size_t n, unsigned P, bool f32, uint32_t seed) {
  std::mt19937 rng(seed);
  std::normal_distribution<double> step(0, 30);
  std::vector<double> x(n);
  double v = 100;
  for (size_t i = 0; i < n; i += P) {
    v += std::round(step(rng)) * 0.5;
    x[i] = f32 ? static_cast<double>(static_cast<float>(v * 0.37)) : v * 0.37;
  }
  const size_t L = (n - 1) / P * P;
  for (size_t a = 0; a < L; a += P)
    for (unsigned j = 1; j < P; ++j) x[a + j] = analog::interpolate(x[a], x[a + P], j, P, f32);
  for (size_t i = L + 1; i < n; ++i) x[i] = x[L] + static_cast<double>(i - L);  // the tail
  return x;
}

// Encodes a window of these columns (9.0, or 8.0 when !v9), decodes it and compares bits.
std::vector<uint8_t> round_trip(const std::vector<std::vector<double>>& cols, bool v9 = true) {
  return capz_test::window_round_trip(capz_test::rows_of(cols), cols.size(),
                                      v9 ? kAnalogFloat9Since : kAnalogLatticeSince);
}

// Each channel's interpolation field as the payload's header gives it.
std::vector<Interp> fields(const std::vector<uint8_t>& p, size_t n, size_t C) {
  std::vector<Interp> out;
  for (const capz_test::ChannelHeader& h : capz_test::channel_headers(p, n, C))
    out.push_back(h.kept.interp);
  return out;
}

TEST(AnalogInterp, GivenPeriodsTwoToFourWhenCodedThenFieldWrittenExactAndSmaller) {
  for (unsigned P = 2; P <= 4; ++P)
    for (bool f32 : {true, false}) {
      SCOPED_TRACE("P " + std::to_string(P) + (f32 ? " float32" : " float64"));
      const std::vector<double> x = interpolated(4001, P, f32, P);
      Interp found;
      ASSERT_TRUE(analog::find_interpolation(x.data(), 1, x.size(), &found));
      EXPECT_EQ(found.period, P);
      EXPECT_EQ(found.f32, f32);
      EXPECT_TRUE(found.exceptions.empty());
      const std::vector<uint8_t> p9 = round_trip({x}, true), p8 = round_trip({x}, false);
      EXPECT_EQ(fields(p9, x.size(), 1)[0].period, P);
      EXPECT_LT(static_cast<double>(p9.size()), 0.85 * static_cast<double>(p8.size()));
    }
}

// The exceptions' budget (1/16 of the interpolable samples) decides from the first sample on:
// a channel with that many exceptions, all at its start, is still found (with each of them),
// one more and it is not, for float32 and float64 channels alike.
TEST(AnalogInterp, GivenExceptionsAtTheStartUpToTheBudgetThenFoundOneMoreThenNot) {
  for (bool f32 : {false, true}) {
    const size_t n = 1000;  // period 2: 499 interpolable samples, a budget of 31
    const std::vector<double> x = interpolated(n, 2, f32, 5);
    for (size_t extra : {size_t{0}, size_t{1}}) {
      std::vector<double> y = x;
      for (size_t e = 0; e < 31 + extra; ++e) y[2 * e + 1] += 0.25;
      Interp in;
      const bool found = analog::find_interpolation(y.data(), 1, n, &in);
      EXPECT_EQ(found, extra == 0) << f32;
      if (!found) continue;
      EXPECT_EQ(in.period, 2);
      EXPECT_EQ(in.f32, f32);
      EXPECT_EQ(in.exceptions.size(), 31u);
    }
  }
}

TEST(AnalogInterp, GivenExceptionsNaNAnchorsAndATailThenExactWithThoseCoded) {
  std::vector<double> x = interpolated(3003, 2, true, 7);
  x[101] += 1;                                        // an exception
  x[500] = std::numeric_limits<double>::quiet_NaN();  // a NaN anchor: 499 and 501 exceptions
  x[2000] = std::numeric_limits<double>::infinity();  // an infinite anchor
  const std::vector<uint8_t> p = round_trip({x});
  const Interp f = fields(p, x.size(), 1)[0];
  ASSERT_EQ(f.period, 2);
  for (uint32_t i : {101u, 499u, 501u})
    EXPECT_TRUE(std::find(f.exceptions.begin(), f.exceptions.end(), i) != f.exceptions.end()) << i;
  EXPECT_EQ(analog::interp_kept_count(x.size(), f), 1502 + f.exceptions.size());
}

TEST(AnalogInterp, GivenChannelsNotInterpolatedThenNoFieldAndSameBytesAsBefore9) {
  std::mt19937 rng(3);
  std::normal_distribution<double> noise(0, 100);
  std::vector<double> x(3000);
  for (double& v : x) v = std::round(noise(rng));
  Interp f;
  EXPECT_FALSE(analog::find_interpolation(x.data(), 1, x.size(), &f));
  EXPECT_EQ(round_trip({x}, true), round_trip({x}, false));
}

TEST(AnalogInterp, GivenCorrelatedInterpolatedChannelsThenReferencesKeptAndExact) {
  const std::vector<double> a = interpolated(4000, 2, false, 11);
  std::vector<double> b(a.size()), c = interpolated(4000, 3, true, 12);
  for (size_t i = 0; i < a.size(); ++i) b[i] = a[i] * 2 + 0.5;  // same layout, correlated
  const std::vector<uint8_t> p = round_trip({a, b, c});
  const std::vector<Interp> f = fields(p, a.size(), 3);
  EXPECT_EQ(f[0].period, 2);
  EXPECT_EQ(f[1].period, 2);
  EXPECT_EQ(f[2].period, 3);
  EXPECT_LT(p.size(), round_trip({a}).size() + round_trip({b}).size() + round_trip({c}).size());
}

TEST(AnalogInterp, GivenTinyWindowsThenExact) {
  for (size_t n : {1, 2, 3, 5, 17, 33}) {
    const std::vector<double> x = interpolated(n, 2, true, static_cast<uint32_t>(n));
    round_trip({x});
  }
}

// A window of one interpolated channel with its header's first bytes, for the damage tests.
struct Coded {
  std::vector<double> x = interpolated(2001, 2, true, 5);
  std::vector<uint8_t> p = round_trip({x});
};

void expect_corrupt(const std::vector<uint8_t>& p, size_t n, bool v9, const std::string& why) {
  capz_test::expect_window_corrupt(p, n, 1, v9 ? kAnalogFloat9Since : kAnalogLatticeSince, why);
}

TEST(AnalogInterp, GivenDamagedFieldsThenCorruptNeverCrash) {
  const Coded c;
  const size_t k = capz_test::first_kind_at(c.p), n = c.x.size();
  ASSERT_TRUE(c.p[k] & 64);
  ASSERT_EQ(c.p[k + 1], 0x82);  // P = 2, float32
  expect_corrupt(c.p, n, false, "bit 6 before 9.0");
  std::vector<uint8_t> q = c.p;
  q[k] |= 32;
  expect_corrupt(q, n, true, "bits 5 and 6");
  q = c.p;
  q[k] = static_cast<uint8_t>((q[k] & ~7) | 0);
  expect_corrupt(q, n, true, "bit 6 with kind 0");
  for (uint8_t bad : {0x80, 0x81, 0x92, 0xC2}) {
    q = c.p;
    q[k + 1] = bad;
    expect_corrupt(q, n, true, "q " + std::to_string(bad));
  }
  // An exception at an anchor (index 0: runs 1, skip 0, length 1), where none was.
  ASSERT_EQ(c.p[k + 2], 0);  // no exceptions
  q = c.p;
  q[k + 2] = 1;
  q.insert(q.begin() + static_cast<long>(k) + 3, {0, 0});
  expect_corrupt(q, n, true, "exception at an anchor");
  // Every payload byte flipped: kCorrupt or the same length of samples, never a crash.
  capz_test::expect_flips_corrupt_or_decoded(c.p, n, 1, kAnalogFloat9Since);
}

TEST(AnalogInterp, GivenANaNInterpolationNotListedThenCorrupt) {
  // Hand-made: kind 4 (float32) with an interpolation field of no exceptions over samples whose
  // anchor 2 is NaN: the decoder computes NaN for samples 1 and 3 and must refuse.
  Interp in;
  in.period = 2;
  in.f32 = true;
  const double nan = std::numeric_limits<double>::quiet_NaN();
  const std::vector<double> kept = {1.0, nan, 3.0};  // anchors 0, 2, 4
  std::vector<double> col(5);
  EXPECT_THROW(analog::expand_interp(kept.data(), 5, in, col.data(), 1, "nan"), Error);
  in.exceptions = {1, 3};
  const std::vector<double> with = {1.0, 7.0, nan, 8.0, 3.0};
  analog::expand_interp(with.data(), 5, in, col.data(), 1, "nan");
  EXPECT_EQ(col[1], 7.0);
  EXPECT_EQ(col[3], 8.0);
  EXPECT_TRUE(std::isnan(col[2]));
}

TEST(AnalogInterp, GivenCodamotionTakeWhenRoundTrippedThen9AndExactAndSmaller) {
  const std::string path = capz_test::shared_data_or_skip(
      "c3d/c3dorg/sample_00/Codamotion/codamotion_gaitwands_20150204.c3d");
  if (path.empty()) return;
  const Take t = read_take(path);
  const size_t n = t.analog.values.size() / static_cast<size_t>(t.analog.channels);
  const std::vector<uint8_t> p9 = encode_analog_window(t.analog.values.data(), n, t.analog.channels,
                                                       analog_hints(t), 0, kAnalogFloat9Since),
                             p8 = encode_analog_window(t.analog.values.data(), n, t.analog.channels,
                                                       analog_hints(t), 0, kAnalogLatticeSince);
  std::vector<double> back(t.analog.values.size());
  decode_analog_window(p9.data(), p9.size(), n, t.analog.channels, back.data(), "coda", 0,
                       kAnalogFloat9Since);
  EXPECT_EQ(std::memcmp(back.data(), t.analog.values.data(), back.size() * 8), 0);
  EXPECT_LT(static_cast<double>(p9.size()), 0.75 * static_cast<double>(p8.size()));
  // And through the whole codec: the stream is 9.0 and gives every analog sample back.
  CompressOptions o;
  o.lossless = true;
  const std::vector<uint8_t> s = compress(t, o);
  EXPECT_EQ(s[9], kFormat9.major);
  const Take back_take = decompress(s.data(), s.size(), "coda");
  EXPECT_EQ(std::memcmp(back_take.analog.values.data(), t.analog.values.data(),
                        t.analog.values.size() * 8),
            0);
}

}  // namespace
}  // namespace capz
