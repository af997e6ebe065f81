// Analog windows in unit tests (docs/FORMAT.md 11): round trips that compare every sample's bits,
// damaged payloads that must decode as corrupt, and the channel headers (each channel's kind byte
// and layout fields: 4.2.2, 7.2, 9.2, 9.4, 9.6; read as a 9.2 window reads them unless the caller
// gives other rules).
#pragma once

#include <gtest/gtest.h>

#include <cstddef>
#include <cstdint>
#include <string>
#include <utility>
#include <vector>

#include "capz/error.h"
#include "capz/version.h"
#include "coding/analog/analog_codec.h"
#include "coding/analog/analog_entropy.h"
#include "coding/analog/analog_hold.h"
#include "coding/analog/analog_interp.h"
#include "coding/analog/analog_repr.h"
#include "coding/bytes.h"
#include "coding/entropy.h"

namespace capz_test {

// Row-major rows of equal-length columns.
inline std::vector<double> rows_of(const std::vector<std::vector<double>>& cols) {
  const size_t n = cols[0].size(), C = cols.size();
  std::vector<double> rows(n * C);
  for (size_t i = 0; i < n; ++i)
    for (size_t c = 0; c < C; ++c) rows[i * C + c] = cols[c][i];
  return rows;
}

// Encodes C channels of row-major rows as one window of `format` (with `hints`; repeat lists
// when S > 0, as a stream of S rows a frame codes them), decodes it and expects every sample's
// bits back (NaN payloads, -0.0); returns the payload. A failure names how many samples differ
// and the first.
inline std::vector<uint8_t> window_round_trip(const std::vector<double>& rows, size_t C,
                                              capz::FormatVersion format,
                                              const capz::AnalogHints& hints = {}, size_t S = 0) {
  const size_t n = rows.size() / C;
  const std::vector<uint8_t> p =
      capz::encode_analog_window(rows.data(), n, static_cast<int>(C), hints, S, format);
  std::vector<double> back(rows.size(), 12345.0);
  capz::decode_analog_window(p.data(), p.size(), n, static_cast<int>(C), back.data(), "window", S,
                             format);
  size_t differ = 0, first = 0;
  for (size_t i = 0; i < rows.size(); ++i)
    if (capz::analog::bits_of(back[i]) != capz::analog::bits_of(rows[i]) && differ++ == 0)
      first = i;
  EXPECT_EQ(differ, 0u) << "of " << rows.size() << " samples; the first is sample " << first
                        << " (row " << first / C << ", channel " << first % C << ")";
  return p;
}

// One channel of n rows encoded as a window of `newer` and of `older` (each round-tripped, bits
// compared): {newer's payload size, older's}.
inline std::pair<size_t, size_t> window_sizes(const std::vector<double>& v,
                                              capz::FormatVersion newer,
                                              capz::FormatVersion older) {
  return {window_round_trip(v, 1, newer).size(), window_round_trip(v, 1, older).size()};
}

// A window of one integer channel of n rows made by hand, in `format` (from 9.2 on): the version
// byte and the channel header as the encoder writes them (kind 1, y = k), then a block whose
// coder `code` gets with the low-bit models started and the channel's flags coded (no cascade,
// no reference, LPC order 0); `code` codes the residuals.
template <typename Code>
std::vector<uint8_t> int_window_by_hand(size_t n, capz::FormatVersion format, Code code) {
  std::vector<double> v(n);
  for (size_t i = 0; i < n; ++i) v[i] = static_cast<double>((i * i * 7919) % 30011) - 15000;
  const std::vector<uint8_t> w = capz::encode_analog_window(v.data(), n, 1, {}, 0, format);
  capz::ByteReader in(w.data(), w.size(), "by hand");
  in.u8();  // the window's version
  const size_t head = static_cast<size_t>(in.varint()), at = in.offset();
  EXPECT_EQ(w[at], 1);  // kind 1 (integers), nothing else in the header
  std::vector<uint8_t> out(w.begin(), w.begin() + static_cast<long>(at + head));
  capz::IntEncoder enc(capz::analog::kAnalogContexts);
  capz::analog::start_low_bit_models(&enc);  // as a version 1 or 2 window's coder starts
  capz::IntEncoder::Cursor c = enc.cursor();
  c.put(0, capz::analog::kParamContext);  // no cascade
  c.put(0, capz::analog::kParamContext);  // no reference
  c.put(0, capz::analog::kParamContext);  // LPC order 0
  code(&c);
  enc.commit(c);
  const std::vector<uint8_t> block = enc.finish();
  out.insert(out.end(), block.begin(), block.end());
  return out;
}

// The offset of the first channel's kind byte: after the window version and the header size.
inline size_t first_kind_at(const std::vector<uint8_t>& p) {
  size_t k = 1;
  while (p.at(k) & 0x80) ++k;
  return k + 1;
}

// Decoding p (n rows, C channels, `format`) as the chunk "damaged" throws kCorrupt, its message
// naming the chunk and holding `message` (when not empty); `why` labels the case.
inline void expect_window_corrupt(const std::vector<uint8_t>& p, size_t n, size_t C,
                                  capz::FormatVersion format, const std::string& why,
                                  const std::string& message = "") {
  std::vector<double> out(n * C);
  try {
    capz::decode_analog_window(p.data(), p.size(), n, static_cast<int>(C), out.data(), "damaged", 0,
                               format);
    ADD_FAILURE() << why << ": decoded";
  } catch (const capz::Error& e) {
    EXPECT_EQ(e.code(), capz::ErrorCode::kCorrupt) << why << ": " << e.what();
    EXPECT_NE(std::string(e.what()).find("damaged"), std::string::npos) << e.what();
    if (!message.empty()) {
      EXPECT_NE(std::string(e.what()).find(message), std::string::npos) << why << ": " << e.what();
    }
  }
}

// Every byte of p flipped in turn (XOR 0x5A): each decodes to samples or throws kCorrupt, never
// anything else, and never crashes.
inline void expect_flips_corrupt_or_decoded(const std::vector<uint8_t>& p, size_t n, size_t C,
                                            capz::FormatVersion format) {
  for (size_t i = 0; i < p.size(); ++i) {
    std::vector<uint8_t> q = p;
    q[i] ^= 0x5A;
    std::vector<double> out(n * C);
    try {
      capz::decode_analog_window(q.data(), q.size(), n, static_cast<int>(C), out.data(), "flip", 0,
                                 format);
    } catch (const capz::Error& e) {
      EXPECT_EQ(e.code(), capz::ErrorCode::kCorrupt) << "byte " << i;
    }
  }
}

// What a 9.2 window's channel headers may hold, without repeat lists (S > 0: with them, for
// frames of S rows).
inline capz::analog::HeaderRules rules_9_2(size_t S = 0) {
  capz::analog::HeaderRules rules;
  rules.S = S;
  rules.lattice = rules.interp = rules.hold = rules.share = true;
  return rules;
}

struct ChannelHeader {
  uint8_t kind_byte = 0;
  capz::analog::KeptRows kept;  // the repeat list, interpolation or hold it names, if any
};

// The C channel headers of window payload p of n rows, read under `rules`.
inline std::vector<ChannelHeader> channel_headers(
    const std::vector<uint8_t>& p, size_t n, size_t C,
    const capz::analog::HeaderRules& rules = rules_9_2()) {
  capz::ByteReader in(p.data(), p.size(), "headers");
  in.u8();  // the window's version
  const size_t h = static_cast<size_t>(in.varint());
  const uint8_t* start = in.bytes(h);
  capz::ByteReader head(start, h, "headers");
  std::vector<ChannelHeader> out(C);
  capz::analog::HeaderState state;
  for (ChannelHeader& c : out) {
    c.kind_byte = start[head.offset()];
    capz::analog::read_repr_header(&head, n, rules, &state, &c.kept);
  }
  return out;
}

}  // namespace capz_test
