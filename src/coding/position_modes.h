// The encoder's choice of a predictor per point for one window of positions (docs/FORMAT.md 8:
// predictors, reference points, period), by the estimated coded size of each point's residuals.
// Encoder only (capz::capz), used by encode_positions (positions_encode.cpp); the decoder reads
// the choice from the payload (positions.cpp).
#pragma once

#include <cstddef>
#include <cstdint>
#include <vector>

#include "coding/positions.h"
#include "coding/predict.h"

namespace capz {

// What the estimate chose for a window: a predictor per point, the reference point of those
// using predictors 5/6, and the period of predictors 8/9 (0 when none is tried).
struct ModeChoice {
  std::vector<uint8_t> modes;
  std::vector<uint32_t> ref;
  size_t period = 0;
};

// Chooses every point's predictor for window w (t: the transform's prediction, or nullptr),
// predictor 10 a candidate unless `ray` is kNone; fills q's gap entries as the walks will.
ModeChoice choose_modes(const WindowInts& w, const int32_t* t, ResidualContexts& ctx,
                        std::vector<int32_t>* q, RayKind ray = RayKind::kNone);

}  // namespace capz
