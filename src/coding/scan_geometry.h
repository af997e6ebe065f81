// The scan geometry coder (docs/FORMAT.md "Scans (format 1.1)"): a lossless coder of one
// window's grid integers for frames of their own size, in file order.
//
// A window is a run of frames; frame f holds counts[f] points, each three int32 grid integers
// (x y z) and a validity flag (a NaN point of the source is a gap: valid 0, kept in place, its
// integers ignored and decoded as 0). The coder predicts each valid point from the points
// decoded before it (FORMAT.md: previous point, the point one firing back on its ring, the
// previous sweep's point at the same ring and column, the laser cone of its ring) and codes the
// residuals with the adaptive range coder (coding/entropy.h).
#pragma once

#include <cstddef>
#include <cstdint>
#include <functional>
#include <memory>
#include <string>
#include <vector>

namespace capz {

// One window's grid integers, frames of their own size, in file order.
struct ScanGeometry {
  std::vector<uint32_t> counts;  // points per frame
  std::vector<int32_t> q;        // total x 3 grid integers (x y z per point)
  std::vector<uint8_t> valid;    // total; 0 = gap (a NaN point)
  // The fine shift k of a raster window at a bound (FORMAT.md "Raster frames"): the integers
  // count the stream's grid step times 2^-k. 0 for every other payload.
  int fine = 0;
  // The decoder's: some frame is an octree frame (FORMAT.md "Octree frames"), which a stream
  // allows only with HEAD bit 6 (the caller's check).
  bool octree = false;
  // The decoder's, when asked: each point's geometry ring (FORMAT.md predictor 13: the ring k a
  // spherical frame's step 1 decoded for a valid point, in a frame without cells or raster),
  // kNoRing for the others. Empty when not asked for.
  static constexpr uint16_t kNoRing = 0xFFFF;
  std::vector<uint16_t> ring;

  size_t total() const { return valid.size(); }
};

// What the encoder may use besides the integers (never stored as such: each hint only steers
// the encoder's choices, which the payload carries).
struct ScanHints {
  // The source's ring / laser / channel number of every point (total entries), or empty: the
  // encoder then infers the rings from the points' elevations.
  std::vector<uint32_t> ring;
  // The source's coordinates (total x 3, any unit), or empty: without a ring field the rings
  // are found from the elevations of these, finer than the grid's (at a coarse grid a near
  // point's elevation is too uncertain to tell neighbouring lasers apart).
  std::vector<float> xyz;
  // The source's distance of every point from the sensor (a `distance` or `range` field; the
  // unit of xyz), or empty: the encoder then takes the distance from the origin.
  std::vector<float> distance;
  // Grid integers per unit of xyz (the integers are about xyz times this), or 0 when the
  // integers are not a scaled copy of xyz: with it the encoder looks for the sensor's range step
  // (FORMAT.md "Scan geometry payload", range units).
  double grid_per_unit = 0;
  // The bound on a coordinate and the grid's step (both in xyz units; a coordinate decodes as
  // its integer times the step), or 0: the integers are coded exactly. With both, a raster
  // window may code other integers, on a finer grid, within the bound of xyz (FORMAT.md
  // "Raster frames", fine shift); decode the payload for them.
  double bound = 0;
  double step = 0;
  // With a ring field: whether the encoder also codes the rings it finds from the elevations
  // (the smaller payload kept): -1 where those differ from the field's (it fits both to know),
  // 0 never, 1 always (a caller that knows: scan_rings_differ, the same for any order).
  int elevation_rings = -1;
};

namespace scan {
class SweepMaps;  // scan_maps.h
}
// What an encoder may keep from window to window: the ring x column maps (two pairs), up to the
// largest table's cells. Given to each window's encode_scan_geometry, their memory is reused (only
// the cells a window wrote are cleared) instead of allocated and zeroed again. Empty until used.
// A laser table choice of the encoder (its azimuth step divided by `divisor`, ranges in the
// sensor's steps or not) and the bits a point of its trial sample's payload; bits 0: none.
struct ScanChoice {
  double divisor = 0;
  bool units = false;
  double bits = 0;
  double finest = 0;  // the trial's finest table: its divisor (16, or 0 for the quantum's)
};
// remember: the windows are one sequence's, in order: a window's table choice is kept in
// `choice` and tried first on the next window's sample (scan_encode.cpp, sampled_choice), and
// ring_peaks, moving and before below are kept and used.
// every_table: each laser table the encoder tries codes the whole window, the smallest payload
// kept (no trial on the window's first points; for measurements and tests). tables_coded and
// sample_codings: the number of whole-window codings and of trial sample codings so far.
struct ScanWorkspace {
  std::shared_ptr<scan::SweepMaps> maps, spare;
  bool remember = false;
  ScanChoice choice;
  bool every_table = false;
  size_t tables_coded = 0, sample_codings = 0;
  // The most points of a frame whose spherical trials are recorded and replayed; a larger
  // frame's trials are only counted, and the one kept coded again (the same payload; recording
  // takes about 60 bytes a point). Replaying is the cheaper below about 2^18 points (pandar64's
  // 113k-point sweeps took 1.22x the CPU with a limit of 2^16), coding again above (a 600k-point
  // frame 0.93x). Lowered by tests.
  static constexpr size_t kRecordLimit = size_t{1} << 18;
  size_t record_limit = kRecordLimit;
  // The elevation peaks of the last window whose rings from the elevations were its ring field's
  // (the next window's ring check tries them first, scan_encode.cpp); else empty.
  std::vector<double> ring_peaks;
  // Whether a window's second frame did not repeat its first's directions (a spinning sensor's,
  // scan_raster.h's keep_smaller): the windows after it are not tried as raster windows.
  bool moving = false;
  // With remember: the trial sample's payload with units bit 7 over the one without, in the last
  // window where it was tried on the sample (0: none yet).
  double before = 0;
  // With remember: a window kept the previous sweep's successors (the more byte's bit 1), so the
  // later windows are coded with them without a trial (scan_encode.cpp's encode_fitted).
  bool successors = false;
  // With remember: the payload under the rings found from the elevations over the one under the
  // ring field's, in the last window where both were coded (0: none yet), and the windows since
  // then that coded only the ring field's (scan_encode.cpp's encode_geometry).
  double second_ratio = 0;
  size_t second_skipped = 0;
  // After each encode_scan_geometry: when its payload codes other integers than it was given (a
  // raster window at a bound, fine shift above 0), that payload and the integers the decoder gives
  // back from it (x y z per point, 0 at gaps; the coder's own, not decoded again); else empty.
  std::vector<uint8_t> fine_payload;
  std::vector<int32_t> fine_q;
  // After each encode_scan_geometry: its payload and the geometry ring a decoder finds for each
  // point in it (ScanGeometry::ring: FORMAT.md predictor 13), worked out from the coder's fit.
  std::vector<uint8_t> ring_payload;
  std::vector<uint16_t> rings;
};

// The payload of one window. Throws Error(kInvalidArgument) when the shapes disagree.
// ws: a workspace kept across windows, or null (the same bytes either way unless ws->remember).
std::vector<uint8_t> encode_scan_geometry(const ScanGeometry& g, const ScanHints& hints = {},
                                          ScanWorkspace* ws = nullptr);

// Whether the rings the encoder finds from the points' elevations differ from the ring field's
// (hints.ring, not empty): encode_scan_geometry then tries both (encoder side).
bool scan_rings_differ(const ScanGeometry& g, const ScanHints& hints);

// Which table orders the points: one per frame with the azimuth step of each ring's sorted
// azimuths (a driver that writes a ring out of firing order), or the window's as the payload
// infers it (the step from the file's order). kPerFrameByRing: the per-frame table's points ring
// by ring (ring, then column, then range), for the cells of a near sweep (FORMAT.md "Cells with
// counts": their firings keep irregular sets of rings).
enum class ScanOrderTable { kPerFrame, kWindow, kPerFrameByRing };
// --point-order any (FORMAT.md "Points reordered"): the coded order of g's points, indices into
// g (total of them), each frame's own points at its own places: its valid points by column,
// ring and range under the table the encoder infers (the sensor's firing order), the valid
// points off the table in file order, then its gaps. Encoder side (scan_order_encode.cpp).
// by_ring (when not null): with kPerFrame, also the kPerFrameByRing order, from the same fits
// (else left empty).
std::vector<uint32_t> scan_point_order(const ScanGeometry& g, const ScanHints& hints = {},
                                       ScanOrderTable table = ScanOrderTable::kPerFrame,
                                       std::vector<uint32_t>* by_ring = nullptr);

// Decodes a payload of encode_scan_geometry. At most `max_points` points in all (the caller's
// memory bound); throws Error(kCorrupt) naming `what` on any inconsistency.
ScanGeometry decode_scan_geometry(const uint8_t* data, size_t size, const std::string& what,
                                  size_t max_points = size_t{1} << 26);
// The same, the result's q in the memory *space held (taken: *space is left empty); with
// `rings`, the result's ring filled (each point's geometry ring).
ScanGeometry decode_scan_geometry(const uint8_t* data, size_t size, const std::string& what,
                                  size_t max_points, std::vector<int32_t>* space,
                                  bool rings = false);
// As above, a frame at a time: each frame's integers (3 x n, of points first..first + n - 1 of
// the window) and flags go to frame(first, n, q, valid) as soon as they are decoded, q in a
// buffer of one frame reused for the next. The result's q is then empty (its valid holds every
// flag). For callers that need each frame's integers only once (the coordinates). space: memory
// for that buffer, given back in *space (a caller decoding window after window keeps it), or null.
using ScanFrameSink =
    std::function<void(size_t first, size_t n, const int32_t* q, const uint8_t* valid)>;
ScanGeometry decode_scan_geometry(const uint8_t* data, size_t size, const std::string& what,
                                  size_t max_points, const ScanFrameSink& frame,
                                  std::vector<int32_t>* space = nullptr);
// The window's frame counts of a payload (its header's n_f, a split frame's two parts as one:
// FORMAT.md "Split frames"), without decoding the rest; no check beyond the bytes read (the
// counts may be anything a varint holds).
std::vector<uint64_t> scan_frame_counts(const uint8_t* data, size_t size, const std::string& what);
// The fine shift k of a payload (its header's; ScanGeometry::fine), without decoding the rest:
// a payload with k > 0 codes other integers than the encoder was given.
int scan_fine_shift(const uint8_t* data, size_t size, const std::string& what);

}  // namespace capz
