// Position predictors and the window coding loop, shared by encoder and decoder so both compute
// identical predictions (docs/FORMAT.md 3.3). All integer arithmetic wraps modulo 2^32.
//
// Shapes: q, t are frames x points x 3 int32 (frame-major); valid is frames x points.
#pragma once

#include <algorithm>
#include <cstddef>
#include <cstdint>
#include <vector>

namespace capz {

enum Predictor : uint8_t {
  kPredPrevious = 0,   // q[f-1]
  kPredLinear = 1,     // 2 q[f-1] - q[f-2]
  kPredQuadratic = 2,  // 3 q[f-1] - 3 q[f-2] + q[f-3]
  kPredTransform = 3,  // t[f]  (the transform codec's reconstruction on the grid)
  kPredTransformLinear = 4,  // t[f] + linear extrapolation of (q - t)
  kPredRefPrevious = 5,      // q[f-1] + (q[f][r] - q[f-1][r]): reference point r < p's motion
  kPredRefLinear = 6,        // linear(p) + (q[f][r] - linear(r)): r's deviation from linear
  kPredCount = 7,
};

// Predictors that add a reference point's motion (docs/FORMAT.md 3.3); ref[p] = r < p.
inline bool uses_ref(int mode) { return mode == kPredRefPrevious || mode == kPredRefLinear; }

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

// Residual contexts of a window (docs/FORMAT.md 3.3.1). Per point and axis: `ta`, the token of
// the last residual coded for it in this window, and `z`, the number of zero tokens ending there
// (capped at 6). Scheme 1 (format 1.x): 32 contexts from ta and tb (the token coded just before
// in the same frame). Scheme 2 (format 2.x): 144 contexts from ta or the zero run, tb, and the
// larger of the other two axes' ta.
class ResidualContexts {
 public:
  ResidualContexts(int scheme, size_t points)
      : scheme_(scheme), ta_(points * 3, 0), z_(points * 3, 0) {}
  static int count(int scheme) { return scheme == 1 ? 32 : 84; }
  // Escape model set of a context (1.3): scheme 2 states 18, 19, 20 use sets 0, 1, 2 (large
  // previous tokens: float-bit data); every other context, and all of scheme 1, set 0.
  static int escape_set(int ctx) { return ctx < 76 ? 0 : ctx < 80 ? 1 : 2; }
  void reset() {
    std::fill(ta_.begin(), ta_.end(), 0);
    std::fill(z_.begin(), z_.end(), 0);
  }
  // Context of axis a of point p (k = 3 p + a, a = k % 3) when tb was coded last in the frame.
  int context(size_t k, int tb) const {
    const int ta = ta_[k];
    if (scheme_ == 1) return std::min(ta, 7) * 4 + std::min(tb, 3);

    static constexpr uint8_t kRunBucket[13] = {0, 1, 2, 3, 4, 4, 5, 5, 5, 6, 6, 6, 6};
    static constexpr uint8_t kTokBucket[64] = {
        0,  7,  8,  9,  10, 11, 12, 13, 14, 14, 14, 14, 15, 15, 16, 16,  // 0-15
        17, 17, 17, 17, 18, 18, 18, 18, 18, 18, 18, 18, 19, 19, 19, 19,  // 16-31
        19, 19, 19, 19, 20, 20, 20, 20, 20, 20, 20, 20, 20, 20, 20, 20,  // 32-47
        20, 20, 20, 20, 20, 20, 20, 20, 20, 20, 20, 20, 20, 20, 20, 20};
    const int s = ta ? kTokBucket[ta] : kRunBucket[z_[k]];
    return s * 4 + std::min(tb, 3);
  }
  void update(size_t k, int tok) {
    ta_[k] = static_cast<uint8_t>(tok);
    z_[k] = tok ? 0 : static_cast<uint8_t>(std::min(z_[k] + 1, 12));
  }

 private:
  int scheme_;
  std::vector<uint8_t> ta_, z_;
};

// Coder: int32_t operator()(size_t i, int32_t pred, int ctx, int* tok), coding sample i under
// context ctx and returning its value; trivially copyable: the walk codes through a local copy
// (kept in registers) and stores it back into `coder` at the end.
template <typename Coder>
void walk_window(size_t frames, size_t points, const uint8_t* valid, const uint8_t* modes,
                 const uint32_t* ref, const int32_t* t, int32_t* q, ResidualContexts& ctx,
                 Coder& coder) {
  Coder code = coder;
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
        if (f == 0) {
          pred = transform ? t[i + a] : last[a];
        } else if (uses_ref(m)) {
          const int base = m == kPredRefPrevious ? kPredPrevious : kPredLinear;
          pred = predict_one(base, f, q + i + a, stride, nullptr);
          const size_t r = ref[p];
          if (valid[f * points + r]) {
            const int32_t* qr = q + f * stride + r * 3 + a;
            pred = wrap_add(pred, wrap_sub(*qr, predict_one(base, f, qr, stride, nullptr)));
          }
        } else {
          pred = predict_one(m, f, q + i + a, stride, t ? t + i + a : nullptr);
        }
        int tok;
        q[i + a] = code(i + a, pred, ctx.context(p * 3 + a, tb), &tok);
        ctx.update(p * 3 + a, tok);
        tb = tok;
      }
      if (f == 0) std::copy(q + i, q + i + 3, last);
    }
  }
  coder = code;
}

}  // namespace capz
