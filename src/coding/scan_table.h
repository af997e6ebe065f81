// The scan encoder's laser table inference (docs/FORMAT.md "Scans (format 1.1)").
#pragma once

#include <cstddef>
#include <vector>

#include "coding/scan_shared.h"

namespace capz {

class ByteWriter;

namespace scan {

// What the tables of every azimuth step share, found once per window: the rings, and per ring
// its cone and its valid points' azimuths (in point order); the azimuth step found in the data;
// every valid point's ring and range (Polar::column left 0).
struct RingFit {
  std::vector<std::vector<double>> phi;  // per ring
  std::vector<float> slope, z0;          // per ring
  double step = 0;                       // radians; 0 when none was found
  double quantum = 0;        // the azimuths' own step (radians, positive), 0 when none was found
  std::vector<Polar> polar;  // per point
  // The sensor's range step, when one is found (FORMAT.md "range units"): per ring the grid
  // units of one step, and per point its range in steps (else both empty).
  std::vector<double> unit, offset;
  std::vector<int32_t> steps;
  float bow = 0;  // the cones' bow (Table::bow), 0 when none is found
  // The firing's base on the quantum's table (Table::fire_turn, share), when found
  // (fit_shares, scan_shares_encode.cpp; else 0 and empty).
  float fire_turn = 0;
  std::vector<float> share;
  double reach = 0;  // the largest range of the points, grid units
  // The firing's slots in their place (Table::slots, slot), when found (fit_shares; else 0 and
  // empty).
  uint32_t slots = 0;
  std::vector<uint8_t> slot;
  bool flipped = false;  // its rings numbered from the top down (flip_rings)
  size_t rings() const { return phi.size(); }
};
// What fit_rings and placed_rings find on one window (g and hints) before they fit anything: the
// cones' bow and the rings, from the ring field and from the elevations (the costly part: a
// window's encoder asks for both rings more than once, scan_encode.cpp). Kept here by the first
// call given it, taken from here by the later ones; empty until then. Valid for that g and those
// hints only.
struct FoundRings {
  bool bow_known = false, field_known = false, elevations_known = false;
  float bow = 0;
  size_t field_rings = 0, elevation_rings = 0;  // 0: none found
  std::vector<uint32_t> field, elevations;      // per point
  std::vector<double> peaks;  // the elevations' peaks (radians under the bow), when found
};
// Without `units` the range step is not looked for (a caller that codes no payload with it);
// without `shares` neither are the firing's base and slots (fit_shares: a caller whose tables
// are never the quantum's, such as the point order's). Without `ring_field` the rings are found
// from the elevations even when hints has a ring field.
// found: g's and hints' FoundRings, or null.
RingFit fit_rings(const ScanGeometry& g, const ScanHints& hints, bool units = true,
                  bool shares = true, bool ring_field = true, FoundRings* found = nullptr);
// The rings fit_rings gives g's points (its RingFit::polar's rings: 0 for a gap), found the same
// way but nothing else fitted; the number of rings, 0 when none are found.
size_t placed_rings(const ScanGeometry& g, const ScanHints& hints, bool ring_field,
                    std::vector<uint32_t>* ring, FoundRings* found = nullptr);
// The rings of points 0, stride, 2 stride ... of g by the nearest of `peaks` (an earlier
// window's FoundRings::peaks) to their elevation under g's bow (kept in found when not null):
// *ring per point taken, and *has whether it has an elevation (valid, not too far, rho above 0).
// Returns the number of rings (peaks).
size_t peak_rings(const ScanGeometry& g, const ScanHints& hints, const std::vector<double>& peaks,
                  size_t stride, FoundRings* found, std::vector<uint32_t>* ring,
                  std::vector<uint8_t>* has);
// Whether the rings fit_rings finds from g's elevations differ from its ring field's (hints.ring,
// not empty), both found once in *found (when not null; kept there for the fits). With ws (when
// not null and remembering) the peaks of a window whose rings were the same are kept in
// ws->ring_peaks and tried first on the next window's points (scan_rings_encode.cpp).
bool rings_differ(const ScanGeometry& g, const ScanHints& hints, FoundRings* found,
                  ScanWorkspace* ws);
// Whether g's valid points, in their order, pass many rings a point going up the rings of `fit`
// (kWalkFlags, scan_trial_gates.h: the ring walk is not tried) and few going down (under
// kDownwardFlags): a driver that writes each firing's rings from the top one down, as most
// Hesai drivers do (scan_rings_encode.cpp).
constexpr size_t kDownwardFlags = 2;
bool rings_run_downward(const ScanGeometry& g, const RingFit& fit);
// Numbers fit's rings the other way, K - 1 - k (per ring values and g's valid points' rings):
// the same table read from the top ring down, so that rings_run_downward's rings run up.
void flip_rings(const ScanGeometry& g, RingFit* fit);
// The geometry rings a decoder finds in `payload`, coded from g's points under the rings of
// `fit` (FORMAT.md predictor 13; scan_rings_encode.cpp).
std::vector<uint16_t> payload_rings(const ScanGeometry& g, const RingFit& fit,
                                    const std::vector<uint8_t>& payload);
// Every point's place under a table (place_points): its ring, column and range, and on a table
// with slots its firing's base and turn (else `fire` is empty).
struct Placement {
  std::vector<Polar> polar;
  std::vector<Fire> fire;
};

// Fits the firing's turn and the rings' shares of it on the azimuths' quantum (r->quantum > 0),
// from g's points in order; kept in r only when the firing's base predicts more columns
// exactly than the ring's lead on the point before.
void fit_shares(const ScanGeometry& g, RingFit* r);
// Each of the first n points' firing's base and turn (p->fire, from p->polar) on a table with
// slots, the firings split per frame as the decoder splits them (scan_shares_encode.cpp).
void fire_points(const ScanGeometry& g, const Table& t, size_t n, Placement* p);
// The azimuth step found in each ring's azimuths sorted (positive), not in point order: a
// driver that writes a ring's points out of firing order (pandar64: columns in a shuffled
// pattern) makes the point-order step a multiple of the sensor's. 0 when none is found.
double sorted_step(const RingFit& r);

// The table of a window's points and every valid point's place under it (*placed); an
// empty table (no rings) when none can be inferred. The azimuth step is the one found in the
// data divided by step_divisor (finer columns for sensors whose azimuths are not on one step),
// or with step_divisor 0 the azimuths' quantum r.quantum, with the column's third candidate
// (Table::turn).
// With `units` (and r.unit found) the table's ranges count the sensor's range steps.
Table table_for(const ScanGeometry& g, const RingFit& r, double step_divisor, bool units,
                Placement* placed);
// table_for in two steps: the table alone (its per-ring fit, the costly part), then *placed
// (resized to n) for points [0, n) under it, so an encoder trying a table on a window's first
// frames places only those and keeps the table for the whole window.
// twin: a table of r fitted before (or null); when its step is this one's, its azimuth offsets
// (which depend on r and the step only) are taken instead of fitted again.
Table table_fit(const RingFit& r, double step_divisor, bool units, const Table* twin = nullptr);
void place_points(const ScanGeometry& g, const RingFit& r, const Table& t, size_t n,
                  Placement* placed);

// Packs t (FORMAT.md "Packed laser table", units bit 5) when that is smaller than the plain
// table: its values rounded to the packed fields' multiples (so that reach, the largest range
// of the points in grid units, moves by at most 1/128 of a grid step for an angle's rounding).
void pack_table(Table* t, double reach);
// The packed fields of a table pack_table packed (t.pack not empty).
void write_packed_table(const Table& t, ByteWriter* w);

// True when every valid point of points [first, first + n) may be coded spherically.
bool spherical_ok(const ScanGeometry& g, size_t first, size_t n);

}  // namespace scan
}  // namespace capz
