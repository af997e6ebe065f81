// Lossy analog channels: the encoder's quantiser (analog_quant.h, docs/FORMAT.md 16.3).
#include "coding/analog/analog_quant.h"

#include <cmath>
#include <limits>

namespace capz {
namespace analog {

namespace {

constexpr double kMaxK = 16777216.0;  // 2^24, what kScaled holds

bool is_f32(double v) {
  return bits_of(round_to_float32(v)) == bits_of(v);
}

}  // namespace

ChannelHint quantise_channel(double* col, size_t stride, size_t n, const ChannelBound& b,
                             const ChannelHint& hint) {
  ChannelHint out = hint;
  out.lattice_step = 0;
  out.lattice_offset = 0;
  if (!(b.bound > 0) || !(b.factor > 0) || !std::isfinite(b.factor) || n < 2) return out;
  const double stored = b.bound / b.factor;  // the bound in stored units
  if (!(stored > 0) || !std::isfinite(stored)) return out;
  bool f32 = true;
  for (size_t i = 0; i < n && f32; ++i)
    if (std::isfinite(col[i * stride])) f32 = is_f32(col[i * stride]);
  double s0 = 0, o0 = 0, s = 0, o = 0;
  if (sample_lattice(col, stride, n, hint, &s0, &o0) && s0 > 0) {
    // Stay on the channel's own lattice: every (2m + 1)-th point of it, the one nearest the
    // stored zero among them, moves a sample by at most m steps.
    const double m = std::floor(stored / s0);
    if (m < 1) return out;  // the bound is finer than the channel's step: lossless already
    s = (2 * m + 1) * s0;
    o = std::isfinite(b.offset) ? o0 + std::round((b.offset - o0) / s0) * s0 : o0;
  } else {
    s = 2 * stored;
    o = std::isfinite(b.offset) ? b.offset : 0.0;
  }
  if (!(s > 0) || !std::isfinite(s) || !std::isfinite(o)) return out;
  for (size_t i = 0; i < n; ++i) {
    double& v = col[i * stride];
    if (!std::isfinite(v)) continue;
    const double k = std::round((v - o) / s);
    if (!(std::fabs(k) <= kMaxK)) continue;
    double w = k * s + o;  // as kScaled reconstructs it (-ffp-contract=off)
    if (f32) w = round_to_float32(w);
    if (b.integers && (w != std::floor(w) || w < b.lo || w > b.hi)) continue;
    if (!b.integers && f32 && !std::isfinite(static_cast<float>(w))) continue;
    if (within_bound(w, v, b)) v = w;
  }
  out.lattice_step = s;
  out.lattice_offset = o;
  return out;
}

void quantise_window(double* rows, size_t nrows, const std::vector<ChannelBound>& bounds,
                     std::vector<ChannelHint>* hints) {
  const size_t C = bounds.size();
  if (hints->size() < C) hints->resize(C);
  for (size_t c = 0; c < C; ++c)
    if (bounds[c].bound > 0)
      (*hints)[c] = quantise_channel(rows + c, C, nrows, bounds[c], (*hints)[c]);
}

}  // namespace analog
}  // namespace capz
