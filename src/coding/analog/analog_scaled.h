// The scaled representation's fit (docs/FORMAT.md 11.7 kind 2, 16.3), apart from the other
// representations (analog_repr): a channel's samples as k * s + o, exact but for a few
// exceptions.
#pragma once

#include <cstddef>
#include <cstdint>
#include <vector>

#include "coding/analog/analog_repr.h"

namespace capz {
namespace analog {

// The largest |k| a scaled fit takes.
constexpr int64_t kMaxScaledK = int64_t{1} << 24;

// R(k * s + o): the scaled representation's reconstruction (built with -ffp-contract=off, so the
// product is rounded before the sum on every platform).
inline double scaled_value(int64_t k, double s, double o, bool round_f32) {
  const double y = static_cast<double>(k) * s + o;
  return round_f32 ? round_to_float32(y) : y;
}
// The most exceptions a fit of n samples may leave (n / 8).
inline size_t n_max_exc(size_t n) {
  return n / 8;
}
// want - got in float32 units (ordered float bits) when rounding to float32, else in ordered
// double bits; wrapping.
inline int64_t exception_delta(double want, double got, bool f32) {
  if (f32) return static_cast<int64_t>(ordered_f32(want)) - static_cast<int64_t>(ordered_f32(got));
  return static_cast<int64_t>(ordered_bits(bits_of(want)) - ordered_bits(bits_of(got)));
}
// The scaled fit for step s and offset o: the k and the exceptions into *r; false when more than
// max_exc samples would be exceptions or a k is out of range.
bool fit_scaled(const std::vector<double>& v, double s, double o, bool f32, size_t max_exc,
                ChannelRepr* r);
// Least-squares line through (k_i, v_i) with k_i = round((v_i - o) / s), for v non-empty: *s
// and *o become its slope and intercept (unchanged when every k_i is the same), a step and
// offset accurate to far below one float32 unit when the samples are rounded k * s + o.
void refine_fit(const std::vector<double>& v, double* s, double* o);
// The best scaled fit of v (`sorted`: its distinct values, increasing) among the steps the data
// and the hint suggest, the fewest exceptions weighed against the k's spread; false when none
// fits.
bool find_scaled(const std::vector<double>& v, const std::vector<double>& sorted, bool f32,
                 const ChannelHint& hint, ChannelRepr* r);

}  // namespace analog
}  // namespace capz
