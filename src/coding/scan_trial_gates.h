// Cheap tests of whether a frame is worth one of the scan encoder's costlier trials
// (scan_encode.cpp): the ring walk and ring pair frames (docs/FORMAT.md "Scan geometry
// payload"). Encoder only.
#pragma once

#include <cstddef>
#include <vector>

#include "coding/scan_geometry.h"
#include "coding/scan_shared.h"

namespace capz {

// Whether the ring walk is worth a trial on frame [first, first + n): its valid points' rings
// run upward, as in firing order, so that the walk's flags (*passed: the rings passed, which is
// the walk's flags but the repeat flags) stay under kWalkFlags a point. Rings in a driver's
// firing permutation or in blocks (most files' own order) never pay the walk, and a long walk
// costs time.
constexpr size_t kWalkFlags = 8;
bool walk_worth_trying(const ScanGeometry& g, const std::vector<scan::Polar>& polar, size_t rings,
                       size_t first, size_t n, size_t* passed);

// Whether ring pair frames (flags_f bit 7) are worth a trial on frame [first, first + n): its
// valid points' columns step as they did the last time the same two rings came in a row more
// often than they repeat the previous point's column, by more than an eighth of its points (a
// driver that writes a firing's rings in its own order, its columns apart by ring).
bool pairs_worth_trying(const ScanGeometry& g, const std::vector<scan::Polar>& polar,
                        const scan::State& st, size_t first, size_t n);

// The turn of frame [first, first + n) against the previous sweep's map in st (FORMAT.md
// "Turns", the encoder's search, informative there): the column shift under which most of a
// sample of its valid points find their range in the previous sweep's cells, or 0 when no shift
// beats none clearly; with the points of the sample that matched under it, and the sample's
// size. polar: the points' places under st's table (valid points only are read).
struct TurnFound {
  int32_t turn = 0;
  uint32_t top = 0;
  size_t sampled = 0;
};
TurnFound find_turn(const ScanGeometry& g, const std::vector<scan::Polar>& polar,
                    const scan::State& st, size_t first, size_t n);
// The move of frame [first, first + n) under its turn (FORMAT.md "Moves", the encoder's
// search): the move (dx, dy, 0) under which the most of a sample of the frame's valid points are
// predicted by the previous sweep's map moved or not, starting from `guess` (the frame before's
// move); zero when none beats no move clearly. per_metre: grid units a metre (the search's
// spacing and reach).
scan::Move find_move(const ScanGeometry& g, const scan::State& st, size_t first, size_t n,
                     int32_t turn, const scan::Move& guess, double per_metre);
// Frame f's turn and move (f > 0, a frame tried spherically; else none) set in *st, its map
// recast for the move, and both kept in (*turns)[f] and (*moves)[f] (sized for f already):
// the move is looked for (per_metre > 0) when the turn's best matches at most three quarters
// of its sample.
void line_up(const ScanGeometry& g, const std::vector<scan::Polar>& polar, bool spherical, size_t f,
             size_t first, size_t n, double per_metre, scan::State* st, std::vector<int32_t>* turns,
             std::vector<scan::Move>* moves);

}  // namespace capz
