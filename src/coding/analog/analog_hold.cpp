#include "coding/analog/analog_hold.h"

#include <string>

#include "capz/error.h"
#include "coding/analog/analog_repeat.h"
#include "coding/analog/analog_repr.h"

namespace capz {
namespace analog {

using namespace hold;

size_t hold_kept_count(size_t n, const Hold& h) {
  return n == 0 ? 0 : anchor_count(n, h.period, h.phase) + h.exceptions.size();
}

void expand_hold(const double* kept, size_t n, const Hold& h, double* col, size_t stride) {
  size_t k = 0, e = 0;
  uint32_t r = 0;  // i mod P
  for (size_t i = 0; i < n; ++i, r = r + 1 == h.period ? 0 : r + 1) {
    const bool exc = e < h.exceptions.size() && h.exceptions[e] == i;
    e += exc;
    // A copy of the bits (NaN payloads kept), not a floating-point operation.
    col[i * stride] = i == 0 || r == h.phase || exc ? kept[k++] : col[(i - 1) * stride];
  }
}

Hold read_hold(ByteReader* in, size_t n) {
  Hold out;
  const uint64_t P = in->varint();
  if (P < kMinPeriod || P > kMaxPeriod)
    throw Error(ErrorCode::kCorrupt,
                in->what() + ": analog hold period " + std::to_string(P) + " outside 2 .. 65535");
  const uint64_t phase = in->varint();
  if (phase >= P)
    throw Error(ErrorCode::kCorrupt, in->what() + ": analog hold phase " + std::to_string(phase) +
                                         " not below its period " + std::to_string(P));
  out.period = static_cast<uint32_t>(P);
  out.phase = static_cast<uint32_t>(phase);
  out.exceptions = read_runs(in, n, "hold exception");
  for (uint32_t i : out.exceptions)
    if (i == 0 || i % out.period == out.phase)
      throw Error(ErrorCode::kCorrupt, in->what() + ": analog hold exception " + std::to_string(i) +
                                           " is not a held sample");
  return out;
}

}  // namespace analog
}  // namespace capz
