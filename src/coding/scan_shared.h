// What the scan geometry encoder and decoder share (docs/FORMAT.md "Scans (format 1.1)"): the
// payload's header, the laser table, the deterministic trigonometry and the one coding loop of a
// frame, written once over an "Io" that either codes (encoder), decodes (decoder) or only counts
// bits (the encoder's per-frame mode choice).
//
// Floating-point use: the predictions use IEEE binary64 +, -, *, / and floor only (no libm
// trigonometry, which differs between builds), and the scan sources are compiled without
// fused multiply-add contraction, so every build computes the same predictions.
#pragma once

#include <algorithm>
#include <cmath>
#include <cstddef>
#include <cstdint>
#include <memory>
#include <string>
#include <vector>

#include "coding/entropy.h"
#include "coding/scan_geometry.h"
#include "coding/scan_maps.h"

namespace capz {

class ByteWriter;

namespace scan {

// Frame flags (one byte per frame).
constexpr uint8_t kAllValid = 0, kSomeValid = 1, kNoneValid = 2;  // bits 0-1
constexpr uint8_t kSpherical = 4;                                 // bit 2
constexpr uint8_t kRingWalk = 8;     // bit 3: rings by the walk (FORMAT "Ring walk frames")
constexpr uint8_t kCells = 16;       // bit 4: cells with counts (scan_cells.h)
constexpr uint8_t kRaster = 32;      // bit 5 (scan_raster.h)
constexpr uint8_t kHypot = 64;       // bit 6: the second of x y from the range's hypotenuse
constexpr uint8_t kRingPairs = 128;  // bit 7: ring pair frames (FORMAT "Ring pair frames")
constexpr uint8_t kFrameFlagMask = 7 | kRingWalk | kCells | kRaster | kHypot | kRingPairs;
// An octree frame: bits 2 and 5 together (FORMAT "Octree frames", scan_octree.h).
constexpr uint8_t kOctreeFrame = kSpherical | kRaster;
inline bool octree_frame(uint8_t flags) {
  return (flags & kOctreeFrame) == kOctreeFrame;
}
// An octree frame with bit 3: the near part of a split frame, the next frame its far part
// (FORMAT "Split frames").
constexpr uint8_t kNearPart = kRingWalk;
inline bool near_part(uint8_t flags) {
  return octree_frame(flags) && (flags & kNearPart) != 0;
}

// Limits the decoder enforces (FORMAT.md).
constexpr uint32_t kMaxRings = 1024;
constexpr uint64_t kMaxMapCells = uint64_t{1} << 22;  // rings x columns
// The range units' bounds (FORMAT.md "Scan geometry payload").
constexpr double kMinUnit = 0x1p-20, kMaxUnit = 0x1p20, kMaxOffset = 0x1p30;
// The units byte's bit of the cones' bow, and the bow's bound (FORMAT.md).
constexpr uint8_t kBowBit = 4;
// The units byte's bit of the column's third candidate, the firing's turn (FORMAT.md step 2).
constexpr uint8_t kTurnBit = 16;
// The units byte's bit of the column's fourth candidate, the firing's base (only with kTurnBit),
// and the bounds of its turn and shares (FORMAT.md step 2).
constexpr uint8_t kShareBit = 8;
constexpr double kMaxFireTurn = 65536, kMaxShare = 16;
// The units byte's bit of the packed table, and the bounds of its fields (FORMAT.md "Packed
// laser table"): exponent, bits of a difference, magnitude of an integer.
constexpr uint8_t kPackBit = 32;
constexpr int kMaxPackExponent = 62;
constexpr unsigned kMaxPackBits = 55;
constexpr int64_t kMaxPacked = int64_t{1} << 53;
// The units byte's bit of the firing's slots (only with kTurnBit, not with kShareBit), and the
// bound of its slots per half turn (FORMAT.md step 2).
constexpr uint8_t kSlotBit = 64;
constexpr uint32_t kMaxSlots = 64;
// The units byte's bit of the range's fourth candidate, the ring's range before its last
// (FORMAT.md step 3).
constexpr uint8_t kBeforeBit = 128;
constexpr double kMaxBow = 1;
// The table's `more` byte's bits: the frames' turns (FORMAT.md "Turns"), the previous sweep's
// successors (FORMAT.md "The previous sweep's successors").
constexpr uint8_t kMoreTurns = 1, kMoreSuccessors = 2;
// Coordinates of a spherical frame stay below this in magnitude (so a range fits an int32).
constexpr int64_t kMaxSphericalCoord = int64_t{1} << 29;
constexpr int kMaxFine = 12;  // the raster header's fine shift k (FORMAT.md "Raster frames")

// The laser table: per ring an azimuth offset, a cone slope and a z offset; one azimuth step.
struct Table {
  float step = 0;        // radians per column (nonzero when rings > 0)
  uint32_t columns = 0;  // map columns (the previous sweep's ring x column map), >= 1
  std::vector<float> azimuth0, slope, z0;  // per ring
  // Per ring the grid units of one range step and the range's offset ("units" 1), or both
  // empty: ranges in grid units.
  std::vector<double> unit, offset;
  // The cones' bow: a ring's slope at azimuth phi is slope + bow (1 - cos phi) (0: none).
  float bow = 0;
  bool turn = false;    // the column's third candidate (units bit 4)
  bool before = false;  // the range's fourth candidate (units bit 7)
  // Ring pair frames read the previous sweep's successors (FORMAT.md, the more byte's bit 1).
  bool successors = false;
  // The column's fourth candidate (units bit 3): the firing's turn in columns and per ring its
  // laser's share of it (empty: none).
  float fire_turn = 0;
  std::vector<float> share;
  // Packed (units bit 5): each packed field's exponent E (a0, slope, z0, then unit and offset as
  // the range units have them); empty: the table is plain.
  std::vector<uint8_t> pack;
  // The firing's slots (units bit 6): slots per half turn N (0: none) and per ring its slot.
  uint32_t slots = 0;
  std::vector<uint8_t> slot;
  size_t rings() const { return azimuth0.size(); }
};

// Contexts of the one IntEncoder block.
enum Ctx : int {
  kCtxValid = 0,               // 2: previous point's flag
  kCtxRing = kCtxValid + 2,    // 2: previous ring residual zero or not
  kCtxColumn = kCtxRing + 2,   // 8
  kCtxRange = kCtxColumn + 8,  // 16: the chosen predictor's recent error
  kCtxX = kCtxRange + 16,      // 24 and (kCtxZ) 24: unused (x y z before the fraction rule)
  kCtxY = kCtxX + 24,          // 16 x 3: the second of x y from the azimuth, by bit length
  kCtxZ = kCtxY + 48,
  kCtxCart = kCtxZ + 24,            // 3 axes x 8: previous residual's bit length
  kCtxRaster = kCtxCart + 24,       // 27: raster frames (scan_raster.h)
  kCtxImage = kCtxRaster + 27,      // the fraction-rule contexts below (FORMAT: 175)
  kCtxRangeFrac = kCtxImage,        // 8 x 3: the range against the smoothed map
  kCtxAxis1 = kCtxRangeFrac + 24,   // 24 x 3: first of x y, by the range's bit length
  kCtxAxis2 = kCtxAxis1 + 72,       // 8 x 3: second of x y from the hypotenuse, by the count
  kCtxZFrac = kCtxAxis2 + 24,       // 24 x 3: z, by the range's bit length
  kCtxWalkRepeat = kCtxZFrac + 72,  // 24: the ring walk's repeat flag
  kCtxWalk = kCtxWalkRepeat + 24,   // 4 x 2 x 2 x 8: the walk's flags
  kCtxWalkColumn = kCtxWalk + 128,  // 1: a repeated ring's column
  kCtxTurn = kCtxWalkColumn + 1,    // 2 x 2 x 4: the column with the third candidate (units bit 4)
  kCtxPairRing = kCtxTurn + 16,     // 6: a ring pair frame's ring, by the previous symbol
  kCtxShare = kCtxPairRing + 6,     // 2 x 4: the column against the firing's base (units bit 3)
  kCtxSlots = kCtxShare + 8,        // 2 + 4 + 2: the firing's turn, base, column (units bit 6)
  kContexts = kCtxSlots + 8,
};

// How the block codes a value of context ctx (FORMAT.md "Zero first"): ranges (spherical and
// raster frames'), Cartesian frames' residuals and the pixel table as plain hybrid tokens (most
// of them are not 0), flags by their bit only, every other value zero first. (The Io's sym_plain
// codes the plain ones, sym the zero-first ones.)
enum class ValueKind { kPlain, kZeroFirst, kFlag };
constexpr ValueKind value_kind(int ctx) {
  return (ctx >= kCtxRange && ctx < kCtxRange + 16) || (ctx >= kCtxCart && ctx < kCtxRaster + 3) ||
                 (ctx >= kCtxRaster + 5 && ctx < kCtxRaster + 21) ||
                 (ctx >= kCtxRangeFrac && ctx < kCtxRangeFrac + 24)
             ? ValueKind::kPlain
         : ctx < kCtxValid + 2 || (ctx >= kCtxWalkRepeat && ctx < kCtxWalkColumn)
             ? ValueKind::kFlag
             : ValueKind::kZeroFirst;
}
namespace detail {
// value_kind of every context, one load for the encoder's replay of a trial's symbols.
struct ValueKinds {
  ValueKind k[kContexts];
  constexpr ValueKinds() : k() {
    for (int c = 0; c < kContexts; ++c) k[c] = value_kind(c);
  }
};
inline constexpr ValueKinds kValueKinds{};
}  // namespace detail

// Codes u (a residual's zig-zag, or an unsigned value) under ctx (below kContexts) as the block
// does; Enc: an IntEncoder or its Cursor, with binary models.
template <class Enc>
__attribute__((always_inline)) inline void put_value(Enc& enc, uint32_t u, int ctx) {
  switch (detail::kValueKinds.k[ctx]) {
    case ValueKind::kPlain:
      enc.put(u, ctx);
      break;
    case ValueKind::kFlag:
      enc.put_bit(u != 0, ctx);
      break;
    case ValueKind::kZeroFirst:
      enc.put_zero_first(u, ctx);
      break;
  }
}

// A point's validity under the frame's validity mode (FORMAT: a flag per point in mode 1, under
// the previous point's flag); *prev_valid carries that flag from point to point.
template <class Io>
bool point_valid(Io& io, uint8_t vmode, size_t i, bool* prev_valid) {
  bool v = vmode == kAllValid;
  if (vmode == kSomeValid) v = io.flag(io.actual_valid(i), kCtxValid + *prev_valid);
  *prev_valid = v;
  return v;
}

// The length of (x, y) as sqrt(x x + y y), each step rounded (the octree's cone class, FORMAT.md
// "The block's flags"; the table fit's lengths): std::hypot's value but for the last bit,
// without its call, for finite coordinates far from hypot's overflow and underflow guards.
inline double planar_length(double x, double y) {
  return std::sqrt(x * x + y * y);
}

// floor(v) (std::floor's value; a zero's sign aside) without a call for |v| < 2^52: the
// integer part by truncation, less one below a negative fraction.
inline double floor_fast(double v) {
  if (std::fabs(v) < 4503599627370496.0) {
    const double t = static_cast<double>(static_cast<int64_t>(v));
    return t > v ? t - 1.0 : t;
  }
  return std::floor(v);
}

namespace detail {
// Taylor series of sin and cos on |r| <= pi/4 (terms to r^17 and r^16) in Horner form:
// sin r = r + r r2 P_s(r2), cos r = 1 + r2 P_c(r2), the coefficients from the highest term.
constexpr double kSinTerms[8] = {
    1.0 / 355687428096000.0, -1.0 / 1307674368000.0, 1.0 / 6227020800.0, -1.0 / 39916800.0,
    1.0 / 362880.0,          -1.0 / 5040.0,          1.0 / 120.0,        -1.0 / 6.0};
constexpr double kCosTerms[8] = {
    1.0 / 20922789888000.0, -1.0 / 87178291200.0, 1.0 / 479001600.0, -1.0 / 3628800.0,
    1.0 / 40320.0,          -1.0 / 720.0,         1.0 / 24.0,        -0.5};
inline double horner(const double (&c)[8], double r2) {
  double p = c[0];
  for (int i = 1; i < 8; ++i) p = p * r2 + c[i];
  return p;
}
}  // namespace detail

// sin and cos of a (radians) with binary64 +, -, * and floor only: the same bits on every build.
// Inline for the coding loop; its callers are compiled without FMA contraction (CMakeLists.txt).
inline void det_sincos(double a, double* s, double* c) {
  // a = k pi/2 + r, |r| <= pi/4 (about; exactness does not matter, only the same bits).
  const double kHalfPiHi = 1.5707963267948966;
  const double kHalfPiLo = 6.123233995736766e-17;
  const double k = floor_fast(a * (1.0 / kHalfPiHi) + 0.5);
  const double r = (a - k * kHalfPiHi) - k * kHalfPiLo;
  const double q = k - 4.0 * floor_fast(k * 0.25);  // 0, 1, 2 or 3
  const double r2 = r * r;
  const double ps = r + r * r2 * detail::horner(detail::kSinTerms, r2),
               pc = 1.0 + r2 * detail::horner(detail::kCosTerms, r2);
  if (q == 0.0) {
    *s = ps, *c = pc;
  } else if (q == 1.0) {
    *s = pc, *c = -ps;
  } else if (q == 2.0) {
    *s = -ps, *c = -pc;
  } else {
    *s = -pc, *c = ps;
  }
}
// sin and cos of a spherical point's azimuth, phi_k + c s (FORMAT step 4): the sum of ring k's
// phi_k and column c's c s, each angle's sine and cosine by det_sincos; ring k's worked out
// once for the table, column c's (0 .. C-1) when first asked for, so that a window's table of
// many columns costs only those its points use. Shared by a state's copies, within one thread.
class Angles {
 public:
  Angles(const std::vector<float>& azimuth0, double step, uint32_t columns)
      : step_(step),
        columns_(columns),
        column_(new double[2 * size_t{columns}]),
        filled_(columns, 0) {
    ring_.resize(2 * azimuth0.size());
    for (size_t k = 0; k < azimuth0.size(); ++k)
      det_sincos(static_cast<double>(azimuth0[k]), &ring_[2 * k], &ring_[2 * k + 1]);
  }
  __attribute__((always_inline)) void of(uint32_t k, int32_t col, double* s, double* c) const {
    const double sa = ring_[2 * k], ca = ring_[2 * k + 1];
    double sb, cb;
    const auto u = static_cast<uint32_t>(col);
    if (__builtin_expect(u < columns_, 1)) {
      if (__builtin_expect(!filled_[u], 0)) {
        det_sincos(static_cast<double>(col) * step_, &column_[2 * size_t{u}],
                   &column_[2 * size_t{u} + 1]);
        filled_[u] = 1;
      }
      sb = column_[2 * size_t{u}];
      cb = column_[2 * size_t{u} + 1];
    } else {
      det_sincos(static_cast<double>(col) * step_, &sb, &cb);
    }
    *s = sa * cb + ca * sb;
    *c = ca * cb - sa * sb;
  }

 private:
  double step_;
  uint32_t columns_;
  std::vector<double> ring_;             // sin, cos of each ring's phi_k
  std::unique_ptr<double[]> column_;     // sin, cos of each column's angle, where filled_
  mutable std::vector<uint8_t> filled_;  // (column_'s values are written through the pointer)
};

// floor(v + 0.5) clamped to the int32 range (NaN gives 0). Below 2^31 - 1 in magnitude (every
// prediction of a point but the odd far one) v + 0.5 truncates into an int64 exactly, and
// floor is that, less one above v + 0.5: floor_fast's value, without its range test or the
// tests of the clamp.
inline int32_t round_clamp(double v) {
  if (__builtin_expect(std::fabs(v) < 2147483647.0, 1)) {
    const double w = v + 0.5;
    const int64_t i = static_cast<int64_t>(w);
    return static_cast<int32_t>(i - static_cast<int64_t>(static_cast<double>(i) > w));
  }
  if (!(v == v)) return 0;
  if (v >= 2147483647.0) return INT32_MAX;
  if (v <= -2147483648.0) return INT32_MIN;
  return static_cast<int32_t>(floor_fast(v + 0.5));
}
// Bit length of |v| (0 for 0).
inline int bit_length(int64_t v) {
  const uint64_t u = static_cast<uint64_t>(v < 0 ? -v : v);
  return u == 0 ? 0 : 64 - __builtin_clzll(u);
}

// The header: frames, counts, flags, table (the entropy-coded block follows it). write_header
// is the encoder's (scan_encode.cpp), read_header the decoder's (scan_shared.cpp).
// turns: the frames' turns (FORMAT.md "Turns"; one a frame, written only when the table has
// rings and one of them is not 0), or null: none.
void write_header(const ScanGeometry& g, const std::vector<uint8_t>& flags, const Table& t,
                  std::vector<uint8_t>* out, const std::vector<int32_t>* turns = nullptr);
// The header's K and laser table (write_header's part after the flags), with its `more` byte
// and the frames' turns (as write_header's).
void write_table(const Table& t, ByteWriter* w, const std::vector<int32_t>* turns = nullptr);
struct Header {
  std::vector<uint32_t> counts;
  std::vector<uint8_t> flags;
  Table table;
  uint32_t pixels = 0;  // raster frames' pixel table (scan_raster.h): P, delta, e; P = 0: none
  double delta = 0;
  int exponent = 0;
  int fine = 0;  // the fine shift k: the integers count the grid step times 2^-k
  // Per frame its copies d_f (0 without bit 4: FORMAT "Cells with counts"), and the counts
  // block's offset and size (size 0: no frame has bit 4).
  std::vector<uint32_t> copies;
  size_t cells = 0, cells_size = 0;
  // The octree block's offset and size (size 0: no octree frame; FORMAT "Octree frames").
  size_t octree = 0, octree_size = 0;
  size_t flags_end = 0;        // offset just past flags_f (where d_f, else K, begins)
  std::vector<int32_t> turns;  // per frame its turn t_f (FORMAT.md "Turns"), or empty: none
  size_t body = 0;             // offset of the entropy-coded block
};
Header read_header(const uint8_t* data, size_t size, const std::string& what, size_t max_points);

// The per-point quantities of a spherical frame (encoder side: computed from the integers).
struct Polar {
  uint32_t ring = 0;
  int32_t column = 0;
  int32_t range = 0;
};
static_assert(sizeof(Polar) == 12, "the encoder keeps several Polar arrays a window");
// Encoder, with the table's slots: the base B and turn D of a point's firing (FORMAT step 2),
// apart from Polar since only tables with slots have them.
struct Fire {
  int32_t b = 0, d = 0;
};

// The state that lives across a window's frames and within one frame.
class State {
 public:
  // The maps are the state's own, or `maps` (reset for this table: an encoder's for each table).
  explicit State(const Table& t, std::shared_ptr<SweepMaps> maps = nullptr);
  const Table& table() const { return *t_; }
  const Angles& angles() const { return *angles_; }
  // Call after each frame: this sweep's map becomes the previous one.
  void end_frame();
  // A copy for a trial (the encoder's cost estimate): shares the maps, never writes them.
  State trial() const {
    State s = *this;
    s.trial_ = true;
    return s;
  }
  // A copy that codes a sweep ahead (the encoder's spherical trial, kept when it wins): writes
  // this sweep's map, which the original shares. The original then takes it over (*this = it)
  // before its end_frame, or drops it with clear_sweep.
  State staged() const {
    State s = *this;
    s.trial_ = false;
    return s;
  }
  // Forgets what this sweep wrote into its map (a dropped staged copy's writes).
  void clear_sweep();

  // Spherical prediction state per ring.
  struct Ring {
    int32_t last_range = 0, last_column = 0, step = 0;
    int32_t before_column = 0;  // the column before the last (has_before)
    int32_t lead = 0;           // its last column less the point's before it then (has_lead)
    uint32_t lead_ring = 0;     // that point's ring
    bool has_last = false, has_before = false, has_lead = false;
    uint32_t score_col[4] = {0, 0, 0, 0};
    uint32_t score_range[4] = {0, 0, 0, 0};
    int32_t before_range = 0;  // the range before the last (has_before_range; units bit 7)
    bool has_before_range = false;
  };
  std::vector<Ring> ring;
  std::vector<uint32_t> succ;  // predicted ring after ring k
  // Per ring in a ring walk frame: its last firing (-1: none), its points in that firing and
  // in the firing before it.
  struct Firing {
    int64_t last = -1;
    uint32_t n = 0, m = 0;
  };
  std::vector<Firing> firing;
  // Ring pair frames: per pair of rings (a, b) at pair_cell(a, b), the ring that followed them
  // last plus one (0: none) and the column step from a to b; empty until such a frame.
  static constexpr uint32_t kPairCells = 4096;
  std::vector<uint16_t> pair_ring;
  std::vector<int32_t> pair_column;
  uint32_t pair_cell(uint32_t a, uint32_t b) const {
    return (a * static_cast<uint32_t>(t_->rings()) + b) & (kPairCells - 1);
  }
  uint32_t ring_score[2] = {0, 0};
  // The firing's base (units bit 3, FORMAT step 2): per j (the lasers spread by their shares, or
  // all on the base) the interval of bases the firing's points allow, whether it is live; the
  // active j; the last point's share.
  struct Base {
    double lo[2] = {0, 0}, hi[2] = {0, 0};
    bool live[2] = {false, false};
    bool open = false;
    int active = 0;
    double last_share = 0;
  };
  Base base;
  // The firing's slots (units bit 6, FORMAT step 2): the firing's base B and turn D, the last
  // point's slot; set again at each frame's start.
  struct Slots {
    bool open = false;
    int32_t b = 0, d = 0;
    uint32_t last = 0;
  };
  Slots slots;
  // The previous sweep's smoothed range (1/16 steps) at ring k, column col (false: none there),
  // the column shifted by the frame's turn (FORMAT.md "Turns").
  bool map_prev(uint32_t k, int32_t col, int64_t* smooth) const {
    return maps_->prev(cell(k, int64_t{col} + turn_), smooth);
  }
  // The same at column col + s, whatever the frame's turn (the encoder's search for it).
  bool map_prev_at(uint32_t k, int64_t col, int64_t* smooth) const {
    return maps_->prev(cell(k, col), smooth);
  }
  void map_set(uint32_t k, int32_t col, int32_t range) {
    if (trial_) return;
    const size_t i = cell(k, col);
    maps_->set(i, turn_ == 0 ? i : cell(k, int64_t{col} + turn_), range);
  }
  // The previous sweep's successor ring of ring k, column col (the frame's turn added; false:
  // none), and this sweep's, set (FORMAT.md "The previous sweep's successors").
  bool map_prev_successor(uint32_t k, int32_t col, uint32_t* next) const {
    return maps_->prev_successor(cell(k, int64_t{col} + turn_), next);
  }
  void map_set_successor(uint32_t k, int32_t col, uint32_t next) {
    if (!trial_) maps_->set_successor(cell(k, col), next);
  }
  // The turn t_f of the frame coded next (0 until set; kept until set again).
  void set_turn(int32_t t) { turn_ = t; }
  // Cartesian / cross-frame state.
  int32_t last[3] = {0, 0, 0};
  int last_bits[3] = {0, 0, 0};
  // The decoder's, when not null: each spherical point's ring k (step 1) at its index in the
  // window (ATTR's geometry ring, FORMAT.md predictor 13); copies share it.
  uint16_t* ring_out = nullptr;

 private:
  size_t cell(uint32_t k, int64_t col) const {
    const uint32_t n = t_->columns;
    int64_t c = col;
    if (static_cast<uint64_t>(c) >= n) {  // a column off [0, n): its residue mod n
      c %= n;
      if (c < 0) c += n;
    }
    // Column-major: a firing's rings lie side by side, and the next firing's beside them (a
    // sweep's walk through the previous sweep's map then reads lines in order).
    return static_cast<size_t>(c) * t_->rings() + k;
  }
  const Table* t_;
  std::shared_ptr<const Angles> angles_;  // the table's (shared by copies)
  std::shared_ptr<SweepMaps> maps_;       // the previous sweep's ranges and this sweep's
  bool trial_ = false;
  int32_t turn_ = 0;
};

// The one frame loop. Io provides:
//   int32_t sym(int32_t actual, int32_t pred, int ctx)  -> the value (actual when encoding)
//   int32_t sym_plain(...) as sym, for the contexts value_kind says are plain
//   uint32_t ring(uint32_t actual_residual, uint32_t rings, int ctx) -> the ring residual
//   bool flag(bool actual, int ctx)
//   Polar polar(size_t i) (encoder: the point's ring, column, range; decoder: anything)
//   Fire fire(size_t i) (encoder, on a table with slots: the point's firing; else anything)
//   const int32_t* actual(size_t i) (encoder: the point's integers; decoder: anything)
//   bool actual_valid(size_t i)
// q_out and valid_out receive the frame's points (n of them).
template <class Io>
void code_frame(Io& io, State& st, uint8_t flags, size_t first, size_t n, int32_t* q_out,
                uint8_t* valid_out);
// code_frame without its closing st.end_frame().
template <class Io>
void code_points(Io& io, State& st, uint8_t flags, size_t first, size_t n, int32_t* q_out,
                 uint8_t* valid_out);

}  // namespace scan
}  // namespace capz

#include "coding/scan_loop.h"
