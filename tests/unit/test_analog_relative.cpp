// Analog window version 2 (docs/FORMAT.md 11.10, format 9.3): an integer residual's token is coded
// relative to its magnitude context, with contexts for tokens far below and one for tokens far
// above. Residuals round-trip through the stage on all three paths; noise of large and changing
// magnitude codes smaller than in a 9.2 window, small residuals about the same; a version 2
// window is corrupt in a 9.2 stream, version 0 and 1 windows decode the same in 9.3, and a token
// out of 0 .. 63 is corrupt.
#include <gtest/gtest.h>

#include <cmath>
#include <random>

#include "analog_window.h"
#include "capz/error.h"
#include "capz/version.h"
#include "coding/analog/analog_codec.h"
#include "coding/analog/analog_entropy.h"
#include "coding/bytes.h"
#include "coding/entropy.h"

namespace capz {
namespace {

using analog::bits_of;

// Which of 9.7's three paths the stage takes for v after the residuals coded so far (m).
int path_of(const analog::Magnitude& m, int32_t v) {
  int nbits;
  const int d = token_of(zigzag(v), &nbits) - m.context() + analog::kRelShift;
  return d <= 0 ? 0 : d < 15 ? 1 : 2;
}

TEST(AnalogRelative, GivenResidualsOnEveryPathThenTheStageRoundTrips) {
  // Runs of large residuals (a high context) broken by zeros and small ones (far below), and
  // small runs broken by large ones (far above); then every token's extremes.
  std::vector<int32_t> v;
  for (int r = 0; r < 40; ++r) v.push_back((r & 1) ? 5000 + r : -7000 - r);
  for (int32_t x : {0, 1, -1, 2, 0, 3}) v.push_back(x);
  for (int r = 0; r < 40; ++r) v.push_back(r % 3 - 1);
  for (int32_t x : {1 << 20, -(1 << 28), 123456, 0, (1 << 30) - 1, -(1 << 30)}) v.push_back(x);
  for (int e = 2; e <= 28; ++e) {
    v.push_back((1 << e) - 1);
    v.push_back(-(1 << e));
    v.push_back(0);
    v.push_back((1 << e) + 3);
  }
  int on[3] = {0, 0, 0};
  analog::Magnitude probe;
  for (int32_t x : v) {
    ++on[path_of(probe, x)];
    probe.update(zigzag(x));
  }
  ASSERT_GT(on[0], 5);  // far below
  ASSERT_GT(on[1], 5);  // the context's own symbols
  ASSERT_GT(on[2], 5);  // far above
  IntEncoder enc(analog::kAnalogContexts);
  analog::start_low_bit_models(&enc);
  IntEncoder::Cursor c = enc.cursor();
  analog::Magnitude m;
  for (int32_t x : v) analog::put_residual_v2(&c, &m, x);
  enc.commit(c);
  const std::vector<uint8_t> block = enc.finish();
  IntDecoder dec(block.data(), block.size(), analog::kAnalogContexts, "relative tokens");
  analog::start_low_bit_models(&dec);
  IntDecoder::Cursor d = dec.cursor();
  analog::Magnitude md;
  for (size_t i = 0; i < v.size(); ++i) ASSERT_EQ(analog::get_residual_v2(&d, &md), v[i]) << i;
  dec.commit(d);
  EXPECT_TRUE(dec.at_end());
}

std::vector<uint8_t> round_trip(const std::vector<double>& v, FormatVersion format) {
  return capz_test::window_round_trip(v, 1, format);
}

// EMG-like: Laplacian noise whose scale changes every 400 samples between 40 and 4000 (bursts),
// so that most residuals' tokens are 15 or more, which a 9.2 window codes through the escapes.
std::vector<double> bursts(uint32_t seed) {
  std::mt19937 rng(seed);
  std::exponential_distribution<double> ex(1.0);
  std::vector<double> v(16000);
  for (size_t i = 0; i < v.size(); ++i) {
    const double scale = (i / 400) % 3 == 0 ? 4000 : (i / 400) % 3 == 1 ? 400 : 40;
    v[i] = std::round(((rng() & 1) ? 1 : -1) * ex(rng) * scale);
  }
  return v;
}

TEST(AnalogRelative, GivenNoiseInBurstsThen93SmallerThan92AndExact) {
  const std::vector<double> v = bursts(3);
  EXPECT_EQ(round_trip(v, kAnalogRelativeSince)[0], 2);  // the window version
  const auto [w93, w92] = capz_test::window_sizes(v, kAnalogRelativeSince, kAnalogLowBitsSince);
  EXPECT_LT(w93 * 1000, w92 * 985) << w93 << " against " << w92;
}

// Residuals mostly below 96 (tokens below 15) never escaped in 9.2: at most 1% larger.
TEST(AnalogRelative, GivenSmallNoiseThen93AboutAs92) {
  std::mt19937 rng(11);
  std::normal_distribution<double> noise(0, 12);
  std::vector<double> v(8000);
  for (double& s : v) s = std::round(noise(rng));
  const auto [w93, w92] = capz_test::window_sizes(v, kAnalogRelativeSince, kAnalogLowBitsSince);
  EXPECT_LT(w93 * 100, w92 * 101) << w93 << " against " << w92;
}

void expect_corrupt(const std::vector<uint8_t>& w, size_t n, FormatVersion format,
                    const std::string& message) {
  capz_test::expect_window_corrupt(w, n, 1, format, message, message);
}

TEST(AnalogRelative, GivenWindowVersionsThenEachDecodesOnlyWhereValid) {
  const std::vector<double> v = bursts(7);
  const std::vector<uint8_t> w93 = round_trip(v, kAnalogRelativeSince),
                             w92 = round_trip(v, kAnalogLowBitsSince),
                             w91 = round_trip(v, kAnalogConstantSince);
  expect_corrupt(w93, v.size(), kAnalogLowBitsSince, "unknown analog window version");
  std::vector<uint8_t> w = w93;
  w[0] = 3;
  expect_corrupt(w, v.size(), kAnalogRelativeSince, "unknown analog window version");
  // Version 1 and version 0 windows decode the same in a 9.3 stream.
  for (const std::vector<uint8_t>* old : {&w92, &w91}) {
    std::vector<double> back(v.size());
    decode_analog_window(old->data(), old->size(), v.size(), 1, back.data(), "older window", 0,
                         kAnalogRelativeSince);
    for (size_t i = 0; i < v.size(); ++i) ASSERT_EQ(bits_of(back[i]), bits_of(v[i])) << i;
  }
  // Damaged anywhere: samples or a clean corrupt error.
  capz_test::expect_flips_corrupt_or_decoded(std::vector<uint8_t>(w93.begin(), w93.begin() + 400),
                                             v.size(), 1, kAnalogRelativeSince);
}

// A version 2 window of one integer channel whose block is made by hand: no cascade, no
// reference, order 0, n - 1 zero residuals (magnitude context 0), then the symbol `sym` under
// context 0 and, for 0 and 15, `value` under the below or above context; a token below 4 has no
// bits below it.
std::vector<uint8_t> crafted(int sym, uint32_t value, size_t n) {
  return capz_test::int_window_by_hand(n, kAnalogRelativeSince, [&](IntEncoder::Cursor* c) {
    analog::Magnitude m;
    for (size_t i = 0; i + 1 < n; ++i) analog::put_residual_v2(c, &m, 0);
    EXPECT_EQ(m.context(), 0);
    c->put_symbol(sym, 0);
    if (sym == 0) c->put(value, analog::kBelowContext);
    if (sym == 15) c->put(value, analog::kAboveContext);
  });
}

TEST(AnalogRelative, GivenATokenOutOfRangeThenCorrupt) {
  const size_t n = 50;
  std::vector<double> out(n);
  // Context 0: symbol 14 is token 0 (u = 0), symbol 15 with 0 above is token 1 (u = 1: -1),
  // with 2 above token 3 (u = 3: -2).
  const std::pair<int, uint32_t> valid[] = {{14, 0}, {15, 0}, {15, 2}};
  const double want[] = {0, -1, -2};
  for (int k = 0; k < 3; ++k) {
    const std::vector<uint8_t> w = crafted(valid[k].first, valid[k].second, n);
    decode_analog_window(w.data(), w.size(), n, 1, out.data(), "crafted", 0, kAnalogRelativeSince);
    EXPECT_EQ(out[n - 1], want[k]) << k;
  }
  // Below context 0 every token is negative; symbol 13 is token -1; 15 with 64 - 1 above is 64.
  expect_corrupt(crafted(0, 0, n), n, kAnalogRelativeSince, "analog residual token out of range");
  expect_corrupt(crafted(13, 0, n), n, kAnalogRelativeSince, "analog residual token out of range");
  expect_corrupt(crafted(15, 63, n), n, kAnalogRelativeSince, "analog residual token out of range");
  expect_corrupt(crafted(15, 0xFFFFFFFFu, n), n, kAnalogRelativeSince,
                 "analog residual token out of range");
}

}  // namespace
}  // namespace capz
