#include "coding/analog/analog_hold.h"

#include <string>

#include "capz/error.h"
#include "coding/analog/analog_repeat.h"
#include "coding/analog/analog_repr.h"

namespace capz {
namespace analog {
namespace {

constexpr uint32_t kMinPeriod = 2, kMaxPeriod = 65535;

// The anchors of a channel of n >= 1 samples: sample 0 and the i in [1, n) with i mod P = phase.
size_t anchor_count(size_t n, uint32_t period, uint32_t phase) {
  const size_t at_phase =
      phase == 0 ? (n - 1) / period : (phase < n ? (n - 1 - phase) / period + 1 : 0);
  return 1 + at_phase;
}

}  // namespace

bool find_hold(const double* col, size_t stride, size_t n, Hold* out) {
  if (n < 9) return false;
  // Counted first without storing: most channels change at most samples and stop here.
  const size_t limit = n / 2 + n / 32;
  size_t changes = 0;
  for (size_t i = 1; i < n; ++i)
    if (bits_of(col[i * stride]) != bits_of(col[(i - 1) * stride]) && ++changes > limit)
      return false;
  if (changes < 2) return false;
  std::vector<uint32_t> at;
  at.reserve(changes);
  for (size_t i = 1; i < n; ++i)
    if (bits_of(col[i * stride]) != bits_of(col[(i - 1) * stride]))
      at.push_back(static_cast<uint32_t>(i));
  // The most common distance between consecutive changes, 2 .. kMaxPeriod (the smallest of
  // equals), then the most common residue of the changes mod it.
  std::vector<uint32_t> dist(std::min<size_t>(n, kMaxPeriod + 1), 0);
  for (size_t k = 1; k < at.size(); ++k) {
    const uint32_t d = at[k] - at[k - 1];
    if (d < dist.size()) ++dist[d];
  }
  uint32_t P = 0;
  for (uint32_t d = kMinPeriod; d < dist.size(); ++d)
    if (dist[d] > (P ? dist[P] : 0)) P = d;
  if (P == 0) return false;
  std::vector<uint32_t> residue(P, 0);
  for (uint32_t i : at) ++residue[i % P];
  uint32_t phase = 0;
  for (uint32_t r = 1; r < P; ++r)
    if (residue[r] > residue[phase]) phase = r;
  const size_t held = n - anchor_count(n, P, phase);
  const size_t exceptions = at.size() - residue[phase];
  if (held < 8 || exceptions > held / 16) return false;
  Hold h;
  h.period = P;
  h.phase = phase;
  h.exceptions.reserve(exceptions);
  for (uint32_t i : at)
    if (i % P != phase) h.exceptions.push_back(i);
  *out = std::move(h);
  return true;
}

size_t hold_kept_count(size_t n, const Hold& h) {
  return n == 0 ? 0 : anchor_count(n, h.period, h.phase) + h.exceptions.size();
}

std::vector<double> hold_kept(const double* col, size_t stride, size_t n, const Hold& h) {
  std::vector<double> out;
  out.reserve(hold_kept_count(n, h));
  size_t e = 0;
  uint32_t r = 0;  // i mod P
  for (size_t i = 0; i < n; ++i, r = r + 1 == h.period ? 0 : r + 1) {
    const bool exc = e < h.exceptions.size() && h.exceptions[e] == i;
    e += exc;
    if (i == 0 || r == h.phase || exc) out.push_back(col[i * stride]);
  }
  return out;
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

void write_hold(const Hold& h, ByteWriter* w) {
  w->varint(h.period);
  w->varint(h.phase);
  write_runs(h.exceptions, w);
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
