// An analog window's integer residuals (docs/FORMAT.md 9.5, 9.7; window version 2, the one
// value format 1.0 defines): a token is coded relative to its magnitude context, with contexts
// for tokens far below and one for tokens far above, and the two bits below it through a model
// per token. Residuals round-trip through the stage on all three paths; any other window version
// is corrupt, and so are a token out of 0 .. 63 and a low-bit symbol out of its range.
#include <gtest/gtest.h>

#include <cmath>
#include <random>

#include "analog_window.h"
#include "capz/error.h"
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

// EMG-like: Laplacian noise whose scale changes every 400 samples between 40 and 4000 (bursts),
// so that most residuals' tokens are 15 or more.
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

void expect_corrupt(const std::vector<uint8_t>& w, size_t n, const std::string& message) {
  capz_test::expect_window_corrupt(w, n, 1, message, message);
}

TEST(AnalogRelative, GivenWindowVersionsThenOnly2Decodes) {
  const std::vector<double> v = bursts(7);
  const std::vector<uint8_t> w2 = capz_test::window_round_trip(v, 1);
  ASSERT_EQ(w2[0], 2);  // the window version
  for (const uint8_t other : {0, 1, 3, 255}) {
    std::vector<uint8_t> w = w2;
    w[0] = other;
    expect_corrupt(w, v.size(), "unknown analog window version");
  }
  // Damaged anywhere: samples or a clean corrupt error.
  capz_test::expect_flips_corrupt_or_decoded(std::vector<uint8_t>(w2.begin(), w2.begin() + 400),
                                             v.size(), 1);
}

// A window of one integer channel whose block is made by hand: no cascade, no reference, order
// 0, n - 1 zero residuals (magnitude context 0), then the symbol `sym` under context 0 and, for
// 0 and 15, `value` under the below or above context; a token below 4 has no bits below it, one
// above has the low-bit symbol `low` (when not negative) and no raw bits (tokens 4 .. 7).
std::vector<uint8_t> crafted(int sym, uint32_t value, size_t n, int tok = 0, int low = -1) {
  return capz_test::int_window_by_hand(n, [&](IntEncoder::Cursor* c) {
    analog::Magnitude m;
    for (size_t i = 0; i + 1 < n; ++i) analog::put_residual_v2(c, &m, 0);
    EXPECT_EQ(m.context(), 0);
    c->put_symbol(sym, 0);
    if (sym == 0) c->put(value, analog::kBelowContext);
    if (sym == 15) c->put(value, analog::kAboveContext);
    if (low >= 0) c->put_symbol(low, analog::kLowContext + tok - 4);
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
    decode_analog_window(w.data(), w.size(), n, 1, out.data(), "crafted");
    EXPECT_EQ(out[n - 1], want[k]) << k;
  }
  // Below context 0 every token is negative; symbol 13 is token -1; 15 with 64 - 1 above is 64.
  expect_corrupt(crafted(0, 0, n), n, "analog residual token out of range");
  expect_corrupt(crafted(13, 0, n), n, "analog residual token out of range");
  expect_corrupt(crafted(15, 63, n), n, "analog residual token out of range");
  expect_corrupt(crafted(15, 0xFFFFFFFFu, n), n, "analog residual token out of range");
}

TEST(AnalogRelative, GivenALowBitSymbolOutOfItsRangeThenCorrupt) {
  const size_t n = 50;
  std::vector<double> out(n);
  // Token 6 (u = 8 .. 11) under context 0 is symbol 15 and 6 + 14 - 15 = 5 above; two bits below
  // it, symbols 0-3. Token 4 (u = 4, 5) is 3 above, one bit, symbols 0-1.
  for (int low = 0; low < 4; ++low) {
    const std::vector<uint8_t> w = crafted(15, 5, n, 6, low);
    decode_analog_window(w.data(), w.size(), n, 1, out.data(), "crafted");
    const int32_t u = 8 + low, e = (u >> 1) ^ -(u & 1);
    EXPECT_EQ(out[n - 1], static_cast<double>(e)) << low;
  }
  expect_corrupt(crafted(15, 5, n, 6, 4), n, "low-bit symbol out of range");
  expect_corrupt(crafted(15, 3, n, 4, 2), n, "low-bit symbol out of range");
  expect_corrupt(crafted(15, 5, n, 6, 15), n, "low-bit symbol out of range");
}

}  // namespace
}  // namespace capz
