// A rank channel's value table read (docs/FORMAT.md 11.2, 11.7); the writer is
// analog_table_encode.cpp.
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

using namespace table;

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

std::vector<double> read_value_table(ByteReader* in, size_t n) {
  const uint64_t m = in->varint();
  if (m == 0) throw Error(ErrorCode::kCorrupt, in->what() + ": empty analog value table");
  const int flag = in->u8();
  if (flag > 3) throw Error(ErrorCode::kCorrupt, in->what() + ": bad analog table flag");
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
