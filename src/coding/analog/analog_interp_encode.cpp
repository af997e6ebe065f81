// The encoder's side of interpolated analog samples (docs/FORMAT.md 11.4): the search for a
// channel's period, its kept samples and its field written; the decoder is analog_interp.cpp.
#include <cmath>
#include <utility>
#include <vector>

#include "coding/analog/analog_interp.h"
#include "coding/analog/analog_repeat.h"
#include "coding/analog/analog_repr.h"
#include "coding/quantiser.h"

namespace capz {
namespace analog {

using namespace interp;

namespace {

// True when no period 2-4 can be found_interpolation's pick, whatever the samples' float32
// flag: each exceeds its exceptions' budget with samples that neither rounding (float32 or
// none) interpolates, counted from the start. A channel that is not interpolated (most) fails
// each period within about its budget's samples, so the flag's pass over every sample is then
// skipped. False decides nothing.
bool no_period_can_fit(const double* col, size_t stride, size_t n) {
  for (unsigned P = 2; P <= 4; ++P) {
    const size_t L = last_anchor(n, P);
    const size_t interpolable = interpolable_count(n, P);
    if (interpolable < 8) continue;
    const size_t max_exc = interpolable / 16;
    size_t misses = 0;
    for (size_t a = 0; a < L && misses <= max_exc; a += P) {
      const double xa = col[a * stride], xb = col[(a + P) * stride];
      for (unsigned j = 1; j < P; ++j) {
        const double x = col[(a + j) * stride];
        // interpolate(..., false) and (..., true): the same quotient, then float32 rounding
        const double p = interpolate_unrounded(xa, xb, j, P), p32 = round_to_float32(p);
        misses += (std::isnan(p) || !same_bits(p, x)) && (std::isnan(p32) || !same_bits(p32, x));
      }
    }
    if (misses <= max_exc) return false;
  }
  return true;
}

}  // namespace

bool find_interpolation(const double* col, size_t stride, size_t n, Interp* out) {
  if (n < 3) return false;
  if (no_period_can_fit(col, stride, n)) return false;
  bool f32 = true;
  for (size_t i = 0; i < n && f32; ++i) f32 = is_float32(col[i * stride]);
  Interp best;
  for (unsigned P = 2; P <= 4; ++P) {
    const size_t L = last_anchor(n, P);
    const size_t interpolable = interpolable_count(n, P);
    if (interpolable < 8) continue;
    const size_t max_exc = interpolable / 16;
    Interp in;
    in.period = static_cast<uint8_t>(P);
    in.f32 = f32;
    bool ok = true;
    for (size_t a = 0; a < L && ok; a += P) {
      const double xa = col[a * stride], xb = col[(a + P) * stride];
      for (unsigned j = 1; j < P; ++j) {
        const double p = interpolate(xa, xb, j, P, f32);
        if (std::isnan(p) || !same_bits(p, col[(a + j) * stride])) {
          in.exceptions.push_back(static_cast<uint32_t>(a + j));
          if (in.exceptions.size() > max_exc) {
            ok = false;
            break;
          }
        }
      }
    }
    if (ok && (best.period == 0 || in.exceptions.size() < best.exceptions.size()))
      best = std::move(in);
  }
  if (best.period == 0) return false;
  *out = std::move(best);
  return true;
}

std::vector<double> interp_kept(const double* col, size_t stride, size_t n, const Interp& in) {
  std::vector<double> out;
  out.reserve(interp_kept_count(n, in));
  const size_t L = n ? last_anchor(n, in.period) : 0;
  size_t e = 0;
  for (size_t i = 0; i < n; ++i) {
    const bool exc = e < in.exceptions.size() && in.exceptions[e] == i;
    e += exc;
    if (i % in.period == 0 || i > L || exc) out.push_back(col[i * stride]);
  }
  return out;
}

void write_interp(const Interp& in, ByteWriter* w) {
  w->u8(static_cast<uint8_t>(in.period | (in.f32 ? 0x80 : 0)));
  write_runs(in.exceptions, w);
}

}  // namespace analog
}  // namespace capz
