#include "coding/analog/analog_table.h"

#include <algorithm>
#include <cmath>
#include <cstdint>

#include "capz/error.h"
#include "coding/analog/analog_repr.h"
#include "coding/analog/analog_round.h"
#include "coding/analog/analog_scaled.h"
#include "coding/entropy.h"

namespace capz {
namespace analog {

namespace {

// A table's entries in the table's ordered space: 32-bit float patterns when f32, else 64-bit.
uint64_t table_ordered(double v, bool f32) {
  return f32 ? ordered_f32(v) : ordered_bits(bits_of(v));
}
double from_table_ordered(uint64_t o, bool f32) {
  return f32 ? from_ordered_f32(static_cast<uint32_t>(o)) : from_bits(from_ordered_bits(o));
}
// The lattice prediction of an entry from the previous one (FORMAT.md 11.7): prev + m * step in
// binary64, two separate operations, rounded to float32 for a float32 table.
double lattice_next(double prev, uint32_t m, double step, bool f32) {
  const double d = static_cast<double>(m) * step;
  const double p = prev + d;
  return f32 ? round_to_float32(p) : p;
}

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

// A value table coded against a lattice (FORMAT.md 11.7), m entries (at most n, the channel's
// samples), each above the previous in the table's ordered space.
void read_lattice_table(ByteReader* in, uint64_t m, size_t n, bool f32,
                        std::vector<double>* table) {
  if (m < 2 || m > n)
    throw Error(ErrorCode::kCorrupt, in->what() + ": bad analog lattice table size");
  const double step = in->f64();
  if (!(step > 0) || !std::isfinite(step))
    throw Error(ErrorCode::kCorrupt, in->what() + ": bad analog lattice step");
  uint64_t prev = in->u64();
  if (f32 && prev > 0xFFFFFFFFu)
    throw Error(ErrorCode::kCorrupt, in->what() + ": analog float32 table entry out of range");
  const uint64_t size = in->count(1, "analog lattice table block");
  const uint8_t* block = in->bytes(static_cast<size_t>(size));
  IntDecoder dec(block, static_cast<size_t>(size), 2, in->what());
  table->reserve(static_cast<size_t>(m));
  table->push_back(from_table_ordered(prev, f32));
  for (uint64_t i = 1; i < m; ++i) {
    const uint32_t k = dec.get(0);
    const int32_t d = dec.get_signed(1);
    const double p = lattice_next(table->back(), k, step, f32);
    if (!std::isfinite(p))
      throw Error(ErrorCode::kCorrupt, in->what() + ": analog lattice prediction not finite");
    const uint64_t o = table_ordered(p, f32) + static_cast<uint64_t>(static_cast<int64_t>(d));
    if (f32 ? (o > 0xFFFFFFFFu || o <= prev) : (o <= prev))
      throw Error(ErrorCode::kCorrupt,
                  in->what() + ": analog lattice table entries not increasing");
    table->push_back(from_table_ordered(o, f32));
    prev = o;
  }
  if (!dec.at_end())
    throw Error(ErrorCode::kCorrupt, in->what() + ": analog lattice table has bytes left over");
}

}  // namespace

void write_value_table(const std::vector<double>& table, bool lattice_tables, ByteWriter* w) {
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
  const std::vector<uint8_t> lat =
      lattice_tables ? lattice_table(table, f32, plain.size()) : std::vector<uint8_t>();
  const bool use_lattice = !lat.empty() && lat.size() < plain.size();
  w->u8(static_cast<uint8_t>((f32 ? 1 : 0) | (use_lattice ? 2 : 0)));
  w->bytes(use_lattice ? lat : plain.buffer());
}

std::vector<double> read_value_table(ByteReader* in, size_t n, bool lattice_tables) {
  const uint64_t m = in->varint();
  if (m == 0) throw Error(ErrorCode::kCorrupt, in->what() + ": empty analog value table");
  const int flag = in->u8();
  if (flag > (lattice_tables ? 3 : 1))
    throw Error(ErrorCode::kCorrupt, in->what() + ": bad analog table flag");
  const bool f32 = flag & 1;
  std::vector<double> table;
  if (flag & 2) {
    read_lattice_table(in, m, n, f32, &table);
    return table;
  }
  if (m > in->remaining())
    throw Error(ErrorCode::kCorrupt,
                in->what() + ": analog value table cannot fit in the bytes left");
  uint64_t prev = 0;
  for (uint64_t i = 0; i < m; ++i) {
    const uint64_t o = i == 0 ? in->u64() : prev + in->varint() + 1;
    if (f32 && o > 0xFFFFFFFFu)
      throw Error(ErrorCode::kCorrupt, in->what() + ": analog float32 table entry out of range");
    table.push_back(from_table_ordered(o, f32));
    prev = o;
  }
  return table;
}

}  // namespace analog
}  // namespace capz
