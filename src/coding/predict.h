// Position predictors and the window coding loop, shared by encoder and decoder so both compute
// identical predictions (docs/FORMAT.md 3.3). All integer arithmetic wraps modulo 2^32.
//
// Shapes: q, t are frames x points x 3 int32 (frame-major); valid is frames x points.
#pragma once

#include <algorithm>
#include <cstddef>
#include <cstdint>

namespace capz {

enum Predictor : uint8_t {
  kPredPrevious = 0,   // q[f-1]
  kPredLinear = 1,     // 2 q[f-1] - q[f-2]
  kPredQuadratic = 2,  // 3 q[f-1] - 3 q[f-2] + q[f-3]
  kPredTransform = 3,  // t[f]  (the transform codec's reconstruction on the grid)
  kPredTransformLinear = 4,  // t[f] + linear extrapolation of (q - t)
  kPredCount = 5,
};

constexpr int kPosContexts = 32;

inline int32_t wrap_add(int32_t a, int32_t b) {
  return static_cast<int32_t>(static_cast<uint32_t>(a) + static_cast<uint32_t>(b));
}
inline int32_t wrap_sub(int32_t a, int32_t b) {
  return static_cast<int32_t>(static_cast<uint32_t>(a) - static_cast<uint32_t>(b));
}
inline int32_t wrap_mul(int32_t a, uint32_t k) {
  return static_cast<int32_t>(static_cast<uint32_t>(a) * k);
}

// Prediction of q[f] from the point's history. `c` points at q[f][p][a]; `stride` = points * 3;
// `tc` at t[f][p][a] (may be null when no transform ran). Requires f >= 1.
inline int32_t predict_one(int mode, size_t f, const int32_t* c, size_t stride,
                           const int32_t* tc) {
  const int32_t q1 = *(c - stride);
  switch (mode) {
    case kPredPrevious:
      return q1;
    case kPredLinear:
      if (f < 2) return q1;
      return wrap_sub(wrap_mul(q1, 2), *(c - 2 * stride));
    case kPredQuadratic:
      if (f < 2) return q1;
      if (f < 3) return wrap_sub(wrap_mul(q1, 2), *(c - 2 * stride));
      return wrap_add(wrap_mul(wrap_sub(q1, *(c - 2 * stride)), 3), *(c - 3 * stride));
    case kPredTransform:
      return *tc;
    default: {  // kPredTransformLinear
      const int32_t e1 = wrap_sub(q1, *(tc - stride));
      if (f < 2) return wrap_add(*tc, e1);
      const int32_t e2 = wrap_sub(*(c - 2 * stride), *(tc - 2 * stride));
      return wrap_add(*tc, wrap_sub(wrap_mul(e1, 2), e2));
    }
  }
}

inline int pos_context(int ta, int tb) { return std::min(ta, 7) * 4 + std::min(tb, 3); }

// Walks a window in coding order (docs/FORMAT.md 3.3): for every valid sample and axis calls
// `code(index, prediction, context)`, which returns the sample's integer (the encoder returns
// the true value after coding the residual, the decoder the prediction plus the decoded
// residual) and stores it in q; fills gap samples by the hold rule. `modes` has one predictor
// per point; `t` may be null if no point uses a transform predictor. `tok_of_last()` of the
// coder gives the token of the last residual it coded.
template <typename Coder>
void walk_window(size_t frames, size_t points, const uint8_t* valid, const uint8_t* modes,
                 const int32_t* t, int32_t* q, uint8_t* tok_prev /* points*3, zeroed */,
                 Coder& code) {
  const size_t stride = points * 3;
  for (size_t f = 0; f < frames; ++f) {
    int tb = 0;
    int32_t last[3] = {0, 0, 0};
    for (size_t p = 0; p < points; ++p) {
      const size_t i = f * stride + p * 3;
      const int m = modes[p];
      const bool transform = m == kPredTransform || m == kPredTransformLinear;
      if (!valid[f * points + p]) {
        for (int a = 0; a < 3; ++a) q[i + a] = f == 0 ? (transform ? t[i + a] : last[a])
                                                       : q[i + a - stride];
        continue;
      }
      for (int a = 0; a < 3; ++a) {
        int32_t pred;
        if (f == 0)
          pred = transform ? t[i + a] : last[a];
        else
          pred = predict_one(m, f, q + i + a, stride, t ? t + i + a : nullptr);
        uint8_t& ta = tok_prev[p * 3 + a];
        int tok;
        q[i + a] = code(i + a, pred, pos_context(ta, tb), &tok);
        ta = static_cast<uint8_t>(tok);
        tb = tok;
      }
      if (f == 0) std::copy(q + i, q + i + 3, last);
    }
  }
}

}  // namespace capz
