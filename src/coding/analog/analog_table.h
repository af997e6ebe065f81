// The value table of a rank channel (kind 3; docs/FORMAT.md 11.2 and 11.7): the channel's
// distinct values in increasing order, which its ranks index. A stage of the analog coder's
// channel header (analog_repr): the entry count, the table flag, then the entries, either as
// gaps of their ordered patterns (4.2.2) or, in 8.x streams, against a lattice (8.2: each entry
// the previous one plus whole steps, the step counts and the corrections entropy-coded).
#pragma once

#include <cstddef>
#include <vector>

#include "coding/bytes.h"

namespace capz {
namespace analog {

// Writes `table` (non-empty, strictly increasing); with lattice_tables (an 8.x stream) the
// lattice coding where it is smaller than the gaps.
void write_value_table(const std::vector<double>& table, bool lattice_tables, ByteWriter* w);
// Reads a table of a channel of n coded samples; corrupt (naming in->what()) when it is empty,
// not increasing, larger than the bytes left can hold, or flagged as a lattice table outside
// an 8.x stream.
std::vector<double> read_value_table(ByteReader* in, size_t n, bool lattice_tables);

}  // namespace analog
}  // namespace capz
