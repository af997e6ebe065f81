// The bound layer's grid as encoder and decoder share it (docs/FORMAT.md 4.2): how a window's
// integers map back to coordinates, and how a transform's reconstruction becomes a prediction on
// the grid. The encoder's choice of grid is in grid_choice.h.
#pragma once

#include <cstdint>
#include <cstring>
#include <limits>
#include <type_traits>
#include <vector>

#include "capz/take.h"
#include "coding/positions.h"
#include "coding/quantiser.h"

namespace capz {

// How coordinates become integers (docs/FORMAT.md 4.2).
struct Grid {
  PosMode mode = PosMode::kGrid;
  double step = 0;   // kGrid: multiplier; kDecimal: divisor
  double bound = 0;  // per-coordinate bound that holds (0 = exact)
  bool lossless = false;
};

// "grid", "decimal-grid", "float32-bits", "float64-bits", "float32-grid".
const char* mode_name(PosMode m);

// The coordinate integer q (and low word lo, kFloat64 only) stands for under grid g.
template <PosMode M>
inline double dequantise_as(const Grid& g, int32_t q, uint32_t lo) {
  if constexpr (M == PosMode::kGrid) return static_cast<double>(q) * g.step;
  if constexpr (M == PosMode::kDecimal) return static_cast<double>(q) / g.step;
  if constexpr (M == PosMode::kFloat32) return static_cast<double>(ordered_to_float(q));
  if constexpr (M == PosMode::kFloat32Grid)
    return static_cast<double>(static_cast<float>(static_cast<double>(q) * g.step));
  if constexpr (M == PosMode::kFloat64)
    return ordered_to_double(
        static_cast<int64_t>((static_cast<uint64_t>(static_cast<uint32_t>(q)) << 32) | lo));
}

// Calls fn(std::integral_constant<PosMode, m>()): one dispatch, then code for that mode.
template <typename Fn>
void with_mode(PosMode m, Fn&& fn) {
  switch (m) {
    case PosMode::kGrid:
      return fn(std::integral_constant<PosMode, PosMode::kGrid>());
    case PosMode::kDecimal:
      return fn(std::integral_constant<PosMode, PosMode::kDecimal>());
    case PosMode::kFloat32:
      return fn(std::integral_constant<PosMode, PosMode::kFloat32>());
    case PosMode::kFloat32Grid:
      return fn(std::integral_constant<PosMode, PosMode::kFloat32Grid>());
    case PosMode::kFloat64:
      return fn(std::integral_constant<PosMode, PosMode::kFloat64>());
  }
}

// dequantise_as() of every coordinate of a window, gap samples included, into rec (resized to
// frames x points x 3): one loop without a test per sample. The encoder's gap samples hold
// q = 0 (and lo = 0), which every mode maps to +0.0; the decoder's hold the walk's gap fill,
// and it sets them to 0 after.
void dequantise_all(const Grid& g, const WindowInts& wi, std::vector<double>* rec);

// Transform prediction on the grid (docs/FORMAT.md 8 predictor 3): round(recon / step),
// clamped to the grid's index range (NaN to its low end).
std::vector<int32_t> grid_prediction(const std::vector<double>& recon, double step);

// C3D reads an all-zero coordinate triple as a gap, so a valid sample that quantises to
// exactly (0, 0, 0) comes back as (0, 0, FLT_MIN) from a lossy C3D stream (FORMAT.md 8): a
// normal float32 that survives float storage, far inside the bound's margin.
inline void keep_valid_off_origin(Format source, bool lossless, double* x) {
  if (source == Format::kC3D && !lossless && x[0] == 0 && x[1] == 0 && x[2] == 0)
    x[2] = static_cast<double>(std::numeric_limits<float>::min());
}

}  // namespace capz
