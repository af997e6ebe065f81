// The analog window codec: lossless coding of one window of analog samples
// (docs/format-drafts/analog.md). It ties the stages together: representation per channel
// (analog_repr.h), then for integer-like channels LPC (analog_lpc.h) and the adaptive cascade
// (analog_cascade.h), for float channels the float predictor (analog_float.h), and one
// entropy-coded block for all the per-sample numbers (analog_entropy.h).
#pragma once

#include <cstddef>
#include <cstdint>
#include <string>
#include <vector>

#include "capz/take.h"
#include "coding/analog/analog_repr.h"

namespace capz {

// What the file says about the channels (ANALOG:SCALE x GEN_SCALE, OFFSET). Hints only change
// which representations the encoder tries; the payload never depends on them being right, and
// the decoder does not need them. `channel` may be shorter than the channel count.
struct AnalogHints {
  std::vector<analog::ChannelHint> channel;
};

// Hints from the take's C3D parameters: per channel the stored-value step ANALOG:SCALE x
// GEN_SCALE and the offset -ANALOG:OFFSET (none for other sources or unreadable parameters).
AnalogHints analog_hints(const Take& t);

// rows: nrows x channels doubles, row-major (capz::Analog::values). Lossless: decoding gives
// every sample back bit for bit (NaN payloads, -0.0, denormals, Inf included). repeat_S: the
// analog samples per point frame (nrows a multiple of it), which lets channels name repeated
// frames (FORMAT.md 7.2, analog_repeat.h) where that codes smaller; 0: no channel does.
std::vector<uint8_t> encode_analog_window(const double* rows, size_t nrows, int channels,
                                          const AnalogHints& hints, size_t repeat_S = 0);

// Fills rows[0 .. nrows * channels). Throws Error(kCorrupt) naming `what` when the payload is
// not a valid window of that shape; memory used is O(nrows * channels + size). repeat_S: as for
// encode_analog_window (0: a repeat list is corrupt).
void decode_analog_window(const uint8_t* data, size_t size, size_t nrows, int channels,
                          double* rows, const std::string& what, size_t repeat_S = 0);

}  // namespace capz
