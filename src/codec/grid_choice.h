// Encoder stage: choosing the grid (docs/FORMAT.md 16.1). A first pass over the take (scan_block,
// a block of frames at a time) gathers what the choice depends on; then exactly one of
// lossless_grid, bounded_grid or kg_grid picks the grid, and quantise_window maps each window's
// coordinates onto it.
#pragma once

#include <cstddef>
#include <cstdint>
#include <string>
#include <vector>

#include "capz/codec.h"
#include "capz/stream.h"
#include "codec/grid.h"
#include "coding/scan_geometry.h"

namespace capz {

// What choosing the grid needs to know of every valid sample, gathered in one pass over the
// take (a block of frames at a time, blocks in order). Each field equals what a pass over the
// whole take computes: maxima, minima, all-of flags and in-order sums.
struct TakeScan {
  double max_abs = 0;                                         // largest |coordinate|
  double min_cheb = std::numeric_limits<double>::infinity();  // smallest max(|x|, |y|, |z|)
  std::vector<Grid> candidates;  // lossless grids in order of preference (lossless_candidates)
  std::vector<uint8_t> exact;    // per candidate: every valid coordinate reproduced exactly
  bool lossless = false;         // a lossless target: all_float32 is tracked
  bool all_float32 = true;       // every valid coordinate is a float32 value
  // A -0.0 counts as on a decimal grid (a lossless ragged stream lists its negative zeros,
  // FORMAT.md "Lossless ragged streams").
  bool zeros_listed = false;
  bool words_on_grid = false;  // C3D residual words are point_scale multiples
  bool kg = false;             // accumulate centred_sq
  double centred_sq = 0;       // sum of squared distances to each frame's centroid
  // With kg: the valid coordinates in take order, for the grid search, while they number at
  // most kg_cap (kg_cached turns false, and the vector is freed, past it).
  size_t kg_cap = 0;
  bool kg_cached = false;
  std::vector<double> kg_coords;
  // PCD takes (FORMAT.md 8.3): each point's last valid position (ray_seen: whether it has one),
  // and of the valid samples that moved since it, how many stayed on their ray from the origin.
  bool ray_track = false;
  std::vector<double> ray_last;
  std::vector<uint8_t> ray_seen;
  uint64_t ray_moved = 0, ray_on = 0;
  // FORMAT.md 11.3: per analog channel, the frames f >= 1 of each block (window) whose
  // analog_S samples repeat frame f - 1's bit for bit and are not all one bit pattern.
  size_t analog_S = 0;
  std::vector<size_t> analog_repeats;  // empty without analog
};

// True when the scan found the take's points moving along their rays from the origin, as a
// sensor's pixels or beams do (FORMAT.md 7.1: predictor 10 is then a candidate).
bool on_rays(const TakeScan& s);

// True when the take is an int16 C3D (its coordinates are multiples of POINT:SCALE).
bool c3d_int16(const Take& t);
// The step of the integers `capz decompress` writes for this take (c3d_write.cpp: stored =
// lround(x / scale) with the scale as float32), or 0 when the written values are the decoded
// doubles to within float32 (float C3D, TRC, PCD).
double written_int16_scale(const Take& t);

// An empty scan for take header `hdr` under `opts`. With a KG target, cache_kg_coordinates lets
// the scan keep up to cap_bytes of coordinates for kg_grid.
TakeScan start_scan(const Take& hdr, const CompressOptions& opts);
void cache_kg_coordinates(const Take& hdr, size_t cap_bytes, TakeScan* s);
// Adds frames b (blocks in order) to the scan; throws kInvalidParameter, naming `src`, on a valid
// sample that is not finite. words: the blocks carry C3D residual words (point_scale: the
// take's).
void scan_block(const FrameBlock& b, const std::string& src, bool words, double point_scale,
                TakeScan* s);

// Whether the scan found analog frames repeated often enough to offer repeat lists (FORMAT.md
// 7.2: some channel with at least 2 and at least 10% of the take's `frames`).
bool analog_repeats_worth(const TakeScan& s, size_t frames);

// The first lossless candidate that reproduces every valid coordinate, else float32 or float64
// bits.
Grid lossless_grid(const TakeScan& s);
// A grid whose step bounds every coordinate's error by `bound` (take units), in the decoded take
// and in the file the decoder writes in the source's format. Throws kInvalidParameter when the
// bound is too fine for the coordinates.
Grid bounded_grid(const Take& t, const TakeScan& s, double bound);

// Whether the frame files the decoder writes for t store x y z as float32: .bin frames, PCD and
// PLY frames whose x is 4 bytes (so bounded_grid keeps float32_half_ulp in reserve).
bool float32_frames(const Take& t);

// Half a float32 ulp at magnitudes up to m (m in [2^(e-1), 2^e): 2^(e-25)): how far writing a
// decoded coordinate of magnitude at most m as float32 may move it. bounded_grid keeps that much
// of the bound in reserve for outputs that store float32 coordinates.
double float32_half_ulp(double m);
// The largest grid whose KG error is at or under `kg` percent (bisection on the step). Reads the
// source again in blocks of `block` frames (into *b) unless the scan cached the coordinates.
Grid kg_grid(FrameSource& src, const TakeScan& s, double kg, size_t block, FrameBlock* b);

// The window's integers on grid g (transform output, grid step 0: all zero).
WindowInts quantise_window(const FrameBlock& b, const Grid& g);
// Grid integers per coordinate unit under g (ScanHints::grid_per_unit): 1 / step for a grid,
// step for a decimal grid, 0 for float bits.
double grid_per_unit(const Grid& g);
// A lossy grid of mode 0 (kGrid) gives the scan payload its bound and step (ScanHints::bound,
// ::step: a raster window may then code its points on their rays); any other leaves h as it is.
void bound_hints(const Grid& g, ScanHints* h);

}  // namespace capz
