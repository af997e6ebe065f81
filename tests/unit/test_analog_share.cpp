// A scaled channel's scaling shared with the previous scaled channel of its window
// (docs/FORMAT.md 11.7, format 9.2): channels stored with one step and offset write them once,
// the others name them by the kind byte's bit 4; a channel with another scaling writes its own
// and is named after; below 9.2, and with no earlier scaled channel, the bit is corrupt; Walk1's
// force channels, whose least-squares steps differ in their last bits, share one but for one.
#include <gtest/gtest.h>

#include <cstring>
#include <random>

#include "analog_window.h"
#include "capz/error.h"
#include "capz/io.h"
#include "coding/analog/analog_codec.h"
#include "coding/analog/analog_repr.h"
#include "coding/bytes.h"
#include "test_util.h"

namespace capz {
namespace {

using analog::Kind;

// Each channel's kind byte, as a 9.2 payload's header gives them.
std::vector<uint8_t> kind_bytes(const std::vector<uint8_t>& p, size_t n, size_t C) {
  std::vector<uint8_t> out;
  for (const capz_test::ChannelHeader& h : capz_test::channel_headers(p, n, C))
    out.push_back(h.kind_byte);
  return out;
}

// C channels of float32(k * step) (k a seeded walk), channel-major, as rows.
std::vector<double> scaled_rows(size_t n, const std::vector<double>& steps, uint32_t seed) {
  std::mt19937 rng(seed);
  std::normal_distribution<double> d(0, 40);
  const size_t C = steps.size();
  std::vector<double> rows(n * C);
  for (size_t c = 0; c < C; ++c) {
    double k = 1000;
    for (size_t i = 0; i < n; ++i) {
      k += std::round(d(rng));
      rows[i * C + c] = static_cast<double>(static_cast<float>(k * steps[c]));
    }
  }
  return rows;
}

std::vector<uint8_t> round_trip(const std::vector<double>& rows, size_t C, FormatVersion f) {
  return capz_test::window_round_trip(rows, C, f);
}

TEST(AnalogShare, GivenChannelsOfOneScalingThenWrittenOnceAndNamedAfter) {
  const double s = 10.0 / 32768, other = 0.01;
  const std::vector<double> rows = scaled_rows(3000, {s, s, other, other, s}, 3);
  const std::vector<uint8_t> p = round_trip(rows, 5, kAnalogHoldSince);
  const std::vector<uint8_t> kinds = kind_bytes(p, 3000, 5);
  for (uint8_t k : kinds) ASSERT_EQ(k & 7, static_cast<int>(Kind::kScaled));
  EXPECT_EQ(kinds[0] & 16, 0);  // the first writes its scaling
  EXPECT_NE(kinds[1] & 16, 0);  // the same: named
  EXPECT_EQ(kinds[2] & 16, 0);  // another scaling: written
  EXPECT_NE(kinds[3] & 16, 0);  // the same as channel 2
  EXPECT_EQ(kinds[4] & 16, 0);  // channel 0's again, but the previous scaled channel is 3's
  // 9.1 writes every scaling: three more headers of 17 bytes.
  const std::vector<uint8_t> p91 = round_trip(rows, 5, kAnalogConstantSince);
  EXPECT_EQ(kind_bytes(p91, 3000, 5)[1] & 16, 0);
}

void expect_corrupt(const std::vector<uint8_t>& p, size_t n, size_t C, FormatVersion f,
                    const std::string& message) {
  capz_test::expect_window_corrupt(p, n, C, f, message, message);
}

TEST(AnalogShare, GivenBit4WithKind2WhereItCannotBeThenCorrupt) {
  const std::vector<double> rows = scaled_rows(500, {0.01}, 5);
  std::vector<uint8_t> p = round_trip(rows, 1, kAnalogHoldSince);
  const size_t k = capz_test::first_kind_at(p);
  ASSERT_EQ(p[k], static_cast<int>(Kind::kScaled));
  p[k] |= 16;  // "the previous scaling", with none before: the 17 bytes then read as more fields
  expect_corrupt(p, 500, 1, kAnalogHoldSince, "analog scaling shared with no earlier channel");
  p[0] = 0;  // as a 9.1 window (version 0): bit 4 with kind 2 is unknown there
  expect_corrupt(p, 500, 1, kAnalogConstantSince, "unknown analog channel kind");
}

TEST(AnalogShare, GivenWalk1ThenItsForceChannelsShareOneScaling) {
  const std::string path =
      capz_test::shared_data_or_skip("c3d/c3dorg/sample_00/Motion Analysis Corporation/Walk1.c3d");
  if (path.empty()) return;
  const Take t = read_take(path);
  const size_t C = static_cast<size_t>(t.analog.channels), n = t.analog.values.size() / C;
  const std::vector<uint8_t> p92 = encode_analog_window(
      t.analog.values.data(), n, t.analog.channels, analog_hints(t), 0, kAnalogHoldSince);
  std::vector<double> back(t.analog.values.size());
  decode_analog_window(p92.data(), p92.size(), n, t.analog.channels, back.data(), "walk1", 0,
                       kAnalogHoldSince);
  EXPECT_EQ(std::memcmp(back.data(), t.analog.values.data(), back.size() * 8), 0);
  const std::vector<uint8_t> kinds = kind_bytes(p92, n, C);
  ASSERT_EQ(C, 18u);
  size_t named = 0;
  for (uint8_t k : kinds) named += (k & 7) == static_cast<int>(Kind::kScaled) && (k & 16);
  // Of the 17 channels after the first, 16 name the previous scaling (measured with 410e443's
  // encoder; before 9.6 each wrote its own, and 7 of the 18 fits differed from 10/32768 in their
  // last bits). Channel 5 writes its own: channels 0-4 share channel 0's least-squares fit (a
  // step 1.5e-14 above 10/32768 relatively, offset -9.3e-18), which leaves channel 5 exceptions,
  // while 10/32768 itself fits it exactly; channels 6-17 then name that.
  EXPECT_GE(named, 16u);
}

}  // namespace
}  // namespace capz
