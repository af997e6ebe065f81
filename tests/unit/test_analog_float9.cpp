// The float coder's predictors of format 9.0 (FORMAT.md 11.9): round trips of every predictor on
// edge cases (NaN payloads, -0.0, subnormals, infinities, float64 channels, 1-3 samples), the
// predictor the encoder keeps for smooth and for noisy channels, the decoder refusing them in a
// window before 9.0, and every new field damaged.
#include <gtest/gtest.h>

#include <cmath>
#include <cstring>
#include <limits>
#include <random>

#include "capz/error.h"
#include "coding/analog/analog_codec.h"
#include "coding/analog/analog_entropy.h"
#include "coding/analog/analog_float.h"
#include "coding/entropy.h"

namespace capz {
namespace analog {
namespace {

// A filtered force: a smooth float32 curve of full mantissas (a resonance driven by noise, which
// the previous sample or a line through two predict worse than a fit of a few).
std::vector<double> smooth_f32(size_t n, uint32_t seed) {
  std::mt19937 rng(seed);
  std::normal_distribution<double> kick(0, 1);
  std::vector<double> x(n);
  double a = 0, b = 0;
  for (size_t i = 0; i < n; ++i) {
    const double v = 1.6 * a - 0.8 * b + kick(rng);
    b = a;
    a = v;
    x[i] = static_cast<double>(static_cast<float>(v));  // crossing 0: no lattice fits
  }
  return x;
}

// EMG-like noise around 0: float32 values whose signs and exponents change all the time.
std::vector<double> noise_f32(size_t n, uint32_t seed) {
  std::mt19937 rng(seed);
  std::normal_distribution<double> g(0, 0.02);
  std::uniform_real_distribution<double> spread(0, 3);
  std::vector<double> x(n);
  for (double& v : x) v = static_cast<float>(g(rng) * std::exp(spread(rng)));
  return x;
}

// Codes x with the given plan and decodes it back (format9 decoding).
std::vector<double> through_plan(const std::vector<double>& x, bool f32, const FloatPlan& plan) {
  IntEncoder enc(kAnalogContexts);
  IntEncoder::Cursor c = enc.cursor();
  EXPECT_TRUE(encode_float_channel(x, f32, plan, &c));
  enc.commit(c);
  const std::vector<uint8_t> block = enc.finish();
  IntDecoder dec(block.data(), block.size(), kAnalogContexts, "float block");
  IntDecoder::Cursor d = dec.cursor();
  std::vector<double> back;
  decode_float_channel(x.size(), f32, &d, &back, true);
  dec.commit(d);
  EXPECT_TRUE(dec.at_end());
  return back;
}

void expect_same_bits(const std::vector<double>& a, const std::vector<double>& b,
                      const char* what) {
  ASSERT_EQ(a.size(), b.size()) << what;
  for (size_t i = 0; i < a.size(); ++i)
    ASSERT_EQ(bits_of(a[i]), bits_of(b[i])) << what << " sample " << i;
}

TEST(AnalogFloat9, GivenEveryPredictorWhenEdgeValuesAreCodedThenTheSameBits) {
  constexpr double kMax = std::numeric_limits<float>::max();
  const double tiny = static_cast<double>(std::numeric_limits<float>::denorm_min());
  std::vector<double> f32_edges = {0.0,  -0.0, kMax,  -kMax, kMax,   tiny,    -tiny, 3 * tiny, 1.0,
                                   -0.0, 0.0,  -kMax, -kMax, 1e-38f, -1e-38f, 7.5,   7.5,      7.5};
  std::vector<double> f64_edges = {0.0,
                                   -0.0,
                                   std::numeric_limits<double>::max(),
                                   -std::numeric_limits<double>::max(),
                                   std::numeric_limits<double>::max(),
                                   std::numeric_limits<double>::denorm_min(),
                                   -std::numeric_limits<double>::denorm_min(),
                                   1e300,
                                   -1e300,
                                   1.0 / 3,
                                   2.0 / 3,
                                   1.0,
                                   -0.0};
  const std::vector<double> smooth = smooth_f32(300, 1), noise = noise_f32(300, 2);
  std::vector<double> smooth64(smooth);
  for (size_t i = 0; i < smooth64.size(); ++i) smooth64[i] += 1e-9 * static_cast<double>(i);
  struct Case {
    std::vector<double> x;
    bool f32;
  };
  const std::vector<Case> cases = {{f32_edges, true}, {f64_edges, false}, {smooth, true},
                                   {noise, true},     {smooth64, false},  {{}, true},
                                   {{2.5}, true},     {{2.5, -1}, false}, {{2.5, -1, 0.25}, true}};
  for (const Case& c : cases)
    for (int p = 2; p <= 5; ++p) {
      FloatPlan plan;
      plan.predictor = p;
      if (p == 5) {  // an order above some channels' length, and coefficients that overflow
        plan.order = 3;
        plan.shift = 1;
        plan.q[0] = 32767;
        plan.q[1] = -32767;
        plan.q[2] = 5;
      }
      expect_same_bits(c.x, through_plan(c.x, c.f32, plan), "edge channel");
    }
}

TEST(AnalogFloat9, GivenSmoothAndNoisyChannelsThenLpcAndZeroAreKeptAndSmallerThan8x) {
  const std::vector<double> smooth = smooth_f32(4000, 3), noise = noise_f32(4000, 4);
  uint64_t est;
  const FloatPlan ps = choose_float_plan9(smooth, true, &est);
  EXPECT_EQ(ps.predictor, 5);
  EXPECT_GE(ps.order, 2);
  EXPECT_EQ(choose_float_plan9(noise, true, &est).predictor, 4);
  for (const std::vector<double>* x : {&smooth, &noise}) {
    const std::vector<uint8_t> p8 =
        encode_analog_window(x->data(), x->size(), 1, {}, 0, kAnalogLatticeSince);
    const std::vector<uint8_t> p9 =
        encode_analog_window(x->data(), x->size(), 1, {}, 0, kAnalogFloat9Since);
    EXPECT_LT(p9.size() * 100, p8.size() * 95) << p8.size() << " -> " << p9.size();
    std::vector<double> back(x->size());
    decode_analog_window(p9.data(), p9.size(), x->size(), 1, back.data(), "w", 0,
                         kAnalogFloat9Since);
    expect_same_bits(*x, back, "9.x window");
    // Before 9.0 the new predictors are unknown.
    try {
      decode_analog_window(p9.data(), p9.size(), x->size(), 1, back.data(), "w8", 0,
                           kAnalogLatticeSince);
      ADD_FAILURE() << "a 9.x float channel decoded as 8.x";
    } catch (const Error& e) {
      EXPECT_EQ(e.code(), ErrorCode::kCorrupt);
      EXPECT_NE(std::string(e.what()).find("unknown analog float predictor"), std::string::npos)
          << e.what();
    }
  }
}

// Windows with gaps (NaN payloads, infinities) and float64 channels, many shapes, 9.x round trip.
TEST(AnalogFloat9, GivenWindowsWithGapsAndFloat64ChannelsThenExact) {
  std::mt19937 rng(9);
  for (size_t n : {1u, 2u, 3u, 17u, 600u}) {
    const size_t C = 3;
    std::vector<double> rows(n * C);
    const std::vector<double> s = smooth_f32(n, 5), z = noise_f32(n, 6);
    for (size_t i = 0; i < n; ++i) {
      rows[i * C] = s[i];
      rows[i * C + 1] = z[i] * 1.0000001;  // float64
      rows[i * C + 2] = s[i] - z[i];
      if (rng() % 7 == 0) rows[i * C + rng() % C] = from_bits(0x7FF8000000000123ull + rng() % 5);
      if (rng() % 11 == 0) rows[i * C + rng() % C] = -std::numeric_limits<double>::infinity();
      if (rng() % 13 == 0) rows[i * C + rng() % C] = -0.0;
    }
    const std::vector<uint8_t> p =
        encode_analog_window(rows.data(), n, 3, {}, 0, kAnalogFloat9Since);
    std::vector<double> back(rows.size());
    decode_analog_window(p.data(), p.size(), n, 3, back.data(), "w", 0, kAnalogFloat9Since);
    expect_same_bits(rows, back, "window");
  }
}

// A block holding one float channel's numbers, made by `make`, decoded with format9.
std::string decode_error(void (*make)(IntEncoder::Cursor*), size_t n = 4) {
  IntEncoder enc(kAnalogContexts);
  IntEncoder::Cursor c = enc.cursor();
  make(&c);
  enc.commit(c);
  const std::vector<uint8_t> block = enc.finish();
  try {
    IntDecoder dec(block.data(), block.size(), kAnalogContexts, "damaged block");
    IntDecoder::Cursor d = dec.cursor();
    std::vector<double> x;
    decode_float_channel(n, true, &d, &x, true);
  } catch (const Error& e) {
    EXPECT_EQ(e.code(), ErrorCode::kCorrupt);
    EXPECT_NE(std::string(e.what()).find("damaged block"), std::string::npos) << e.what();
    return e.what();
  }
  return std::string();
}

TEST(AnalogFloat9, GivenEachNewFieldOutOfRangeThenCorrupt) {
  struct Case {
    const char* field;
    void (*make)(IntEncoder::Cursor*);
    const char* message;  // what the error must say
  };
  const Case cases[] = {
      {"predictor 6", [](IntEncoder::Cursor* c) { c->put(6, kParamContext); },
       "unknown analog float predictor"},
      {"LPC order 0",
       [](IntEncoder::Cursor* c) {
         c->put(5, kParamContext);
         c->put(0, kParamContext);
       },
       "LPC order"},
      {"LPC order above the maximum",
       [](IntEncoder::Cursor* c) {
         c->put(5, kParamContext);
         c->put(kMaxFloatLpcOrder + 1, kParamContext);
       },
       "LPC order"},
      {"shift above 40",
       [](IntEncoder::Cursor* c) {
         c->put(5, kParamContext);
         c->put(1, kParamContext);
         c->put(kMaxFloatLpcShift + 1, kParamContext);
       },
       "shift"},
      {"a coefficient of 2^15",
       [](IntEncoder::Cursor* c) {
         c->put(5, kParamContext);
         c->put(1, kParamContext);
         c->put(10, kParamContext);
         c->put_signed(1 << 15, kCoefContext);
       },
       "coefficient"},
      {"a bit length beyond 64, through the escape above",
       [](IntEncoder::Cursor* c) {
         c->put(2, kParamContext);
         c->put_symbol(15, kMagContexts);
         c->put(57, kFarContext);  // 0 + 8 + 57 = 65
       },
       "bit length"},
      {"a bit length below 0, through the escape below",
       [](IntEncoder::Cursor* c) {
         c->put(2, kParamContext);
         c->put_symbol(0, kMagContexts);
         c->put(0, kFarContext);  // 0 - 7 - 0 < 0
       },
       "bit length"},
      {"top bits wider than the bit length leaves (nb 3: 2 bits below the leading one)",
       [](IntEncoder::Cursor* c) {
         c->put(2, kParamContext);
         c->put_symbol(7 + 3, kMagContexts);
         c->put_symbol(4, kTopContext + 1);
       },
       "top bits"},
  };
  for (const Case& k : cases) {
    const std::string error = decode_error(k.make);
    EXPECT_NE(error.find(k.message), std::string::npos) << k.field << ": \"" << error << "\"";
  }
  // A valid block decodes (the cases above fail on their field, not on the block).
  EXPECT_EQ(decode_error(
                [](IntEncoder::Cursor* c) {
                  c->put(5, kParamContext);
                  c->put(1, kParamContext);
                  c->put(10, kParamContext);
                  c->put_signed(1024, kCoefContext);
                  c->put_symbol(7 + 3, kMagContexts);
                  c->put_symbol(3, kTopContext + 1);
                },
                1),
            "");
}

}  // namespace
}  // namespace analog
}  // namespace capz
