// What the TRC residue's encoder (trc_residue_encode.cpp) and decoder (trc_residue.cpp) share
// (docs/FORMAT.md 7, 14.2): the payload's flags and limits, the row model and the fields it
// predicts, and the check of a block against the take.
#pragma once

#include <cstddef>
#include <cstdint>
#include <string>
#include <vector>

#include "capz/error.h"
#include "capz/stream.h"
#include "capz/take.h"
#include "io/text_number.h"

namespace capz {
namespace residue {
namespace trcr {

inline constexpr uint8_t kKindTRC = 2;
// A row's exception: its field count differs from the model's (missing fields are empty, extra
// ones predicted empty), some fields' text differs, its line end differs.
inline constexpr uint8_t kFixFields = 1, kNewEnding = 2, kFieldCount = 4;
inline constexpr uint64_t kMaxExtraFields = 65536;
// Caps on the row model, so a damaged payload cannot make the decoder spell rows of unbounded
// size (a value beyond them stays possible, as an exception).
inline constexpr uint64_t kMaxDecimals = 40, kMaxTrailing = 4096;
inline constexpr size_t kMaxGapText = 64, kMaxEnding = 4096;

// How the window's rows are spelled (see trc_residue.h).
struct RowModel {
  uint64_t time_decimals = 0;
  uint64_t trailing = 0;           // empty fields after the last coordinate
  std::string gap;                 // the text of each of a gap's three fields
  std::string ending;              // line end (and blank lines) after a row's last field
  std::vector<uint64_t> decimals;  // per coordinate column (points x 3)
};

// The fields the model predicts for row k of `b` (frame b.first + k of `t`). `exact` false (an
// archive at a bound): coordinates are printed rounded to the take's TRC decimals.
inline void predict(const RowModel& m, const Take& t, const FrameBlock& b, size_t k,
                    std::vector<std::string>* out, bool exact = true) {
  const size_t r = b.first + k, N = b.points;
  const TRCExtra* x = t.trc.get();
  // At a bound: the most decimals the source printed a coordinate with, which the encoder's
  // grid left room for (its rounding stays within the bound); the model's per-column decimals
  // are only the padding that reproduced the most fields.
  const int bound_decimals = x ? x->decimals : -1;
  out->clear();
  out->push_back(std::to_string(x && x->frame_numbers.size() == t.frames
                                    ? x->frame_numbers[r]
                                    : t.first_frame + static_cast<long>(r)));
  out->push_back(x && x->times.size() == t.frames
                     ? format_decimal(x->times[r], static_cast<int>(m.time_decimals))
                     : std::string());
  for (size_t p = 0; p < N; ++p)
    for (size_t a = 0; a < 3; ++a)
      out->push_back(!b.valid[k * N + p] ? m.gap
                     : exact             ? format_decimal(b.xyz[(k * N + p) * 3 + a],
                                                          static_cast<int>(m.decimals[3 * p + a]))
                             : format_decimal_rounded(b.xyz[(k * N + p) * 3 + a], bound_decimals));
  out->resize(out->size() + m.trailing);
}

inline void check_block(const Take& t, const FrameBlock& b, const std::string& name,
                        ErrorCode code) {
  if (b.points != t.points || b.first > t.frames || b.frames > t.frames - b.first ||
      b.xyz.size() != b.frames * b.points * 3 || b.valid.size() != b.frames * b.points)
    fail(code, name,
         "TRC residue: block of frames " + std::to_string(b.first) + "+" +
             std::to_string(b.frames) + " does not match the take's " + std::to_string(t.frames) +
             " frames x " + std::to_string(t.points) + " points");
}

}  // namespace trcr
}  // namespace residue
}  // namespace capz
