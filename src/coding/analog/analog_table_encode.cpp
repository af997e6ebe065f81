// A rank channel's value table written (docs/FORMAT.md 11.2, 11.7): the gaps of its entries'
// ordered patterns, or the lattice coding where that is smaller; the reader is analog_table.cpp.
#include <algorithm>
#include <cmath>
#include <cstdint>

#include "capz/error.h"
#include "coding/analog/analog_repr.h"
#include "coding/analog/analog_round.h"
#include "coding/analog/analog_scaled.h"
#include "coding/analog/analog_table.h"
#include "coding/entropy.h"

namespace capz {
namespace analog {

namespace {

using namespace table;

// A value table coded against a lattice (FORMAT.md 11.7): the step, the first entry, then an
// entropy-coded block of each later entry's (m, d). Empty when some entry does not fit (d or
// the prediction out of range). The step: a least-squares line through the entries at
// k = round((v - v0) / gap) (refine_fit). Also empty once the coding is known to take at least
// `bound` bytes (it cannot be the smallest then).
std::vector<uint8_t> lattice_table(const std::vector<double>& t, bool f32, double gap,
                                   size_t bound) {
  if (!(gap > 0) || !std::isfinite(gap)) return {};
  double step = gap, offset = t[0];
  refine_fit(t, &step, &offset);
  if (!(step > 0) || !std::isfinite(step)) return {};
  IntEncoder enc(2);
  // round_half_away of each quotient, mostly without a division (the same results).
  const QuotientRounder round_quotient(step);
  for (size_t i = 1; i < t.size(); ++i) {
    const double q = round_quotient(t[i] - t[i - 1]);  // std::round's result
    const uint32_t m0 = q > 0 && q < 1e9 ? static_cast<uint32_t>(q) : 0;
    // The nearest number of steps, or one either side when that leaves a smaller error in the
    // ordered space: next to zero, where float32 patterns are dense, the nearest can land on the
    // other side of zero, billions of patterns away.
    uint32_t m = m0;
    int64_t d = 0;
    uint64_t best = UINT64_MAX;
    for (uint32_t mm : {m0, m0 + 1, m0 - 1}) {
      if (best == 0) break;            // no other count can have a smaller error
      if (mm == UINT32_MAX) continue;  // m0 - 1 of m0 = 0
      const double p = lattice_next(t[i - 1], mm, step, f32);
      if (!std::isfinite(p)) continue;
      const int64_t dd = static_cast<int64_t>(table_ordered(t[i], f32) - table_ordered(p, f32));
      const uint64_t a = dd < 0 ? 0 - static_cast<uint64_t>(dd) : static_cast<uint64_t>(dd);
      if (a < best) {
        best = a;
        m = mm;
        d = dd;
      }
    }
    if (best >= (uint64_t{1} << 30)) return {};
    // The step, the first entry and a byte of block size come before the block's bytes.
    if (enc.cursor().bytes_out() + 17 >= bound) return {};
    enc.put(m, 0);
    enc.put_signed(static_cast<int32_t>(d), 1);
  }
  const std::vector<uint8_t> block = enc.finish();
  ByteWriter w;
  w.f64(step);
  w.u64(table_ordered(t[0], f32));
  w.varint(block.size());
  w.bytes(block);
  return std::move(w.buffer());
}

// The smallest of the lattice codings from three gaps between entries: the smallest, the median,
// and the smallest of at least half the median. They differ when entries lie off the lattice:
// in PiG's float32 EMG tables two entries are 15 float32 units apart (1/5000 of the step) and
// others a fraction of a step off, so only the median gap is the step; a lattice of the smallest
// gap codes every entry as thousands of steps, 4-5 times the bytes. A coding of `bound` bytes
// or more is never the smallest: then, or with no lattice, the result is empty.
std::vector<uint8_t> lattice_table(const std::vector<double>& t, bool f32, size_t bound) {
  if (t.size() < 2) return {};
  std::vector<double> gaps;
  gaps.reserve(t.size() - 1);
  for (size_t i = 1; i < t.size(); ++i)
    if (t[i] - t[i - 1] > 0) gaps.push_back(t[i] - t[i - 1]);
  if (gaps.empty()) return {};
  const double smallest = *std::min_element(gaps.begin(), gaps.end());
  std::nth_element(gaps.begin(), gaps.begin() + gaps.size() / 2, gaps.end());
  const double median = gaps[gaps.size() / 2];
  double robust = median;
  for (double g : gaps)
    if (g >= median / 2 && g < robust) robust = g;
  std::vector<double> tries = {smallest};
  if (median != smallest) tries.push_back(median);
  if (robust != smallest && robust != median) tries.push_back(robust);
  std::vector<uint8_t> best;
  for (double g : tries) {
    std::vector<uint8_t> c = lattice_table(t, f32, g, best.empty() ? bound : best.size());
    if (!c.empty() && (best.empty() || c.size() < best.size())) best = std::move(c);
  }
  return best;
}

}  // namespace

void write_value_table(const std::vector<double>& table, ByteWriter* w) {
  w->varint(table.size());
  const bool f32 = std::all_of(table.begin(), table.end(), is_float32);
  // The entries as gaps of their ordered patterns; in 8.x streams the lattice coding instead
  // when it is smaller (FORMAT.md 11.7).
  ByteWriter plain;
  uint64_t prev = 0;
  for (size_t i = 0; i < table.size(); ++i) {
    const uint64_t o = table_ordered(table[i], f32);
    if (i == 0)
      plain.u64(o);
    else
      plain.varint(o - prev - 1);
    prev = o;
  }
  const std::vector<uint8_t> lat = lattice_table(table, f32, plain.size());
  const bool use_lattice = !lat.empty() && lat.size() < plain.size();
  w->u8(static_cast<uint8_t>((f32 ? 1 : 0) | (use_lattice ? 2 : 0)));
  w->bytes(use_lattice ? lat : plain.buffer());
}

}  // namespace analog
}  // namespace capz
