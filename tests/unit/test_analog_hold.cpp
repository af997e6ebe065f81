// Held analog samples (docs/FORMAT.md 11.5): channels written by sample and hold from a slower
// sensor (every sample but those at one phase of a period a copy of the one before) round-trip
// bit for bit with a hold field, which is written only in 9.2 windows and only where it codes
// smaller; exceptions, NaN and -0.0 samples, long periods and references between channels follow
// the format; damaged fields throw kCorrupt; the Cometa take's accelerometers (changing every
// 14th row) go C3D -> capz 9.2 -> C3D exactly and smaller.
#include <gtest/gtest.h>

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
#include "coding/analog/analog_hold.h"
#include "coding/analog/analog_interp.h"
#include "coding/analog/analog_repr.h"
#include "coding/bytes.h"
#include "relabel.h"
#include "test_util.h"

namespace capz {
namespace {

using analog::bits_of;
using analog::Hold;

// n samples of a noisy walk on a 1/32 lattice (as Cometa's accelerometers), changing only at the
// rows i with i mod P = phase and held in between.
std::vector<double> held(size_t n, uint32_t P, uint32_t phase, uint32_t seed) {
  std::mt19937 rng(seed);
  std::normal_distribution<double> step(0, 6);
  std::vector<double> x(n);
  double v = 0.25;
  for (size_t i = 0; i < n; ++i) {
    if (i % P == phase) v += std::round(step(rng)) / 32;
    x[i] = v;
  }
  return x;
}

// Encodes a window of these columns as `format`, decodes it and compares bits.
std::vector<uint8_t> round_trip(const std::vector<std::vector<double>>& cols,
                                FormatVersion format = kAnalogHoldSince) {
  return capz_test::window_round_trip(capz_test::rows_of(cols), cols.size(), format);
}

// Each channel's hold field as a 9.2 payload's header gives it.
std::vector<Hold> fields(const std::vector<uint8_t>& p, size_t n, size_t C) {
  std::vector<Hold> out;
  for (const capz_test::ChannelHeader& h : capz_test::channel_headers(p, n, C))
    out.push_back(h.kept.hold);
  return out;
}

TEST(AnalogHold, GivenHeldChannelsWhenCodedThenFieldWrittenExactAndSmallerThan91) {
  struct Case {
    uint32_t P, phase;
    size_t n;
  };
  for (const Case& k : {Case{2, 0, 4001}, Case{2, 1, 4000}, Case{14, 9, 8000}, Case{14, 0, 3000},
                        Case{300, 17, 40000}, Case{65535, 3, 200000}}) {
    SCOPED_TRACE("P " + std::to_string(k.P) + " phase " + std::to_string(k.phase));
    const std::vector<double> x = held(k.n, k.P, k.phase, k.P + k.phase);
    Hold found;
    ASSERT_TRUE(analog::find_hold(x.data(), 1, x.size(), &found));
    EXPECT_EQ(found.period, k.P);
    EXPECT_EQ(found.phase, k.phase);
    EXPECT_TRUE(found.exceptions.empty());
    const std::vector<uint8_t> p92 = round_trip({x}), p91 = round_trip({x}, kAnalogConstantSince);
    const Hold f = fields(p92, x.size(), 1)[0];
    EXPECT_EQ(f.period, k.P);
    EXPECT_EQ(f.phase, k.phase);
    EXPECT_LT(p92.size(), p91.size());
    if (k.P >= 14) {  // a 2:1 hold already codes cheaply as zero residuals
      EXPECT_LT(static_cast<double>(p92.size()), 0.65 * static_cast<double>(p91.size()));
    }
  }
}

// The exceptions' budget (1/16 of the held samples): a channel with that many changes off its
// phase is still found, with each of them as an exception; one more and it is not.
TEST(AnalogHold, GivenExceptionsUpToTheBudgetThenFoundOneMoreThenNot) {
  const size_t n = 1000;  // period 2, phase 0: anchors 0, 2, .., 998; 500 held, a budget of 31
  const std::vector<double> x = held(n, 2, 0, 5);
  for (size_t extra : {size_t{0}, size_t{1}}) {
    std::vector<double> y = x;
    for (size_t e = 0; e < 31 + extra; ++e) y[2 * e + 1] += 0.5;
    Hold h;
    const bool found = analog::find_hold(y.data(), 1, n, &h);
    EXPECT_EQ(found, extra == 0);
    if (!found) continue;
    EXPECT_EQ(h.period, 2u);
    EXPECT_EQ(h.phase, 0u);
    ASSERT_EQ(h.exceptions.size(), 31u);
    EXPECT_EQ(h.exceptions[30], 61u);
    EXPECT_EQ(analog::hold_kept_count(n, h), 500u + 31u);
    const std::vector<uint8_t> p = round_trip({y});
    EXPECT_EQ(fields(p, n, 1)[0], h);
  }
}

// Gaps and signed zeros inside a held channel: a NaN with a payload held over its period, an
// infinity, -0.0 after +0.0 at a held row (an exception) and a NaN at a held row.
TEST(AnalogHold, GivenNaNPayloadsInfinitiesAndSignedZerosThenExact) {
  std::vector<double> x = held(5000, 14, 9, 3);
  double nan;
  const uint64_t payload = 0x7FF80000DEADBEEFull;
  std::memcpy(&nan, &payload, 8);
  for (size_t i = 23; i < 37; ++i) x[i] = nan;  // one held period of a NaN with a payload
  for (size_t i = 37; i < 51; ++i) x[i] = std::numeric_limits<double>::infinity();
  for (size_t i = 51; i < 65; ++i) x[i] = 0.0;
  for (size_t i = 60; i < 65; ++i) x[i] = -0.0;  // a change at a held row
  x[1000] = std::numeric_limits<double>::quiet_NaN();
  const std::vector<uint8_t> p = round_trip({x});
  const Hold f = fields(p, x.size(), 1)[0];
  ASSERT_EQ(f.period, 14u);
  EXPECT_EQ(f.exceptions, (std::vector<uint32_t>{60, 1000, 1001}));
}

// The channel headers of a window (after its version byte and the headers' size).
std::vector<uint8_t> headers(const std::vector<uint8_t>& p) {
  ByteReader in(p.data(), p.size(), "headers");
  in.u8();
  const size_t h = static_cast<size_t>(in.varint());
  const uint8_t* b = in.bytes(h);
  return std::vector<uint8_t>(b, b + h);
}

TEST(AnalogHold, GivenChannelsNotHeldThenNoFieldAndTheHeadersOf91) {
  std::mt19937 rng(3);
  std::normal_distribution<double> noise(0, 100);
  std::vector<double> x(3000), steps(3000);
  for (double& v : x) v = std::round(noise(rng));
  // A staircase whose changes come 13 and 14 rows apart (a rate that is no integer fraction):
  // no period leaves few exceptions.
  double v = 0;
  for (size_t i = 0; i < steps.size(); ++i) {
    if ((i * 2) % 27 < 2) v += 1;
    steps[i] = v;
  }
  for (const std::vector<double>* c : {&x, &steps}) {
    Hold f;
    EXPECT_FALSE(analog::find_hold(c->data(), 1, c->size(), &f));
    EXPECT_EQ(headers(round_trip({*c})), headers(round_trip({*c}, kAnalogConstantSince)));
  }
}

TEST(AnalogHold, GivenHeldChannelsOfOneSensorThenReferencesAllowedAndExact) {
  // Three axes of one sensor share the period and phase; b follows a, c is another sensor.
  const std::vector<double> a = held(6000, 14, 9, 11), c = held(6000, 10, 4, 12);
  std::vector<double> b(a.size());
  for (size_t i = 0; i < a.size(); ++i) b[i] = a[i] * 2 + 0.5;
  const std::vector<uint8_t> p = round_trip({a, b, c});
  const std::vector<Hold> f = fields(p, a.size(), 3);
  EXPECT_EQ(f[0].period, 14u);
  EXPECT_EQ(f[1], f[0]);
  EXPECT_EQ(f[2].period, 10u);
  EXPECT_LT(p.size(), round_trip({a}).size() + round_trip({b}).size() + round_trip({c}).size());
}

TEST(AnalogHold, GivenTinyWindowsThenExact) {
  for (size_t n : {1, 2, 3, 9, 10, 17, 33}) round_trip({held(n, 2, 1, static_cast<uint32_t>(n))});
}

TEST(AnalogHold, GivenKeptSamplesThenExpandGivesTheChannelBack) {
  Hold h;
  h.period = 4;
  h.phase = 2;
  h.exceptions = {3, 7};
  const std::vector<double> x = {1, 1, 2, 5, 5, 5, 6, 8, 8, 8, 9};
  // anchors 0, 2, 6, 10 and exceptions 3, 7
  EXPECT_EQ(analog::hold_kept_count(x.size(), h), 6u);
  const std::vector<double> kept = analog::hold_kept(x.data(), 1, x.size(), h);
  EXPECT_EQ(kept, (std::vector<double>{1, 2, 5, 6, 8, 9}));
  std::vector<double> back(x.size(), -1);
  analog::expand_hold(kept.data(), x.size(), h, back.data(), 1);
  EXPECT_EQ(back, x);
}

// A window of one held channel (P 14, phase 9, no exceptions), for the damage tests.
struct Coded {
  std::vector<double> x = held(2001, 14, 9, 5);
  std::vector<uint8_t> p = round_trip({x});
};

void expect_corrupt(const std::vector<uint8_t>& p, size_t n, FormatVersion format,
                    const std::string& why, const std::string& message) {
  capz_test::expect_window_corrupt(p, n, 1, format, why, message);
}

TEST(AnalogHold, GivenDamagedFieldsThenCorruptNeverCrash) {
  const Coded c;
  const size_t k = capz_test::first_kind_at(c.p), n = c.x.size();
  ASSERT_TRUE(c.p[k] & 128);
  ASSERT_EQ(c.p[k + 1], 14);  // P
  ASSERT_EQ(c.p[k + 2], 9);   // phase
  ASSERT_EQ(c.p[k + 3], 0);   // no exceptions
  const char* kind = "unknown analog channel kind";
  // Before 9.2 the window's version 1 (FORMAT.md 11.10) is corrupt first; as version 0, bit 7.
  expect_corrupt(c.p, n, kAnalogConstantSince, "version 1 before 9.2",
                 "unknown analog window version");
  std::vector<uint8_t> q = c.p;
  q[0] = 0;
  expect_corrupt(q, n, kAnalogConstantSince, "bit 7 before 9.2", kind);
  expect_corrupt(q, n, kAnalogLatticeSince, "bit 7 before 9.0", kind);
  for (uint8_t other : {32, 64}) {
    q = c.p;
    q[k] |= other;
    expect_corrupt(q, n, kAnalogHoldSince, "bit 7 with bit " + std::to_string(other), kind);
  }
  q = c.p;
  q[k] = static_cast<uint8_t>(q[k] & ~7);
  expect_corrupt(q, n, kAnalogHoldSince, "bit 7 with kind 0", kind);
  for (uint8_t P : {0, 1}) {
    q = c.p;
    q[k + 1] = P;
    expect_corrupt(q, n, kAnalogHoldSince, "P " + std::to_string(P), "analog hold period");
  }
  q = c.p;  // P = 65536, a three-byte varint
  q[k + 1] = 0x80;
  q.insert(q.begin() + static_cast<long>(k) + 2, {0x80, 0x04});
  expect_corrupt(q, n, kAnalogHoldSince, "P 65536", "analog hold period");
  q = c.p;
  q[k + 2] = 14;
  expect_corrupt(q, n, kAnalogHoldSince, "phase P", "analog hold phase");
  // An exception at sample 0 and one at the phase (runs 1, skip, length 1), where none was.
  for (uint8_t at : {0, 23}) {
    q = c.p;
    q[k + 3] = 1;
    q.insert(q.begin() + static_cast<long>(k) + 4, {at, 0});
    expect_corrupt(q, n, kAnalogHoldSince, "exception at " + std::to_string(at),
                   "is not a held sample");
  }
  q = c.p;  // a run of exceptions past the window's end
  q[k + 3] = 1;
  q.insert(q.begin() + static_cast<long>(k) + 4, {1, 0x90, 0x10});
  expect_corrupt(q, n, kAnalogHoldSince, "run past n", "run past the window's end");
  // Every payload byte flipped: kCorrupt or samples, never a crash.
  capz_test::expect_flips_corrupt_or_decoded(c.p, n, 1, kAnalogHoldSince);
}

// The header writer refuses a layout its rules do not allow (an encoder bug, not bad input): a
// hold before 9.2, an interpolation before 9.0, a repeat list outside 7.x windows, two layouts.
TEST(AnalogHold, GivenLayoutsTheRulesDoNotAllowThenTheWriterRefuses) {
  analog::ChannelRepr r;
  r.kind = analog::Kind::kInt;
  analog::KeptRows held, interp, repeats, both;
  held.hold.period = 14;
  interp.interp.period = 2;
  repeats.repeats = {3};
  both = held;
  both.repeats = {3};
  analog::HeaderRules all;
  all.S = 4;
  all.lattice = all.interp = all.hold = all.share = true;
  auto refused = [&](const analog::KeptRows& kept, const analog::HeaderRules& rules) {
    analog::HeaderState state;
    ByteWriter w;
    try {
      analog::write_repr_header(r, kept, rules, &state, &w);
    } catch (const Error& e) {
      EXPECT_EQ(e.code(), ErrorCode::kInternal);
      return true;
    }
    return false;
  };
  for (const analog::KeptRows* kept : {&held, &interp, &repeats}) EXPECT_FALSE(refused(*kept, all));
  analog::HeaderRules rules = all;
  rules.hold = false;
  EXPECT_TRUE(refused(held, rules));
  rules = all;
  rules.interp = false;
  EXPECT_TRUE(refused(interp, rules));
  rules = all;
  rules.S = 0;
  EXPECT_TRUE(refused(repeats, rules));
  EXPECT_TRUE(refused(both, all));
}

// The bundled sample (data/make_held_analog.py): its three accelerometer channels get hold fields
// of period 14 and phase 9, ACCY with the two changes it makes off the phase as exceptions; its
// two EMG channels none.
TEST(AnalogHold, GivenTheBundledHeldSampleThenItsAccelerometersAreHeld) {
  const Take t = read_take(std::string(CAPZ_TEST_DIR) + "/../data/held_analog.c3d");
  ASSERT_EQ(t.analog.channels, 5);
  const size_t n = t.analog.values.size() / 5;
  const std::vector<uint8_t> p =
      encode_analog_window(t.analog.values.data(), n, 5, analog_hints(t), 0, kAnalogHoldSince);
  const std::vector<Hold> f = fields(p, n, 5);
  EXPECT_EQ(f[0].period, 0u);
  EXPECT_EQ(f[1].period, 0u);
  for (int c = 2; c < 5; ++c) {
    EXPECT_EQ(f[c].period, 14u) << c;
    EXPECT_EQ(f[c].phase, 9u) << c;
  }
  EXPECT_TRUE(f[2].exceptions.empty());
  EXPECT_EQ(f[3].exceptions, (std::vector<uint32_t>{500, 503}));
}

// The 9.2 golden stream relabelled 9.1 (header CRC made right): its analog windows (of version
// 1, FORMAT.md 11.10, with hold fields) are then corrupt, and the decoder says so, naming the
// chunk, rather than misreading them.
TEST(AnalogHold, GivenA92StreamRelabelled91ThenTheHoldFieldIsCorrupt) {
  const std::vector<uint8_t> b = capz_test::golden_bytes("held_analog.c3d.lossless.v9.2.capz");
  ASSERT_EQ(b[9], 9);
  ASSERT_EQ(b[10], 2);
  EXPECT_EQ(decompress(b.data(), b.size()).analog.channels, 5);  // as written: decodes
  capz_test::expect_corrupt_naming(capz_test::relabelled(b, 9, 1),
                                   {"unknown analog window version", "ANLG"});
}

TEST(AnalogHold, GivenCometaTakeWhenRoundTrippedThen92AndExactAndSmaller) {
  const std::string path =
      capz_test::shared_data_or_skip("c3d/c3dorg/sample_00/Cometa Systems/EMG Data Cometa.c3d");
  if (path.empty()) return;
  const Take t = read_take(path);
  const int C = t.analog.channels;
  const size_t n = t.analog.values.size() / static_cast<size_t>(C);
  const std::vector<uint8_t> p92 = encode_analog_window(t.analog.values.data(), n, C,
                                                        analog_hints(t), 0, kAnalogHoldSince),
                             p91 = encode_analog_window(t.analog.values.data(), n, C,
                                                        analog_hints(t), 0, kAnalogConstantSince);
  std::vector<double> back(t.analog.values.size());
  decode_analog_window(p92.data(), p92.size(), n, C, back.data(), "cometa", 0, kAnalogHoldSince);
  EXPECT_EQ(std::memcmp(back.data(), t.analog.values.data(), back.size() * 8), 0);
  // Its 18 accelerometer channels (every fourth channel is EMG) hold for 14 rows.
  const std::vector<Hold> f = fields(p92, n, static_cast<size_t>(C));
  for (int c = 0; c < C; ++c) EXPECT_EQ(f[c].period, c % 4 ? 14u : 0u) << "channel " << c;
  EXPECT_LT(static_cast<double>(p92.size()), 0.95 * static_cast<double>(p91.size()));
  // And through the whole codec: the stream is 9.2 and gives every analog sample back.
  CompressOptions o;
  o.lossless = true;
  const std::vector<uint8_t> s = compress(t, o);
  EXPECT_EQ(s[9], kFormat9.major);
  EXPECT_EQ(s[10], kFormat9.minor);
  EXPECT_TRUE(kFormat9 >= kAnalogHoldSince);
  const Take back_take = decompress(s.data(), s.size(), "cometa");
  EXPECT_EQ(std::memcmp(back_take.analog.values.data(), t.analog.values.data(),
                        t.analog.values.size() * 8),
            0);
}

}  // namespace
}  // namespace capz
