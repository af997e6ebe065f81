// Lossy analog channels (docs/FORMAT.md 16.3), the encoder's stage before the lossless window
// codec: a bounded channel's samples are moved, each by at most its bound, onto a lattice the
// codec then codes as kScaled (analog_repr.h). Nothing here is needed to decode.
#pragma once

#include <cmath>
#include <cstddef>
#include <vector>

#include "coding/analog/analog_repr.h"

namespace capz {
namespace analog {

// What the encoder knows of one channel.
struct ChannelBound {
  double bound = 0;   // in physical units; 0: the channel is lossless
  double factor = 1;  // physical units per stored unit (|ANALOG:SCALE x GEN_SCALE|)
  double offset = 0;  // the stored value of physical zero (ANALOG:OFFSET)
  // The stored values' range: int16 or uint16 storage keep integers within it; float32 storage
  // is within +-FLT_MAX.
  double lo = 0, hi = 0;
  bool integers = false;  // the storage holds integers (int16 / uint16)
};

// True when `w` stands for `v` within the channel's bound: |w - v| * factor <= bound.
inline bool within_bound(double w, double v, const ChannelBound& b) {
  return std::fabs(w - v) * b.factor <= b.bound;
}

// Quantises the n samples col[0], col[stride], ... of a bounded channel in place and returns the
// hint to code them with (lattice_step 0 when the samples are left as they are: a bound finer
// than the channel's own step, or no bound). Non-finite samples, and samples the lattice would
// move out of the bound or the storage range, are left as they are.
ChannelHint quantise_channel(double* col, size_t stride, size_t n, const ChannelBound& b,
                             const ChannelHint& hint);

// Every bounded channel of a window of nrows x bounds.size() samples (row-major), with the hints
// updated for the codec.
void quantise_window(double* rows, size_t nrows, const std::vector<ChannelBound>& bounds,
                     std::vector<ChannelHint>* hints);

}  // namespace analog
}  // namespace capz
