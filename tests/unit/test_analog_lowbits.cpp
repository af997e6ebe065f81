// Analog window version 1 (docs/FORMAT.md 11.10, format 9.2): the two bits below an integer
// residual's token go through a model per token. Residuals round-trip through the stage for
// every token; a channel whose differences keep a pattern in their low bits codes smaller than
// in 9.1, noise about the same; a version 1 window is corrupt in a 9.1 stream, a version 0 one
// decodes the same in 9.2, and a low-bit symbol out of its range is corrupt.
#include <gtest/gtest.h>

#include <cstring>
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

TEST(AnalogLowBits, GivenResidualsOfEveryTokenThenTheStageRoundTrips) {
  std::vector<int32_t> v = {0, 1, -1, 2, -2, 3, 4, 5, 7, 8, -9, 15, 16, 100, -1000, 123456};
  for (int e = 2; e <= 28; ++e) {
    v.push_back((1 << e) - 1);
    v.push_back(-(1 << e));
    v.push_back((1 << e) + 3);
  }
  v.push_back(1 << 28);
  v.push_back(-(1 << 28));
  IntEncoder enc(analog::kAnalogContexts);
  analog::start_low_bit_models(&enc);
  IntEncoder::Cursor c = enc.cursor();
  analog::Magnitude m;
  for (int32_t x : v) analog::put_residual_v1(&c, &m, x);
  enc.commit(c);
  const std::vector<uint8_t> block = enc.finish();
  IntDecoder dec(block.data(), block.size(), analog::kAnalogContexts, "low bits");
  analog::start_low_bit_models(&dec);
  IntDecoder::Cursor d = dec.cursor();
  analog::Magnitude md;
  for (int32_t x : v) ASSERT_EQ(analog::get_residual_v1(&d, &md), x);
  dec.commit(d);
  EXPECT_TRUE(dec.at_end());
}

// Encodes one channel as `format`, decodes it and compares bits; returns the window.
std::vector<uint8_t> round_trip(const std::vector<double>& v, FormatVersion format) {
  return capz_test::window_round_trip(v, 1, format);
}

// As emgwl.c3d's channel MG-4: a walk whose steps are all 4m + 2, so that the zig-zag of each
// first difference is 3 or 4 mod 8 and its two bits below the token are predictable.
TEST(AnalogLowBits, GivenStepsOf4mPlus2Then92SmallerThan91AndExact) {
  std::mt19937 rng(5);
  std::geometric_distribution<int> mag(0.3);
  std::vector<double> v(8000);
  double x = 0;
  for (double& s : v) {
    const int m = mag(rng);
    x += (rng() & 1) ? 4 * m + 2 : -(4 * m + 2);
    s = x;
  }
  EXPECT_EQ(round_trip(v, kAnalogLowBitsSince)[0], 1);  // the window version
  EXPECT_EQ(round_trip(v, kAnalogConstantSince)[0], 0);
  const auto [w92, w91] = capz_test::window_sizes(v, kAnalogLowBitsSince, kAnalogConstantSince);
  EXPECT_LT(w92 * 100, w91 * 94) << w92 << " against " << w91;
}

// White noise has no pattern below its tokens: the models cost at most 1%.
TEST(AnalogLowBits, GivenNoiseThen92AboutAs91) {
  std::mt19937 rng(9);
  std::normal_distribution<double> noise(0, 300);
  std::vector<double> v(8000);
  for (double& s : v) s = std::round(noise(rng));
  const auto [w92, w91] = capz_test::window_sizes(v, kAnalogLowBitsSince, kAnalogConstantSince);
  EXPECT_LT(w92 * 100, w91 * 101) << w92 << " against " << w91;
}

void expect_corrupt(const std::vector<uint8_t>& w, size_t n, FormatVersion format,
                    const std::string& message) {
  capz_test::expect_window_corrupt(w, n, 1, format, message, message);
}

TEST(AnalogLowBits, GivenWindowVersionsThenEachDecodesOnlyWhereValid) {
  std::vector<double> v(3000);
  for (size_t i = 0; i < v.size(); ++i) v[i] = static_cast<double>((i * 37) % 101);
  const std::vector<uint8_t> w92 = round_trip(v, kAnalogLowBitsSince),
                             w91 = round_trip(v, kAnalogConstantSince);
  expect_corrupt(w92, v.size(), kAnalogConstantSince, "unknown analog window version");
  std::vector<uint8_t> w = w92;
  w[0] = 2;
  expect_corrupt(w, v.size(), kAnalogLowBitsSince, "unknown analog window version");
  // A version 0 window decodes the same in a 9.2 stream.
  std::vector<double> back(v.size());
  decode_analog_window(w91.data(), w91.size(), v.size(), 1, back.data(), "9.1 window", 0,
                       kAnalogLowBitsSince);
  for (size_t i = 0; i < v.size(); ++i) ASSERT_EQ(bits_of(back[i]), bits_of(v[i])) << i;
}

// A version 1 window of one integer channel whose block is made by hand: no cascade, no
// reference, order 0, then residual 0s and one residual of token `tok` whose low-bit symbol is
// `sym`.
std::vector<uint8_t> crafted(int tok, int sym, size_t n) {
  return capz_test::int_window_by_hand(n, kAnalogLowBitsSince, [&](IntEncoder::Cursor* c) {
    analog::Magnitude m;
    for (size_t i = 0; i + 1 < n; ++i) analog::put_residual_v1(c, &m, 0);
    // The last residual by hand: its token (u = the token's least value), its symbol, no raw
    // bits beyond it for tokens 4..7.
    int nbits;
    const uint32_t u = token_floor(tok, &nbits);
    c->put_token(u, m.context(), &nbits);
    c->put_symbol(sym, analog::kLowContext + tok - 4);
  });
}

TEST(AnalogLowBits, GivenALowBitSymbolOutOfItsRangeThenCorrupt) {
  const size_t n = 50;
  std::vector<double> out(n);
  // Token 6 (u = 8 .. 11): two bits below it, symbols 0-3; token 4 (u = 4, 5): one bit, 0-1.
  for (int sym = 0; sym < 4; ++sym) {
    const std::vector<uint8_t> w = crafted(6, sym, n);
    decode_analog_window(w.data(), w.size(), n, 1, out.data(), "crafted", 0, kAnalogLowBitsSince);
    const int32_t u = 8 + sym, e = (u >> 1) ^ -(u & 1);
    EXPECT_EQ(out[n - 1], static_cast<double>(e)) << sym;
  }
  expect_corrupt(crafted(6, 4, n), n, kAnalogLowBitsSince, "low-bit symbol out of range");
  expect_corrupt(crafted(4, 2, n), n, kAnalogLowBitsSince, "low-bit symbol out of range");
  expect_corrupt(crafted(6, 15, n), n, kAnalogLowBitsSince, "low-bit symbol out of range");
}

}  // namespace
}  // namespace capz
