// The scan geometry encoder's coding of a window's frames under one table (scan_frames_encode.cpp):
// per frame the cheaper of spherical and Cartesian coding, the spherical trials recorded and
// replayed. scan_encode.cpp chooses the tables. Encoder only.
#pragma once

#include <cstddef>
#include <cstdint>
#include <memory>
#include <vector>

#include "coding/entropy.h"
#include "coding/scan_geometry.h"
#include "coding/scan_shared.h"
#include "coding/scan_table.h"
#include "coding/scan_trial_sinks.h"

namespace capz {
namespace scan_frames {

using scan_sinks::AltSym;
using scan_sinks::Room;
using scan_sinks::Sym;
using scan_sinks::Tally;

// A frame's Cartesian estimate from a state: the same under every table (Cartesian coding reads
// only st.last and st.last_bits), so kept for the next table's pass over the window.
struct CartesianEstimate {
  bool known = false;
  int32_t last[3] = {0, 0, 0};
  int last_bits[3] = {0, 0, 0};
  double bits = 0;
  uint64_t symbols = 0;
  bool same_state(const scan::State& st) const {
    return known && std::equal(last, last + 3, st.last) &&
           std::equal(last_bits, last_bits + 3, st.last_bits);
  }
};

// A frame's spherical trial: its symbols (the first `syms` of sym_room), the hypotenuse's
// alternatives to the second of x y, and their tallies.
struct Trial {
  Room<Sym> sym_room;
  Room<AltSym> alt_room;
  size_t syms = 0;
  Tally tally, azimuth, hypot;
  const Sym* begin() const { return sym_room.data(); }
  const Sym* end() const { return sym_room.data() + syms; }
};

// Scratch of the per-frame choice, kept across frames and tables.
struct Scratch {
  std::vector<int32_t> q;
  std::vector<uint8_t> v;
  Trial trial, walk_trial;  // the spherical trial of the frame; with the ring walk
  int walk = -1;            // the window's choice of the ring walk (code_chosen): -1 not made yet
  int pairs = -1;           // the window's choice of ring pair frames (code_chosen), every table's
  // Coding a trial sample (sample_size) of a fit whose rings were numbered from the top down
  // (scan::flip_rings): the ring walk is not tried on the sample, only on the window.
  bool no_walk_trial = false;
  std::vector<double> log_t, log_c;     // Tally::estimate's prefix sums
  std::vector<CartesianEstimate> cart;  // per frame of the window
  std::vector<int8_t> spherical_ok;     // per frame: scan::spherical_ok, -1 not yet known
  std::shared_ptr<scan::SweepMaps> maps = std::make_shared<scan::SweepMaps>();   // every table's
  std::shared_ptr<scan::SweepMaps> spare = std::make_shared<scan::SweepMaps>();  // a kept coding's
  size_t record_limit = ScanWorkspace::kRecordLimit;
  bool successors = false;  // a window before kept the previous sweep's successors
};

// A window's coding under one table, frame by frame: the block so far, the state after it and
// the frames' flags. (The encoder points into itself and the state at its table: neither moves.)
struct Coding {
  Coding(const scan::Table& t, std::shared_ptr<scan::SweepMaps> maps)
      : enc(new IntEncoder(scan::kContexts)), st(new scan::State(t, std::move(maps))) {
    enc->add_bit_models();
  }
  std::unique_ptr<IntEncoder> enc;
  std::unique_ptr<scan::State> st;
  std::vector<uint8_t> flags;
  std::vector<int32_t> turns;    // per frame its turn (FORMAT.md "Turns")
  size_t frames = 0, first = 0;  // the frames coded, their points
  int walk = -1;                 // its ring walk choice (Scratch::walk)
};

// Codes frames c->frames .. to - 1 of g: per frame the cheaper of spherical and Cartesian coding.
void code_frames(const ScanGeometry& g, const scan::Placement& placed, size_t to, Coding* c,
                 Scratch* s);
// The payload of c's frames (g's first c->frames) under c's table; c's block is finished.
std::vector<uint8_t> finish(const ScanGeometry& g, Coding* c);
// finish(g, c)'s size, c left as it is.
size_t finished_size(const ScanGeometry& g, const Coding& c);
// The payload under one table.
std::vector<uint8_t> encode_with(const ScanGeometry& g, const scan::Table& t,
                                 const scan::Placement& placed, Scratch* s);

}  // namespace scan_frames
}  // namespace capz
