#include "coding/analog/analog_interp.h"

#include <cmath>

#include "capz/error.h"
#include "coding/analog/analog_repeat.h"
#include "coding/analog/analog_repr.h"
#include "coding/quantiser.h"

namespace capz {
namespace analog {
namespace {

constexpr unsigned kMinPeriod = 2, kMaxPeriod = 15;

// The last anchor of a channel of n >= 1 samples: P * floor((n - 1) / P).
size_t last_anchor(size_t n, unsigned period) {
  return (n - 1) / period * period;
}
// Its interpolable samples: those below the last anchor that are not anchors.
size_t interpolable_count(size_t n, unsigned period) {
  const size_t L = last_anchor(n, period);
  return L - L / period;
}

}  // namespace

namespace {

// interpolate before its float32 rounding (inlined into the encoder's search).
inline double interpolate_unrounded(double xa, double xb, unsigned j, unsigned period) {
  // Separate statements: each product, the sum and the quotient rounded on their own.
  const double wa = xa * static_cast<double>(period - j);
  const double wb = xb * static_cast<double>(j);
  const double sum = wa + wb;
  return sum / static_cast<double>(period);
}

}  // namespace

double interpolate(double xa, double xb, unsigned j, unsigned period, bool f32) {
  const double p = interpolate_unrounded(xa, xb, j, period);
  return f32 ? round_to_float32(p) : p;  // a NaN stays NaN (the callers refuse it)
}

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

size_t interp_kept_count(size_t n, const Interp& in) {
  return n == 0 ? 0 : n - interpolable_count(n, in.period) + in.exceptions.size();
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

void expand_interp(const double* kept, size_t n, const Interp& in, double* col, size_t stride,
                   const std::string& what) {
  if (n == 0) return;
  const unsigned P = in.period;
  const size_t L = last_anchor(n, P);
  size_t k = 0, e = 0;
  // Anchor by anchor: the anchor, the exceptions before the next anchor; then, once the next
  // anchor is known, the interpolations between them.
  for (size_t a = 0; a <= L; a += P) {
    col[a * stride] = kept[k++];
    if (a == L) break;
    const size_t first = e;  // this segment's exceptions: in.exceptions[first .. e)
    while (e < in.exceptions.size() && in.exceptions[e] < a + P)
      col[in.exceptions[e++] * stride] = kept[k++];
    const double xa = col[a * stride], xb = kept[k];  // the next anchor, taken next round
    size_t x = first;
    for (unsigned j = 1; j < P; ++j) {
      if (x < e && in.exceptions[x] == a + j) {
        ++x;
        continue;
      }
      const double p = interpolate(xa, xb, j, P, in.f32);
      if (std::isnan(p)) throw Error(ErrorCode::kCorrupt, what + ": analog interpolation is NaN");
      col[(a + j) * stride] = p;
    }
  }
  for (size_t i = L + 1; i < n; ++i) col[i * stride] = kept[k++];
}

void write_interp(const Interp& in, ByteWriter* w) {
  w->u8(static_cast<uint8_t>(in.period | (in.f32 ? 0x80 : 0)));
  write_runs(in.exceptions, w);
}

Interp read_interp(ByteReader* in, size_t n) {
  Interp out;
  const int q = in->u8();
  const unsigned P = static_cast<unsigned>(q & 15);
  if (P < kMinPeriod || P > kMaxPeriod || (q & 0x70) != 0)
    throw Error(ErrorCode::kCorrupt,
                in->what() + ": bad analog interpolation field " + std::to_string(q));
  out.period = static_cast<uint8_t>(P);
  out.f32 = (q & 0x80) != 0;
  out.exceptions = read_runs(in, n, "interpolation exception");
  const size_t L = n ? last_anchor(n, P) : 0;
  for (uint32_t i : out.exceptions)
    if (i % P == 0 || i >= L)
      throw Error(ErrorCode::kCorrupt, in->what() + ": analog interpolation exception " +
                                           std::to_string(i) + " is not an interpolable sample");
  return out;
}

}  // namespace analog
}  // namespace capz
