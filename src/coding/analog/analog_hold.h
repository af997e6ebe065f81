// Held analog samples (docs/FORMAT.md 11.5): a channel of a window written by sample and hold from
// a sensor at a lower rate changes only at one phase of a period. Only the samples at that phase
// (the anchors, and sample 0) and the few held samples that change anyway (exceptions) are its
// *kept* samples; the decoder copies every other sample from the one before it. Only in 9.2 and
// later streams.
#pragma once

#include <cstddef>
#include <cstdint>
#include <vector>

#include "coding/bytes.h"

namespace capz {
namespace analog {

struct Hold {
  uint32_t period = 0;               // P, 2..65535; 0: the channel has no hold field
  uint32_t phase = 0;                // 0..P-1: anchors are 0 and the i with i mod P = phase
  std::vector<uint32_t> exceptions;  // held samples coded anyway, increasing
  bool operator==(const Hold& o) const {
    return period == o.period && phase == o.phase && exceptions == o.exceptions;
  }
  bool operator!=(const Hold& o) const { return !(*this == o); }
};

// The encoder's choice (FORMAT.md 11.5) over col[0], col[stride], ... (n samples): the period is
// the most common distance between samples whose bit pattern differs from the previous one's,
// the phase their most common residue; kept when the changes at other residues are at most 1/16
// of the held samples and there are at least 8 of those. False (and *out untouched) otherwise.
bool find_hold(const double* col, size_t stride, size_t n, Hold* out);

// The number of kept samples of a channel of n samples held as `h`.
size_t hold_kept_count(size_t n, const Hold& h);
// The kept samples (anchors and exceptions, in order) of col[0], col[stride], ...
std::vector<double> hold_kept(const double* col, size_t stride, size_t n, const Hold& h);
// Writes the channel's n samples to col[0], col[stride], ... from its kept samples.
void expand_hold(const double* kept, size_t n, const Hold& h, double* col, size_t stride);

// The field of FORMAT.md 11.5 (P, phase, then the exception runs), and its reader for a channel
// of n samples; the reader throws Error(kCorrupt) for a bad period or phase, or an exception that
// is not a held sample.
void write_hold(const Hold& h, ByteWriter* w);
Hold read_hold(ByteReader* in, size_t n);

// What the encoder's search (analog_hold_encode.cpp) and the decoder (analog_hold.cpp) share.
namespace hold {

inline constexpr uint32_t kMinPeriod = 2, kMaxPeriod = 65535;

// The anchors of a channel of n >= 1 samples: sample 0 and the i in [1, n) with i mod P = phase.
inline size_t anchor_count(size_t n, uint32_t period, uint32_t phase) {
  const size_t at_phase =
      phase == 0 ? (n - 1) / period : (phase < n ? (n - 1 - phase) / period + 1 : 0);
  return 1 + at_phase;
}

}  // namespace hold

}  // namespace analog
}  // namespace capz
