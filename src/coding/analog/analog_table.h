// The value table of a rank channel (kind 3; docs/FORMAT.md 11.2 and 11.7): the channel's
// distinct values in increasing order, which its ranks index. A stage of the analog coder's
// channel header (analog_repr): the entry count, the table flag, then the entries, either as
// gaps of their ordered patterns (4.2.2) or, in 8.x streams, against a lattice (8.2: each entry
// the previous one plus whole steps, the step counts and the corrections entropy-coded).
#pragma once

#include <cstddef>
#include <vector>

#include "coding/analog/analog_repr.h"
#include "coding/bytes.h"

namespace capz {
namespace analog {

// Writes `table` (non-empty, strictly increasing); the lattice coding where it is smaller than
// the gaps.
void write_value_table(const std::vector<double>& table, ByteWriter* w);
// Reads a table of a channel of n coded samples; corrupt (naming in->what()) when it is empty,
// not increasing, larger than the bytes left can hold, or of an unknown flag.
std::vector<double> read_value_table(ByteReader* in, size_t n);

// What the writer (analog_table_encode.cpp) and the reader (analog_table.cpp) share.
namespace table {

// A table's entries in the table's ordered space: 32-bit float patterns when f32, else 64-bit.
inline uint64_t table_ordered(double v, bool f32) {
  return f32 ? ordered_f32(v) : ordered_bits(bits_of(v));
}
inline double from_table_ordered(uint64_t o, bool f32) {
  return f32 ? from_ordered_f32(static_cast<uint32_t>(o)) : from_bits(from_ordered_bits(o));
}
// The lattice prediction of an entry from the previous one (FORMAT.md 11.7): prev + m * step in
// binary64, two separate operations, rounded to float32 for a float32 table.
inline double lattice_next(double prev, uint32_t m, double step, bool f32) {
  const double d = static_cast<double>(m) * step;
  const double p = prev + d;
  return f32 ? round_to_float32(p) : p;
}

}  // namespace table

}  // namespace analog
}  // namespace capz
