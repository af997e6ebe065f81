// The encoder's side of held analog samples (docs/FORMAT.md 11.5): the search for a channel's
// period and phase, its kept samples and its field written; the decoder is analog_hold.cpp.
#include <algorithm>
#include <vector>

#include "coding/analog/analog_hold.h"
#include "coding/analog/analog_repeat.h"
#include "coding/analog/analog_repr.h"

namespace capz {
namespace analog {

using namespace hold;

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

void write_hold(const Hold& h, ByteWriter* w) {
  w->varint(h.period);
  w->varint(h.phase);
  write_runs(h.exceptions, w);
}

}  // namespace analog
}  // namespace capz
