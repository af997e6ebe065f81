// Interpolated analog samples (docs/FORMAT.md 11.4): a channel of a window whose samples between
// anchors (every P-th) are, bit for bit, the linear interpolation of them, except a few. Only
// the anchors, the tail after the last anchor and those exceptions (the *kept* samples) are
// coded; the decoder computes the rest. Only in 9.x streams.
#pragma once

#include <cstddef>
#include <cstdint>
#include <string>
#include <vector>

#include "coding/bytes.h"

namespace capz {
namespace analog {

struct Interp {
  uint8_t period = 0;                // P, 2..15; 0: the channel has no interpolation field
  bool f32 = false;                  // interpolations rounded to float32
  std::vector<uint32_t> exceptions;  // interpolable samples coded anyway, increasing
  bool operator==(const Interp& o) const {
    return period == o.period && f32 == o.f32 && exceptions == o.exceptions;
  }
  bool operator!=(const Interp& o) const { return !(*this == o); }
};

// The interpolation of sample a + j (0 < j < P) from anchors x[a] and x[a + P], as FORMAT.md 11.4
// computes it (binary64 products, sum and quotient, then float32 rounding when f32).
double interpolate(double xa, double xb, unsigned j, unsigned period, bool f32);

// The encoder's choice (FORMAT.md 11.4): periods 2, 3 and 4 over col[0], col[stride], ...
// (n samples), the one with the fewest exceptions when they are at most 1/16 of its
// interpolable samples and there are at least 8 of those. False (and *out untouched) when
// none qualifies.
bool find_interpolation(const double* col, size_t stride, size_t n, Interp* out);

// The number of kept samples of a channel of n samples with interpolation `in`.
size_t interp_kept_count(size_t n, const Interp& in);
// The kept samples (anchors, tail and exceptions, in order) of col[0], col[stride], ...
std::vector<double> interp_kept(const double* col, size_t stride, size_t n, const Interp& in);
// Writes the channel's n samples to col[0], col[stride], ... from its kept samples; throws
// Error(kCorrupt) naming `what` when an interpolation is NaN.
void expand_interp(const double* kept, size_t n, const Interp& in, double* col, size_t stride,
                   const std::string& what);

// The field of FORMAT.md 11.4 (q, then the exception runs), and its reader for a channel of n
// samples; the reader throws Error(kCorrupt) for a bad q or an exception that is not
// interpolable.
void write_interp(const Interp& in, ByteWriter* w);
Interp read_interp(ByteReader* in, size_t n);

// What the encoder's search (analog_interp_encode.cpp) and the decoder (analog_interp.cpp) share.
namespace interp {

inline constexpr unsigned kMinPeriod = 2, kMaxPeriod = 15;

// The last anchor of a channel of n >= 1 samples: P * floor((n - 1) / P).
inline size_t last_anchor(size_t n, unsigned period) {
  return (n - 1) / period * period;
}
// Its interpolable samples: those below the last anchor that are not anchors.
inline size_t interpolable_count(size_t n, unsigned period) {
  const size_t L = last_anchor(n, period);
  return L - L / period;
}

// interpolate before its float32 rounding (inlined into the encoder's search).
inline double interpolate_unrounded(double xa, double xb, unsigned j, unsigned period) {
  // Separate statements: each product, the sum and the quotient rounded on their own.
  const double wa = xa * static_cast<double>(period - j);
  const double wb = xb * static_cast<double>(j);
  const double sum = wa + wb;
  return sum / static_cast<double>(period);
}

}  // namespace interp

}  // namespace analog
}  // namespace capz
