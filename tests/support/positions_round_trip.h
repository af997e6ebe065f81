// Test helper: the POSW position coder alone, encoded and decoded (gtest expectations).
#pragma once

#include <gtest/gtest.h>

#include <vector>

#include "coding/positions.h"
#include "coding/predict.h"

namespace capz {

// Encodes a window's integers with no transform, decodes them, expects every valid integer back
// (and the float64 low words); returns the predictor mode of every point as the stream holds it.
inline std::vector<uint8_t> positions_round_trip(const WindowInts& w, int scheme,
                                                 bool float64 = false) {
  std::vector<uint8_t> pos = encode_positions(w, {}, {}, float64, scheme);
  PositionsPayload pp = split_positions(pos.data(), pos.size(), "test");
  WindowInts back;
  back.frames = w.frames;
  back.points = w.points;
  back.valid = w.valid;
  decode_positions(pp, {}, float64, scheme, &back, "test");
  size_t diff = 0;
  for (size_t i = 0; i < w.frames * w.points; ++i)
    if (w.valid[i])
      for (size_t k = i * 3; k < i * 3 + 3; ++k)
        diff += back.q[k] != w.q[k] || (float64 && back.lo[k] != w.lo[k]);
  EXPECT_EQ(diff, 0u);
  return decode_modes(pp, w.points, scheme, "test");
}

// Points whose predictor uses a reference point (FORMAT.md 8, predictors 5 and 6).
inline size_t count_refs(const std::vector<uint8_t>& modes) {
  size_t n = 0;
  for (uint8_t m : modes) n += uses_ref(m) ? 1 : 0;
  return n;
}

}  // namespace capz
