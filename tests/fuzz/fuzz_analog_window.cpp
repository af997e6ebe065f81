// Fuzz target: the format 4.0 analog window codec (src/coding/analog/, FORMAT.md 11), and its
// repeated frames of 7.0 (FORMAT.md 11.3). Byte 0 picks the mode, bytes 1-2 the shape (channels
// 1..16, rows 1..2048). With bit 7 of the mode the window is a 7.x one: S = 1 + bits 3-6 samples
// a frame, rows rounded up to whole frames (and in odd modes some frames of some channels made
// copies of the previous frame, as input bytes say); without it, a window of 4.x-6.x. With bit 7
// of byte 2 the window is an 8.x one (FORMAT.md 11.7: rank tables against a lattice), and with bit
// 6 of the mode or bit 7 of byte 1 too a 9.x one (FORMAT.md 11.9: the float coder's predictors
// 2-5; 9.2: interpolated samples: with bit 6 of the mode, in odd modes every second row is made
// the mean of its neighbours, so that the encoder finds them), a 9.1 one when bit 0 of byte 2 is
// set too (FORMAT.md 11.8: integer blocks predicted by a constant), and a 9.2 one when bit 1 of
// byte 2 is set as well (FORMAT.md 11.10: windows of version 1, whose integer residuals code the
// bits below their tokens through models; 9.4: held samples: without bit 6 of the mode, in odd
// modes the even channels are made to change only at the rows i = 0 and i mod P = 1, P = 2 + bits
// 4-6 of byte 1, and held in between), and a 9.3 one when bit 2 of byte 2 is set as well
// (FORMAT.md 11.10: windows of version 2, whose integer residuals' tokens are coded relative to
// their context):
//   mode even: the rest is an ANLG body; decoding must return or throw capz::Error, and a body
//     that decodes must re-encode to one that decodes to the same bits;
//   mode odd: the rest are sample bits (as int16 counts, float32 or float64 values, by mode),
//     which must round-trip bit for bit.
#include <cstddef>
#include <cstdint>
#include <cstring>
#include <vector>

#include "capz/error.h"
#include "coding/analog/analog_codec.h"
#include "coding/analog/analog_interp.h"
#include "fuzz_common.h"

namespace {

void round_trip(const std::vector<double>& rows, size_t nrows, int channels, size_t S,
                capz::FormatVersion v) {
  const std::vector<uint8_t> enc =
      capz::encode_analog_window(rows.data(), nrows, channels, capz::AnalogHints(), S, v);
  std::vector<double> back(rows.size());
  capz::decode_analog_window(enc.data(), enc.size(), nrows, channels, back.data(), "re-encoded", S,
                             v);
  CAPZ_FUZZ_CHECK(std::memcmp(back.data(), rows.data(), rows.size() * 8) == 0);
}

}  // namespace

extern "C" int LLVMFuzzerTestOneInput(const uint8_t* data, size_t size) {
  if (size < 3) return 0;
  const uint8_t mode = data[0];
  const int channels = 1 + (data[1] & 15);
  size_t nrows = 1 + ((static_cast<size_t>(data[1] >> 4) | size_t{data[2]} << 4) & 2047);
  const size_t S = (mode & 0x80) ? 1 + ((mode >> 3) & 15) : 0;
  const bool v8 = data[2] & 0x80;
  const bool v9 = v8 && ((mode & 0x40) || (data[1] & 0x80));
  const bool v91 = v9 && (data[2] & 1);
  const bool v92 = v91 && (data[2] & 2);
  const bool v93 = v92 && (data[2] & 4);
  const capz::FormatVersion v = v93   ? capz::kAnalogRelativeSince
                                : v92 ? capz::kAnalogHoldSince
                                : v91 ? capz::kAnalogConstantSince
                                : v9  ? capz::kAnalogFloat9Since
                                : v8  ? capz::kAnalogLatticeSince
                                      : capz::kAnalogWindowsSince;
  const size_t hold_P = 2 + ((data[1] >> 4) & 7);
  if (S) nrows = (nrows + S - 1) / S * S;
  data += 3;
  size -= 3;
  std::vector<double> rows(nrows * static_cast<size_t>(channels));
  if (mode % 2 == 0) {
    try {
      capz::decode_analog_window(data, size, nrows, channels, rows.data(), "fuzz ANLG", S, v);
    } catch (const capz::Error&) {
      return 0;
    }
    round_trip(rows, nrows, channels, S, v);
    return 0;
  }
  // Sample bits from the input, repeated to fill the window; the kind of value by mode.
  if (size == 0) return 0;
  const size_t width = mode % 6 == 1 ? 2 : mode % 6 == 3 ? 4 : 8;
  for (size_t i = 0; i < rows.size(); ++i) {
    uint8_t b[8] = {0};
    for (size_t k = 0; k < width; ++k) b[k] = data[(i * width + k) % size];
    if (width == 2) {
      int16_t v;
      std::memcpy(&v, b, 2);
      rows[i] = v;
    } else if (width == 4) {
      float f;
      std::memcpy(&f, b, 4);
      rows[i] = static_cast<double>(f);
    } else {
      std::memcpy(&rows[i], b, 8);
    }
  }
  const size_t nch = static_cast<size_t>(channels);
  for (size_t f = 1; S && f < nrows / S; ++f)
    for (size_t c = 0; c < nch; ++c)
      if (data[f % size] & (1u << (c % 8)))
        for (size_t j = 0; j < S; ++j)
          rows[(f * S + j) * nch + c] = rows[((f - 1) * S + j) * nch + c];
  if (v9 && (mode & 0x40))  // every second row the mean of its neighbours (float32-rounded for
    for (size_t i = 1; i + 1 < nrows; i += 2)  // float32 modes)
      for (size_t c = 0; c < nch; ++c)
        rows[i * nch + c] = capz::analog::interpolate(rows[(i - 1) * nch + c],
                                                      rows[(i + 1) * nch + c], 1, 2, width == 4);
  if (v92 && !(mode & 0x40)) {  // sample and hold at period P, phase 1, on the even channels
    for (size_t i = 1; i < nrows; ++i)
      if (i % hold_P != 1)
        for (size_t c = 0; c < nch; c += 2) rows[i * nch + c] = rows[(i - 1) * nch + c];
  }
  round_trip(rows, nrows, channels, S, v);
  return 0;
}
