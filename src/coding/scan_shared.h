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
#include <cstddef>
#include <cstdint>
#include <memory>
#include <string>
#include <vector>

#include "coding/entropy.h"
#include "coding/scan_geometry.h"

namespace capz {
namespace scan {

// Frame flags (one byte per frame).
constexpr uint8_t kAllValid = 0, kSomeValid = 1, kNoneValid = 2;  // bits 0-1
constexpr uint8_t kSpherical = 4;                                 // bit 2
constexpr uint8_t kFrameFlagMask = 7;

// Limits the decoder enforces (FORMAT.md).
constexpr uint32_t kMaxRings = 1024;
constexpr uint64_t kMaxMapCells = uint64_t{1} << 22;  // rings x columns
// Coordinates of a spherical frame stay below this in magnitude (so a range fits an int32).
constexpr int64_t kMaxSphericalCoord = int64_t{1} << 29;

// The laser table: per ring an azimuth offset, a cone slope and a z offset; one azimuth step.
struct Table {
  float step = 0;        // radians per column (nonzero when rings > 0)
  uint32_t columns = 0;  // map columns (the previous sweep's ring x column map), >= 1
  std::vector<float> azimuth0, slope, z0;  // per ring
  size_t rings() const { return azimuth0.size(); }
};

// Contexts of the one IntEncoder block.
enum Ctx : int {
  kCtxValid = 0,               // 2: previous point's flag
  kCtxRing = kCtxValid + 2,    // 2: previous ring residual zero or not
  kCtxColumn = kCtxRing + 2,   // 8
  kCtxRange = kCtxColumn + 8,  // 16: the chosen predictor's recent error
  kCtxX = kCtxRange + 16,      // 24: bit length of the range
  kCtxY = kCtxX + 24,          // 48: as X, twice (x residual zero or not)
  kCtxZ = kCtxY + 48,          // 24
  kCtxCart = kCtxZ + 24,       // 3 axes x 8: previous residual's bit length
  kContexts = kCtxCart + 24,
};

// sin and cos of a (radians) with binary64 +, -, * and floor only: the same bits on every build.
void det_sincos(double a, double* s, double* c);
// floor(v + 0.5) clamped to the int32 range (NaN gives 0).
int32_t round_clamp(double v);
// Bit length of |v| (0 for 0).
inline int bit_length(int64_t v) {
  const uint64_t u = static_cast<uint64_t>(v < 0 ? -v : v);
  return u == 0 ? 0 : 64 - __builtin_clzll(u);
}

// The header: frames, counts, flags, table (the entropy-coded block follows it). write_header
// is the encoder's (scan_encode.cpp), read_header the decoder's (scan_shared.cpp).
void write_header(const ScanGeometry& g, const std::vector<uint8_t>& flags, const Table& t,
                  std::vector<uint8_t>* out);
struct Header {
  std::vector<uint32_t> counts;
  std::vector<uint8_t> flags;
  Table table;
  size_t body = 0;  // offset of the entropy-coded block
};
Header read_header(const uint8_t* data, size_t size, const std::string& what, size_t max_points);

// The per-point quantities of a spherical frame (encoder side: computed from the integers).
struct Polar {
  uint32_t ring = 0;
  int32_t column = 0;
  int32_t range = 0;
};

// The state that lives across a window's frames and within one frame.
class State {
 public:
  explicit State(const Table& t);
  const Table& table() const { return *t_; }
  // Call after each frame: this sweep's map becomes the previous one.
  void end_frame();
  // A copy for a trial (the encoder's cost estimate): shares the maps, never writes them.
  State trial() const {
    State s = *this;
    s.trial_ = true;
    return s;
  }

  // Spherical prediction state per ring.
  struct Ring {
    int32_t last_range = 0, last_column = 0, step = 0;
    bool has_last = false;
    uint32_t score_col[2] = {0, 0};
    uint32_t score_range[3] = {0, 0, 0};
  };
  std::vector<Ring> ring;
  std::vector<uint32_t> succ;  // predicted ring after ring k
  uint32_t ring_score[2] = {0, 0};
  // The previous sweep's range at ring k, column col (false: none there).
  bool map_prev(uint32_t k, int32_t col, int32_t* range) const;
  void map_set(uint32_t k, int32_t col, int32_t range);
  // Cartesian / cross-frame state.
  int32_t last[3] = {0, 0, 0};
  int last_bits[3] = {0, 0, 0};

 private:
  size_t cell(uint32_t k, int32_t col) const;
  const Table* t_;
  // The previous sweep's ring x column map and this sweep's: ranges and whether set.
  struct Maps {
    std::vector<int32_t> prev, cur;
    std::vector<uint8_t> prev_set, cur_set;
  };
  std::shared_ptr<Maps> maps_;
  bool trial_ = false;
};

// The one frame loop. Io provides:
//   int32_t sym(int32_t actual, int32_t pred, int ctx)  -> the value (actual when encoding)
//   uint32_t ring(uint32_t actual_residual, uint32_t rings, int ctx) -> the ring residual
//   bool flag(bool actual, int ctx)
//   Polar polar(size_t i) (encoder: the point's ring, column, range; decoder: anything)
//   const int32_t* actual(size_t i) (encoder: the point's integers; decoder: anything)
//   bool actual_valid(size_t i)
// q_out and valid_out receive the frame's points (n of them).
template <class Io>
void code_frame(Io& io, State& st, uint8_t flags, size_t first, size_t n, int32_t* q_out,
                uint8_t* valid_out);

}  // namespace scan
}  // namespace capz

#include "coding/scan_loop.h"
