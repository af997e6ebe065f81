#include "coding/analog/analog_interp.h"

#include <cmath>

#include "capz/error.h"
#include "coding/analog/analog_repeat.h"
#include "coding/analog/analog_repr.h"
#include "coding/quantiser.h"

namespace capz {
namespace analog {

using namespace interp;

double interpolate(double xa, double xb, unsigned j, unsigned period, bool f32) {
  const double p = interpolate_unrounded(xa, xb, j, period);
  return f32 ? round_to_float32(p) : p;  // a NaN stays NaN (the callers refuse it)
}

size_t interp_kept_count(size_t n, const Interp& in) {
  return n == 0 ? 0 : n - interpolable_count(n, in.period) + in.exceptions.size();
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
