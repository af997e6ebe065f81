// pdct: the closed-loop predictor shared by the encoder and the decoder (Amjoun & Strasser 2007,
// Sec. 4.3-4.4 and 4.7). Both run run_closed_loop(); only the hooks differ (the encoder computes
// the integers from the original and stores them, the decoder reads them), so the encoder's
// reconstruction is the decoder's output bit for bit.
//
// Per window (frames x points):
//  * Frame points (the triangles' vertices, K of them) live on the world grid seed_step:
//    I(f, k, a) = round(p / seed_step) (encoder). Stored: I - prediction, where the prediction is
//    I(f-1) (seed_order 1, the paper's differential coding) or 2 I(f-1) - I(f-2) (seed_order 2,
//    from f = 2); in frame 0 it is the previous frame point's I (0 for the first).
//    Decoded position = I * seed_step.
//  * Cluster k's local frame in frame f: make_lcf() on its triangle's decoded positions, or the
//    identity when the triangle's three indices are equal (a take with no usable triangle).
//  * Frame 0, members of cluster k in ascending point order: local q quantised on first_step,
//    J = round(q / first_step) per axis; stored J - (previous member's J, 0 for the first);
//    decoded local = J * first_step.
//  * Frame f >= 1: prediction pred = q~(f-1) (local_order 1, the paper) or 2 q~(f-1) - q~(f-2)
//    (local_order 2, from f = 2), q~ = decoded local coordinates. The encoder forms
//    delta = q(f) - pred (0 for a gap sample), per axis takes the DCT along the cluster's members
//    in consecutive blocks of at most dct_block members (BlockDct), zeroes and quantises each
//    block's coefficients (dct.h); stored: the integer coefficients, axis-major (x of every
//    member, then y, then z). Decoded local q~(f) = pred + IDCT(coefficients * coef_step).
//  * World = to_world(frame, q~).
#pragma once

#include <array>
#include <cmath>
#include <cstddef>
#include <cstdint>
#include <memory>
#include <vector>

#include "codec/pdct/dct.h"
#include "codec/pdct/lcf.h"

namespace capz {
namespace pdct {

struct Layout {
  size_t frames = 0, points = 0;
  std::vector<uint32_t> frame_points;  // K ascending point indices, coded on the seed grid
  // One per cluster: indices into frame_points (p1, p2, p3 of the triangle). All three equal =
  // the identity frame.
  std::vector<std::array<uint32_t, 3>> triangles;
  // One per cluster: its non-frame points in ascending order (the DCT's order).
  std::vector<std::vector<uint32_t>> members;
  size_t dct_block = 64;  // longest DCT; a cluster is transformed in blocks of at most this many
};

constexpr size_t kMaxDctBlock = 4096;  // bounds the cosine tables (dct_block^2 doubles each)

// The DCT of a cluster of n members cut into consecutive blocks of at most `block` members
// (the last may be shorter); each block is an orthonormal DCT of its own length.
class BlockDct {
 public:
  BlockDct(size_t n, size_t block);
  size_t size() const { return n_; }
  size_t blocks() const { return (n_ + block_ - 1) / block_; }
  size_t block_begin(size_t b) const { return b * block_; }
  size_t block_size(size_t b) const;
  void forward(const double* x, double* X) const;  // n in, n out
  void inverse(const double* X, double* x) const;

 private:
  size_t n_, block_;
  std::unique_ptr<DctPlan> full_, tail_;
};

struct Steps {
  double seed = 0;      // frame-point grid, position units, > 0
  double first = 0;     // frame-0 local grid, > 0
  double coef = 0;      // DCT coefficient step, > 0
  int seed_order = 1;   // 1 or 2
  int local_order = 1;  // 1 or 2
};

// Checks a layout read from a stream against the window (every index in range, every point in
// exactly one of frame_points or one cluster, 1 <= dct_block <= kMaxDctBlock; identity
// triangles are exempt from the range check). Throws Error(kCorrupt) naming `what`.
void check_layout(const Layout& layout, const char* what);

// The integers of a window, supplied by the encoder or read by the decoder.
class LoopHooks {
 public:
  virtual ~LoopHooks() = default;
  // Residual of frame point k (index into frame_points), axis a, frame f, given its prediction.
  virtual int64_t seed_residual(size_t f, size_t k, int a, int64_t prediction) = 0;
  // Frame 0: residual of member m of cluster c, axis a (frame = the cluster's frame-0 frame).
  virtual int64_t first_residual(size_t c, size_t m, int a, const Lcf& frame,
                                 int64_t prediction) = 0;
  // Frame f >= 1: fills coefs (3 x n, axis-major) for cluster c given its frame, the
  // prediction pred (n x 3 local coordinates) and the cluster's transform.
  virtual void coefficients(size_t f, size_t c, const Lcf& frame, const double* pred,
                            const BlockDct& dct, int64_t* coefs) = 0;
};

// Runs the window; recon: frames x points x 3, resized and filled with the decoded positions.
void run_closed_loop(const Layout& layout, const Steps& steps, LoopHooks* hooks,
                     std::vector<double>* recon);

// ---------------------------------------------------------------------------------------------
// Grid mode (used with a max error): every point lives on the bound layer's world grid g, so
// the reconstruction of every measured sample is exactly the bound layer's quantisation
// round(p / g) * g and the bound layer has nothing left to code. The DCT is not used (it cannot
// be exact on the grid); prediction is the paper's, in the clusters' local frames, built on the
// decoded (grid) positions of the frame points:
//  * frame points: as in the DCT mode with seed_step = g and seed_order 2;
//  * frame 0, members of each cluster in ascending order: I = round(p / g) per axis, stored
//    I - (previous member's I, 0 for the first);
//  * frame f >= 1, point i of cluster c with predictor kind:
//      kWorldLinear: 2 I(f-1) - I(f-2) (I(f-1) at f = 1), in integers;
//      kLocal1:      the paper's: x = to_world(F(f), to_local(F(f-1), I(f-1) g));
//      kLocal2:      x = to_world(F(f), 2 to_local(F(f-1), I(f-1) g) - to_local(F(f-2), I(f-2) g))
//                    (kLocal1 at f = 1);
//      kClusterAccel: x = (2 I(f-1) - I(f-2)) g + (o(f) - 2 o(f-1) + o(f-2)), o = the frame's
//      origin:
//                    linear extrapolation plus the cluster's acceleration (kLocal1 at f = 1);
//    F(f) = the cluster's frame in frame f; prediction = grid_index(x / g) per axis; stored:
//    I - prediction. The encoder stores 0 for a gap sample, so a gap is predicted through its
//    cluster's frame.
enum PointPredictor : uint8_t { kWorldLinear = 0, kLocal1 = 1, kLocal2 = 2, kClusterAccel = 3 };
constexpr int kPointPredictors = 4;

class GridHooks {
 public:
  virtual ~GridHooks() = default;
  virtual int64_t seed_residual(size_t f, size_t k, int a, int64_t prediction) = 0;
  // Frame 0 (prediction = previous member) and f >= 1 (prediction per the point's kind).
  virtual int64_t point_residual(size_t f, uint32_t point, int a, int kind, int64_t prediction) = 0;
};

// predictor: one kind per point (frame points' entries are ignored). recon: frames x points x 3.
void run_grid_loop(const Layout& layout, double grid, int seed_order,
                   const std::vector<uint8_t>& predictor, GridHooks* hooks,
                   std::vector<double>* recon);

// round-half-away-from-zero(x) clamped to +-2^40 (NaN -> 0): predictions from corrupt streams
// stay defined.
inline int64_t grid_index(double x) {
  if (!(x == x)) return 0;
  if (x > 1099511627776.0) return 1099511627776;
  if (x < -1099511627776.0) return -1099511627776;
  return static_cast<int64_t>(x < 0 ? -std::floor(-x + 0.5) : std::floor(x + 0.5));
}

// The decoded value of an integer on a grid (shared rounding-free dequantiser).
inline double on_grid(int64_t v, double step) {
  return static_cast<double>(v) * step;
}

// Wrapping int64 add: a corrupt stream gives garbage positions, never undefined behaviour.
inline int64_t wrap_add(int64_t a, int64_t b) {
  return static_cast<int64_t>(static_cast<uint64_t>(a) + static_cast<uint64_t>(b));
}

}  // namespace pdct
}  // namespace capz
