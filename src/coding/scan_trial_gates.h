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
// The rings the valid points of [first, first + n) pass from each to the next, counted up the
// table's rings (*up) and down them (*down), each with wrap; returns the valid points.
size_t ring_passes(const std::vector<uint8_t>& valid, const std::vector<scan::Polar>& polar,
                   size_t rings, size_t first, size_t n, size_t* up, size_t* down);
bool walk_worth_trying(const ScanGeometry& g, const std::vector<scan::Polar>& polar, size_t rings,
                       size_t first, size_t n, size_t* passed);

// Whether ring pair frames (flags_f bit 7) are worth a trial on frame [first, first + n): its
// valid points' columns step as they did the last time the same two rings came in a row more
// often than they repeat the previous point's column, by more than an eighth of its points (a
// driver that writes a firing's rings in its own order, its columns apart by ring).
bool pairs_worth_trying(const ScanGeometry& g, const std::vector<scan::Polar>& polar,
                        const scan::State& st, size_t first, size_t n);

// The trial sample of a window (scan_encode.cpp's table trials): the first points of each of its
// first `frames` frames (the sensor's first firings of each sweep, so the second frame's sample
// is predicted from the first one's map of the same azimuths), a quarter of a frame's points, at
// least 16,384 of them. *from: the index of each sample point in g.
ScanGeometry trial_sample(const ScanGeometry& g, size_t frames, std::vector<size_t>* from);

// Whether payload p has ring pair frames (FORMAT.md flags_f bit 7): a window whose payload is
// worth the previous sweep's successors' trial (the more byte's bit 1, scan_encode.cpp).
bool has_pair_frames(const std::vector<uint8_t>& p);

// The raw bits (below each token) of frame [first, first + n)'s Cartesian coding from state st:
// each valid point's x y z against the previous one's (scan_loop.h's code_cartesian); a lower
// bound of that coding's cost (scan_encode.cpp's spherical_wins).
uint64_t cartesian_raw_bits(const scan::State& st, const ScanGeometry& g, size_t first, size_t n);

// The turn of frame [first, first + n) against the previous sweep's map in st (FORMAT.md
// "Turns", the encoder's search, informative there): the column shift under which most of a
// sample of its valid points find their range in the previous sweep's cells, or 0 when no shift
// beats none clearly. polar: the points' places under st's table (valid points only are read).
// *scored (when given) counts the shifts scored besides shift 0.
int32_t find_turn(const ScanGeometry& g, const std::vector<scan::Polar>& polar,
                  const scan::State& st, size_t first, size_t n, size_t* scored = nullptr);

}  // namespace capz
