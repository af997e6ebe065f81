// Repeated analog frames (docs/FORMAT.md 11.3): windows whose channels repeat whole point frames
// round-trip bit for bit with repeat lists, the lists are written where frames repeat (and only
// in 7.x windows), references follow the same-set rule, corrupt lists throw kCorrupt, and
// vicon_zerowire.c3d (the shared take with repeated frames) goes C3D -> capz 7.0 -> C3D exactly.
#include <gtest/gtest.h>

#include <cmath>
#include <cstring>
#include <random>

#include "analog_window.h"
#include "capz/codec.h"
#include "capz/error.h"
#include "capz/io.h"
#include "capz/version.h"
#include "coding/analog/analog_codec.h"
#include "coding/analog/analog_repeat.h"
#include "coding/analog/analog_repr.h"
#include "coding/bytes.h"
#include "relabel.h"
#include "test_util.h"

namespace capz {
namespace {

using analog::bits_of;
using analog::from_bits;

// A window of `frames` point frames x S rows x C channels, row-major, that the tests fill.
struct Window {
  size_t frames, S;
  int C;
  std::vector<double> rows;
  Window(size_t f, size_t s, int c) : frames(f), S(s), C(c), rows(f * s * c, 0.0) {}
  size_t n() const { return frames * S; }
  double& at(size_t row, int c) { return rows[row * C + c]; }
  // Frame f of channel c made a copy of frame f - 1 (the frame list in increasing order).
  void repeat(int c, const std::vector<uint32_t>& fs) {
    for (uint32_t f : fs)
      for (size_t j = 0; j < S; ++j) at(f * S + j, c) = at((f - 1) * S + j, c);
  }
};

// Int16-like counts of a noisy sine (no two frames alike).
void fill_counts(Window* w, int c, double amp, uint32_t seed) {
  std::mt19937 rng(seed);
  std::normal_distribution<double> noise(0, 20);
  for (size_t i = 0; i < w->n(); ++i)
    w->at(i, c) = std::round(amp * std::sin(0.003 * i + seed) + noise(rng));
}

// Float samples of a random walk.
void fill_floats(Window* w, int c, uint32_t seed) {
  std::mt19937 rng(seed);
  std::normal_distribution<double> step(0, 0.01);
  double v = 0;
  for (size_t i = 0; i < w->n(); ++i) w->at(i, c) = static_cast<float>(v += step(rng));
}

// The frames in [1, frames) chosen with probability p (seeded).
std::vector<uint32_t> some_frames(size_t frames, double p, uint32_t seed) {
  std::mt19937 rng(seed);
  std::bernoulli_distribution pick(p);
  std::vector<uint32_t> v;
  for (size_t f = 1; f < frames; ++f)
    if (pick(rng)) v.push_back(static_cast<uint32_t>(f));
  return v;
}

// Each channel's repeat list as the payload's headers give it.
std::vector<std::vector<uint32_t>> repeat_lists(const std::vector<uint8_t>& p, const Window& w) {
  analog::HeaderRules rules;  // a 7.x window's: repeat lists only
  rules.S = w.S;
  std::vector<std::vector<uint32_t>> lists;
  for (const capz_test::ChannelHeader& h :
       capz_test::channel_headers(p, w.n(), static_cast<size_t>(w.C), rules))
    lists.push_back(h.kept.repeats);
  return lists;
}

// Encodes with repeat lists allowed, decodes, compares bit patterns; returns the payload.
std::vector<uint8_t> round_trip(const Window& w) {
  return capz_test::window_round_trip(w.rows, static_cast<size_t>(w.C), kAnalogWindowsSince, {},
                                      w.S);
}

size_t size_without_lists(const Window& w) {
  return encode_analog_window(w.rows.data(), w.n(), w.C, {}, 0).size();
}

TEST(AnalogRepeat, GivenRunsOfFramesThenTheListRoundTripsAndRejectsFrameZero) {
  const std::vector<uint32_t> fs = {1, 2, 3, 7, 9, 10, 99};
  ByteWriter w;
  analog::write_runs(fs, &w);
  ByteReader r(w.buffer().data(), w.size(), "runs");
  EXPECT_EQ(analog::read_repeats(&r, 100), fs);
  EXPECT_TRUE(r.at_end());
  ByteReader short_window(w.buffer().data(), w.size(), "runs");
  EXPECT_EQ(capz_test::error_of([&] { analog::read_repeats(&short_window, 99); }),
            ErrorCode::kCorrupt);  // frame 99 is outside [1, 99)
  ByteWriter z;
  analog::write_runs({0, 1}, &z);
  ByteReader rz(z.buffer().data(), z.size(), "runs");
  EXPECT_EQ(capz_test::error_of([&] { analog::read_repeats(&rz, 10); }), ErrorCode::kCorrupt);
}

TEST(AnalogRepeat, GivenChannelsWithDifferentRepeatSetsThenExactListsAsRepeatedAndSmaller) {
  Window w(300, 40, 5);
  for (int c = 0; c < 3; ++c) fill_counts(&w, c, 2000 + 300 * c, 10 + c);
  fill_floats(&w, 3, 20);
  fill_counts(&w, 4, 800, 21);  // no repeats
  const std::vector<uint32_t> force = some_frames(w.frames, 0.7, 1);
  const std::vector<uint32_t> emg = some_frames(w.frames, 0.5, 2);
  for (int c = 0; c < 3; ++c) w.repeat(c, force);
  w.repeat(3, emg);
  const std::vector<uint8_t> p = round_trip(w);
  const auto lists = repeat_lists(p, w);
  for (int c = 0; c < 3; ++c) EXPECT_EQ(lists[c], force) << "channel " << c;
  EXPECT_EQ(lists[3], emg);
  EXPECT_TRUE(lists[4].empty());
  EXPECT_LT(p.size() * 10, size_without_lists(w) * 7);  // measured: about half
}

TEST(AnalogRepeat, GivenGapsMinusZeroAndEdgeFramesInRepeatedFramesThenBitExact) {
  Window w(64, 8, 3);
  fill_counts(&w, 0, 1000, 3);
  fill_floats(&w, 1, 4);
  fill_counts(&w, 2, 500, 5);
  // NaN payloads, -0.0 and infinities inside frames that are then repeated.
  const double nan1 = from_bits(0x7FF0000000000123ull), nan2 = from_bits(0xFFF8000000000abcull);
  for (int c = 0; c < 3; ++c) {
    w.at(0 * 8 + 1, c) = nan1;   // frame 0, repeated by frame 1
    w.at(10 * 8 + 3, c) = -0.0;  // frame 10, repeated by 11 and 12
    w.at(10 * 8 + 4, c) = nan2;
    w.at(62 * 8 + 0, c) = -HUGE_VAL;  // frame 62, repeated by the last frame 63
    w.at(30 * 8 + 5, c) = c == 1 ? 0.0 : -0.0;
  }
  const std::vector<uint32_t> fs = {1, 11, 12, 20, 21, 22, 23, 40, 63};
  for (int c = 0; c < 3; ++c) w.repeat(c, fs);
  const std::vector<uint8_t> p = round_trip(w);
  const auto lists = repeat_lists(p, w);
  EXPECT_EQ(lists[0], fs);
  EXPECT_EQ(lists[1], fs);
}

TEST(AnalogRepeat, GivenAChannelRepeatingEveryFrameThenOnlyItsFirstFrameIsCoded) {
  Window w(200, 16, 2);
  fill_counts(&w, 0, 3000, 6);
  fill_counts(&w, 1, 3000, 7);
  std::vector<uint32_t> all;
  for (uint32_t f = 1; f < w.frames; ++f) all.push_back(f);
  w.repeat(0, all);  // one 16-sample pattern, 200 times: not a constant channel
  const std::vector<uint8_t> p = round_trip(w);
  EXPECT_EQ(repeat_lists(p, w)[0], all);
  EXPECT_TRUE(repeat_lists(p, w)[1].empty());
  // Nearly all of the payload is channel 1 now.
  Window only1(200, 16, 1);
  fill_counts(&only1, 0, 3000, 7);
  EXPECT_LT(p.size(), round_trip(only1).size() + 80);
}

TEST(AnalogRepeat, GivenConstantFramesOrNoRepeatsThenTheWindowIsTheOneBefore7) {
  // Without repeated frames (and for constant channels, which repeat trivially) a 7.x window is
  // byte for byte the window of earlier versions.
  Window w(50, 10, 3);
  fill_counts(&w, 0, 900, 8);
  fill_floats(&w, 1, 9);
  for (size_t i = 0; i < w.n(); ++i) w.at(i, 2) = 2.5;
  EXPECT_EQ(encode_analog_window(w.rows.data(), w.n(), w.C, {}, w.S),
            encode_analog_window(w.rows.data(), w.n(), w.C, {}, 0));
}

// Correlated channels: 1 is about -0.8 x channel 0 (an inter-channel reference pays), 2 the same
// of channel 0 but with another repeat set.
Window correlated(const std::vector<uint32_t>& a, const std::vector<uint32_t>& b) {
  Window w(120, 20, 3);
  fill_counts(&w, 0, 3000, 30);
  std::mt19937 rng(31);
  std::normal_distribution<double> noise(0, 2);
  for (size_t i = 0; i < w.n(); ++i) {
    w.at(i, 1) = std::round(-0.8 * w.at(i, 0) + noise(rng));
    w.at(i, 2) = std::round(0.6 * w.at(i, 0) + noise(rng));
  }
  w.repeat(0, a);
  w.repeat(1, a);
  w.repeat(2, b);
  return w;
}

TEST(AnalogRepeat, GivenReferencesNextToRepeatListsThenExactAndOnlyBetweenEqualSets) {
  const std::vector<uint32_t> a = some_frames(120, 0.4, 40), b = some_frames(120, 0.4, 41);
  const Window w = correlated(a, b);
  const std::vector<uint8_t> p = round_trip(w);
  const auto lists = repeat_lists(p, w);
  EXPECT_EQ(lists[0], a);
  EXPECT_EQ(lists[1], a);
  EXPECT_EQ(lists[2], b);
  // Channel 1 references channel 0: the same window without that correlation codes larger.
  Window apart = w;
  fill_counts(&apart, 1, 2400, 32);
  apart.repeat(1, a);
  EXPECT_GT(round_trip(apart).size(), p.size() + 100);
}

// The payload with channel c's repeat list replaced by `list` (the rest of the payload as it is).
std::vector<uint8_t> with_list(const std::vector<uint8_t>& p, const Window& w, int c,
                               const std::vector<uint32_t>& list) {
  ByteReader in(p.data(), p.size(), "edit");
  in.u8();
  const size_t h = static_cast<size_t>(in.varint());
  ByteReader head(in.bytes(h), h, "edit");
  ByteWriter nh;
  analog::HeaderRules rules;
  rules.S = w.S;
  analog::HeaderState in_state, out_state;
  for (int k = 0; k < w.C; ++k) {
    analog::KeptRows kept;
    const analog::ChannelRepr r = analog::read_repr_header(&head, w.n(), rules, &in_state, &kept);
    if (k == c) kept.repeats = list;
    analog::write_repr_header(r, kept, rules, &out_state, &nh);
  }
  ByteWriter out;
  out.u8(0);
  out.varint(nh.size());
  out.bytes(nh.buffer());
  out.bytes(std::vector<uint8_t>(p.begin() + static_cast<long>(in.offset()), p.end()));
  return std::move(out.buffer());
}

TEST(AnalogRepeat, GivenAReferenceToAChannelWithAnotherRepeatSetThenCorrupt) {
  const std::vector<uint32_t> a = some_frames(120, 0.4, 40), b = some_frames(120, 0.4, 41);
  const Window w = correlated(a, b);
  const std::vector<uint8_t> p = round_trip(w);
  // Channel 1's list moved by one frame: same length, so its samples still decode, but its
  // reference (channel 0) now has another set.
  std::vector<uint32_t> moved = a;
  for (size_t i = moved.size(); i-- > 0;)
    if (moved[i] + 1 < 120 && (i + 1 == moved.size() || moved[i] + 1 < moved[i + 1])) {
      ++moved[i];
      break;
    }
  ASSERT_NE(moved, a);
  const std::vector<uint8_t> q = with_list(p, w, 1, moved);
  std::vector<double> out(w.rows.size());
  std::string msg;
  EXPECT_EQ(
      capz_test::error_of(
          [&] { decode_analog_window(q.data(), q.size(), w.n(), w.C, out.data(), "edited", w.S); },
          &msg),
      ErrorCode::kCorrupt);
  EXPECT_NE(msg.find("same repeated frames"), std::string::npos) << msg;
  // The unedited list through the same path decodes (the edit, not the path, is the fault).
  const std::vector<uint8_t> same = with_list(p, w, 1, a);
  EXPECT_EQ(same, p);
}

TEST(AnalogRepeat, GivenARepeatListInAWindowBefore7ThenCorrupt) {
  Window w(100, 10, 2);
  fill_counts(&w, 0, 1000, 50);
  fill_counts(&w, 1, 1000, 51);
  w.repeat(0, some_frames(100, 0.5, 52));
  const std::vector<uint8_t> p = round_trip(w);
  ASSERT_FALSE(repeat_lists(p, w)[0].empty());
  std::vector<double> out(w.rows.size());
  std::string msg;
  // A 4.x-6.x stream decodes ANLG with no samples per frame for repeats (decoder.cpp).
  EXPECT_EQ(
      capz_test::error_of(
          [&] { decode_analog_window(p.data(), p.size(), w.n(), w.C, out.data(), "v6"); }, &msg),
      ErrorCode::kCorrupt);
  EXPECT_NE(msg.find("before format 7.0"), std::string::npos) << msg;
}

// A one-channel kConst window whose kind byte has bit 5 and the given list bytes.
std::vector<uint8_t> const_window(const std::vector<uint8_t>& list_bytes) {
  ByteWriter h;
  h.u8(0x20);  // kConst | repeat list
  h.bytes(list_bytes);
  h.varint(__builtin_bswap64(bits_of(1.5)));
  ByteWriter out;
  out.u8(0);
  out.varint(h.size());
  out.bytes(h.buffer());
  return std::move(out.buffer());
}

TEST(AnalogRepeat, GivenCorruptRepeatListsThenKCorruptNeverCrash) {
  const size_t S = 4, frames = 10, n = S * frames;
  std::vector<double> out(n);
  auto decode = [&](const std::vector<uint8_t>& p) {
    return capz_test::error_of(
        [&] { decode_analog_window(p.data(), p.size(), n, 1, out.data(), "bad list", S); });
  };
  // Valid: frames 2-3 and 9 repeat a constant channel.
  ASSERT_EQ(decode(const_window({2, 2, 1, 5, 0})), ErrorCode::kInternal);  // no error
  for (double v : out) EXPECT_EQ(v, 1.5);
  const std::vector<std::vector<uint8_t>> bad = {
      {0},                                                                 // no runs
      {1, 0, 0},                                                           // frame 0
      {1, 10, 0},                                                          // starts at Fw
      {1, 9, 1},                                                           // 9..10 passes Fw
      {1, 0xFF, 0xFF, 0xFF, 0xFF, 0xFF, 0xFF, 0xFF, 0xFF, 0xFF, 0x01, 0},  // start 2^64 - 1
      {1, 1, 0xFF, 0xFF, 0xFF, 0xFF, 0xFF, 0xFF, 0xFF, 0xFF, 0xFF, 0x01},  // length 2^64
      {0xFF, 0xFF, 0x03, 1, 0},  // 65535 runs in a few bytes
      {1, 1},                    // truncated
  };
  for (size_t k = 0; k < bad.size(); ++k)
    EXPECT_EQ(decode(const_window(bad[k])), ErrorCode::kCorrupt) << "case " << k;
  // Adjacent runs (1..1 then 2..2) are a valid, if longer, spelling of one run.
  EXPECT_EQ(decode(const_window({2, 1, 0, 0, 0})), ErrorCode::kInternal);
  // A window whose rows are not whole frames cannot carry a list.
  const std::vector<uint8_t> p = const_window({1, 1, 0});
  std::vector<double> odd(n - 1);
  EXPECT_EQ(capz_test::error_of(
                [&] { decode_analog_window(p.data(), p.size(), n - 1, 1, odd.data(), "odd", S); }),
            ErrorCode::kCorrupt);
}

TEST(AnalogRepeat, GivenFlippedBytesOfARepeatWindowThenKCorruptNeverCrash) {
  const std::vector<uint32_t> a = some_frames(120, 0.4, 40), b = some_frames(120, 0.4, 41);
  const Window w = correlated(a, b);
  const std::vector<uint8_t> p = round_trip(w);
  std::vector<double> out(w.rows.size());
  std::mt19937 rng(60);
  int corrupt = 0;
  for (int trial = 0; trial < 2000; ++trial) {
    std::vector<uint8_t> q = p;
    if (trial < static_cast<int>(p.size()) && trial < 400) {
      q.resize(static_cast<size_t>(trial));
    } else {
      for (int k = 0; k < 1 + trial % 3; ++k)
        q[rng() % std::min<size_t>(q.size(), 64)] ^= static_cast<uint8_t>(1 + rng() % 255);
    }
    const ErrorCode e = capz_test::error_of(
        [&] { decode_analog_window(q.data(), q.size(), w.n(), w.C, out.data(), "flip", w.S); });
    EXPECT_TRUE(e == ErrorCode::kCorrupt || e == ErrorCode::kInternal);
    corrupt += e == ErrorCode::kCorrupt;
  }
  EXPECT_GT(corrupt, 500);
}

// The 7.0 golden stream relabelled 6.0 (header CRC made right): its ANLG repeat lists are then
// corrupt, and the decoder says so rather than misreading them.
TEST(AnalogRepeat, GivenA7StreamRelabelled6ThenTheRepeatListIsCorrupt) {
  const std::vector<uint8_t> b = capz_test::golden_bytes("repeat_analog.c3d.lossless.v7.0.capz");
  ASSERT_EQ(b[9], 7);
  EXPECT_EQ(decompress(b.data(), b.size()).analog.channels, 6);  // as written: decodes
  capz_test::expect_corrupt_naming(capz_test::relabelled(b, 6, 0), {"before format 7.0", "ANLG"});
}

TEST(AnalogRepeat, GivenViconZerowireThenCapz7AndTheC3DComesBackByteForByte) {
  const std::string src = capz_test::shared_data_or_skip("c3d/c3dorg/sample_32/vicon_zerowire.c3d");
  if (src.empty()) return;
  capz_test::TempDir dir("capz_analog_repeat");
  const std::string capz = dir.file("z.capz"), back = dir.file("z.c3d");
  const auto c = capz_test::run_command(
      CAPZ_CLI, "compress -q --lossless '" + src + "' -o '" + capz + "'", dir.file("c.txt"));
  ASSERT_EQ(c.status, 0) << c.out;
  const std::string stream = capz_test::file_text(capz);
  ASSERT_GT(stream.size(), 11u);
  // FORMAT.md 11.3, in the 9.0 every take with analog channels is written as (9.1, 9.2).
  EXPECT_EQ(static_cast<int>(static_cast<uint8_t>(stream[9])), kFormat9.major);
  const auto d = capz_test::run_command(CAPZ_CLI, "decompress -q '" + capz + "' -o '" + back + "'",
                                        dir.file("d.txt"));
  ASSERT_EQ(d.status, 0) << d.out;
  EXPECT_TRUE(capz_test::file_text(back) == capz_test::file_text(src));
  // The analog windows shrink by more than a quarter with the repeat lists.
  const Take t = read_take(src);
  const size_t S = static_cast<size_t>(t.analog.samples_per_frame);
  const size_t n = t.analog.values.size() / t.analog.channels;
  const std::vector<uint8_t> with =
      encode_analog_window(t.analog.values.data(), n, t.analog.channels, analog_hints(t), S);
  const std::vector<uint8_t> without =
      encode_analog_window(t.analog.values.data(), n, t.analog.channels, analog_hints(t), 0);
  EXPECT_LT(with.size() * 4, without.size() * 3);
}

}  // namespace
}  // namespace capz
