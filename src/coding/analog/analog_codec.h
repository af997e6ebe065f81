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
#include "capz/version.h"
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
// every sample back bit for bit (NaN payloads, -0.0, denormals, Inf included). repeat_S: in a
// 7.x stream the analog samples per point frame (nrows a multiple of it), which lets channels
// name repeated frames (FORMAT.md 11.3, analog_repeat.h) where that codes smaller; 0 in earlier
// streams.
// format: the version of the stream the window is in; what the codec does depends on it only
// through the versions below (any version from 4.0 to 7.x codes as 4.0's windows).
// The first version with analog windows in this codec (FORMAT.md 11).
constexpr FormatVersion kAnalogWindowsSince{4, 0};
// Value tables may be coded against a lattice (FORMAT.md 11.7).
constexpr FormatVersion kAnalogLatticeSince{8, 0};
// Float channels use 9.1's predictors and coding, and channels may name interpolated samples
// (FORMAT.md 11.9, 11.4).
constexpr FormatVersion kAnalogFloat9Since{9, 0};
// Integer channels' blocks may be predicted by a constant (FORMAT.md 11.8).
constexpr FormatVersion kAnalogConstantSince{9, 1};
// Channels may name held samples (FORMAT.md 11.5).
constexpr FormatVersion kAnalogHoldSince{9, 2};
// Windows may be of version 1: the bits below integer residuals' tokens through models (9.5).
constexpr FormatVersion kAnalogLowBitsSince{9, 2};
// A kind 2 channel may name the previous kind 2 channel's scaling (9.6).
constexpr FormatVersion kAnalogShareSince{9, 2};
// Windows may be of version 2: integer residuals' tokens relative to their magnitude context
// (9.7).
constexpr FormatVersion kAnalogRelativeSince{9, 3};

std::vector<uint8_t> encode_analog_window(const double* rows, size_t nrows, int channels,
                                          const AnalogHints& hints, size_t repeat_S = 0,
                                          FormatVersion format = kAnalogWindowsSince);

// Fills rows[0 .. nrows * channels). Throws Error(kCorrupt) naming `what` when the payload is
// not a valid window of that shape; memory used is O(nrows * channels + size). repeat_S and
// format: as for encode_analog_window (repeat_S 0: a repeat list is corrupt; a format before
// kAnalogLatticeSince, kAnalogFloat9Since, kAnalogConstantSince, kAnalogHoldSince,
// kAnalogLowBitsSince, kAnalogShareSince or kAnalogRelativeSince: a lattice table, an
// interpolation field, a constant predictor, a hold field, a version 1 window, a shared scaling
// or a version 2 window is corrupt).
void decode_analog_window(const uint8_t* data, size_t size, size_t nrows, int channels,
                          double* rows, const std::string& what, size_t repeat_S = 0,
                          FormatVersion format = kAnalogWindowsSince);

}  // namespace capz
