// The channel headers of an analog window (unit tests): each channel's kind byte and layout
// fields, read as a 9.2 window reads them (docs/FORMAT.md 4.2.2, 9.2, 9.4, 9.6; earlier windows'
// headers read the same).
#pragma once

#include <cstddef>
#include <cstdint>
#include <vector>

#include "coding/analog/analog_hold.h"
#include "coding/analog/analog_interp.h"
#include "coding/analog/analog_repr.h"
#include "coding/bytes.h"

namespace capz_test {

struct ChannelHeader {
  uint8_t kind_byte = 0;
  capz::analog::Interp interp;  // period 0: none
  capz::analog::Hold hold;      // period 0: none
};

// The C channel headers of window payload p of n rows.
inline std::vector<ChannelHeader> channel_headers(const std::vector<uint8_t>& p, size_t n,
                                                  size_t C) {
  capz::ByteReader in(p.data(), p.size(), "headers");
  in.u8();  // the window's version
  const size_t h = static_cast<size_t>(in.varint());
  const uint8_t* start = in.bytes(h);
  capz::ByteReader head(start, h, "headers");
  std::vector<ChannelHeader> out(C);
  capz::analog::HeaderRules rules;  // a 9.2 window's, without repeat lists
  rules.lattice = rules.interp = rules.hold = rules.share = true;
  capz::analog::HeaderState state;
  for (ChannelHeader& c : out) {
    c.kind_byte = start[head.offset()];
    capz::analog::KeptRows kept;
    capz::analog::read_repr_header(&head, n, rules, &state, &kept);
    c.interp = kept.interp;
    c.hold = kept.hold;
  }
  return out;
}

}  // namespace capz_test
