// Position predictors and the window coding loop, shared by encoder and decoder so both compute
// identical predictions (docs/FORMAT.md 3.3). All integer arithmetic wraps modulo 2^32.
//
// Shapes: q, t are frames x points x 3 int32 (frame-major); valid is frames x points.
#pragma once

#include <algorithm>
#include <cstddef>
#include <cstdint>
#include <type_traits>
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
  kPredSmooth = 7,           // least-squares line through the last min(6, f) frames (format 3)
  kPredPeriod = 8,           // q[f-T], T = the window's period (format 3)
  kPredPeriodPrevious = 9,   // q[f-1] + q[f-T] - q[f-T-1]
  kPredCount = 10,
};

// Predictor ids a stream of position-coding scheme `scheme` may use (FORMAT.md 3.3).
inline int predictor_count(int scheme) {
  return scheme >= 3 ? kPredCount : scheme == 2 ? kPredSmooth : kPredRefPrevious;
}
// Predictors extrapolating the last two frames' motion: after a step on the grid their next
// residual tends to undo it, so scheme 3 gives them their own contexts.
inline bool extrapolates(int mode) {
  return mode == kPredLinear || mode == kPredQuadratic || mode == kPredTransformLinear ||
         mode == kPredRefLinear;
}
// Predictors that need the window's period field.
inline bool uses_period(int mode) { return mode == kPredPeriod || mode == kPredPeriodPrevious; }

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

// n / d rounded to the nearest integer, halves away from zero (d > 0).
inline int64_t round_div(int64_t n, int64_t d) {
  return n >= 0 ? (n + d / 2) / d : -((-n + d / 2) / d);
}

// Predictor 7: the least-squares line through q[f-1] .. q[f-K], K = min(6, f), at frame f, as
// q[f-1] + rdiv(sum_{j=2..K} (4K + 2 - 6j) (q[f-j] - q[f-1]), K (K - 1)) (FORMAT.md 3.3).
// Differences wrap to int32; the sum (|.| < 5 * 26 * 2^31) cannot overflow int64.
inline int32_t predict_smooth(size_t f, const int32_t* c, size_t stride) {
  const int32_t q1 = *(c - stride);
  const int64_t k = f < 6 ? static_cast<int64_t>(f) : 6;
  if (k < 2) return q1;
  int64_t n = 0;
  for (int64_t j = 2; j <= k; ++j)
    n += (4 * k + 2 - 6 * j) * static_cast<int64_t>(wrap_sub(*(c - j * stride), q1));
  return wrap_add(q1, static_cast<int32_t>(static_cast<uint32_t>(round_div(n, k * (k - 1)))));
}

// Prediction of q[f] from the point's history. `c` points at q[f][p][a]; `stride` = points * 3;
// `tc` at t[f][p][a] (may be null when no transform ran); `period` is the window's period T
// (used by predictors 8 and 9 only). Requires f >= 1.
inline int32_t predict_one(int mode, size_t f, const int32_t* c, size_t stride, const int32_t* tc,
                           size_t period = 0) {
  const int32_t q1 = *(c - stride);
  switch (mode) {
    case kPredSmooth:
      return predict_smooth(f, c, stride);
    case kPredPeriod:
      return f < period ? q1 : *(c - period * stride);
    case kPredPeriodPrevious:
      if (f < period + 1) return q1;
      return wrap_add(q1, wrap_sub(*(c - period * stride), *(c - (period + 1) * stride)));
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
// (capped at 12). Scheme 1 (format 1.x): 32 contexts from ta and tb (the token coded just before
// in the same frame). Scheme 2 (format 2.x): 84 contexts from ta or the zero run, and tb.
// Scheme 3 (format 3.x): scheme 2's context times 6, refined while ta = 0 by the phase of the
// zero run against the previous run length `L` and the sign `g` of the token that ended it.
//
// Mechanics (not format): each (point, axis) keeps, besides ta, z and the run, `part`: its share
// of the context (scheme 2: 4 s; scheme 3: 24 s + the zero-run phase and sign), recomputed by
// update(), so context() on the decoder's critical path only adds tb's share and the mode's base.
// Escape sets come from a table by context.
class ResidualContexts {
 public:
  ResidualContexts(int scheme, size_t points)
      : scheme_(scheme),
        ta_(points * 3, 0),
        z_(points * 3, 0),
        run_(points * 3, 0),
        part_(points * 3, 0),
        eset_(static_cast<size_t>(count(scheme))) {
    for (int c = 0; c < count(scheme); ++c) {
      int e = 0;
      if (scheme != 1) {
        const int c2 = scheme == 3 ? c % 504 / 6 : c;
        e = c2 < 76 ? 0 : c2 < 80 ? 1 : 2;
      }
      eset_[static_cast<size_t>(c)] = static_cast<uint8_t>(e);
    }
  }
  static int count(int scheme) { return scheme == 1 ? 32 : scheme == 2 ? 84 : 1008; }

  // The state by raw pointers, trivially copyable: the walk works on a local copy, whose fields
  // the compiler keeps in registers (through the object, every byte the walk stores might alias
  // them and force reloads).
  class Cursor {
   public:
    // Escape model set of a context (1.3): scheme 2 states 18, 19, 20 use sets 0, 1, 2 (large
    // previous tokens: float-bit data); scheme 3 as its scheme 2 context; all of scheme 1, 0.
    int escape_set(int ctx) const { return eset_[ctx]; }
    // Context of axis a of point p (k = 3 p + a, a = k % 3) when tb was coded last in the
    // frame. Scheme 2: s * 4 + min(tb, 3), s = ta ? bucket(ta) : bucket(z). Scheme 3:
    // base + 6 * that (base 504 for extrapolating predictors), plus 2 h + g while ta = 0.
    int context(size_t k, int tb, int mode) const {
      const int t = std::min(tb, 3);
      if (scheme_ == 1) return std::min<int>(ta_[k], 7) * 4 + t;
      if (scheme_ == 2) return part_[k] + t;
      return (extrapolates(mode) ? 504 : 0) + part_[k] + 6 * t;
    }
    void update(size_t k, int tok) {
      const int ta = ta_[k], z = z_[k];
      // run_ = L << 1 | g: L the previous run length + 1 (capped at 16, 0 = none), g its sign.
      const int run = tok && !ta ? std::min(z + 1, 16) << 1 | (tok & 1) : run_[k];
      const int nz = tok ? 0 : std::min(z + 1, 12);
      run_[k] = static_cast<uint8_t>(run);
      ta_[k] = static_cast<uint8_t>(tok);
      z_[k] = static_cast<uint8_t>(nz);
      part_[k] = part(tok, nz, run);
    }

   private:
    friend class ResidualContexts;
    // The (point, axis) share of the context from its state after an update (see context()).
    uint16_t part(int ta, int z, int run) const {
      static constexpr uint8_t kRunBucket[13] = {0, 1, 2, 3, 4, 4, 5, 5, 5, 6, 6, 6, 6};
      static constexpr uint8_t kTokBucket[64] = {
          0,  7,  8,  9,  10, 11, 12, 13, 14, 14, 14, 14, 15, 15, 16, 16,  // 0-15
          17, 17, 17, 17, 18, 18, 18, 18, 18, 18, 18, 18, 19, 19, 19, 19,  // 16-31
          19, 19, 19, 19, 20, 20, 20, 20, 20, 20, 20, 20, 20, 20, 20, 20,  // 32-47
          20, 20, 20, 20, 20, 20, 20, 20, 20, 20, 20, 20, 20, 20, 20, 20};
      const int s = ta ? kTokBucket[ta] : kRunBucket[z];
      if (scheme_ != 3) return static_cast<uint16_t>(s * 4);
      if (ta) return static_cast<uint16_t>(s * 24);
      const int L = run >> 1;
      const int h = L == 0 || z < L - 1 ? 0 : z == L - 1 ? 1 : 2;
      return static_cast<uint16_t>(s * 24 + 2 * h + (run & 1));
    }

    int scheme_;
    uint8_t *ta_, *z_, *run_;
    uint16_t* part_;
    const uint8_t* eset_;
  };
  Cursor cursor() {
    Cursor c;
    c.scheme_ = scheme_;
    c.ta_ = ta_.data();
    c.z_ = z_.data();
    c.run_ = run_.data();
    c.part_ = part_.data();
    c.eset_ = eset_.data();
    return c;
  }

  int escape_set(int ctx) const { return eset_[static_cast<size_t>(ctx)]; }
  int context(size_t k, int tb, int mode = 0) { return cursor().context(k, tb, mode); }
  void update(size_t k, int tok) { cursor().update(k, tok); }
  void reset() {
    std::fill(ta_.begin(), ta_.end(), 0);
    std::fill(z_.begin(), z_.end(), 0);
    std::fill(run_.begin(), run_.end(), 0);
    std::fill(part_.begin(), part_.end(), 0);
  }

 private:
  int scheme_;
  std::vector<uint8_t> ta_, z_, run_;
  std::vector<uint16_t> part_;
  std::vector<uint8_t> eset_;
};

// Calls fn(std::integral_constant<int, m>()) for predictor m, so a loop over axes inside fn
// has its predictor fixed at compile time (one dispatch per point, not per axis). Ids without
// a case get fn(m) (a plain int).
template <typename Fn>
inline void with_predictor(int m, Fn&& fn) {
  switch (m) {
    case kPredPrevious: fn(std::integral_constant<int, kPredPrevious>()); break;
    case kPredLinear: fn(std::integral_constant<int, kPredLinear>()); break;
    case kPredQuadratic: fn(std::integral_constant<int, kPredQuadratic>()); break;
    case kPredTransform: fn(std::integral_constant<int, kPredTransform>()); break;
    case kPredTransformLinear: fn(std::integral_constant<int, kPredTransformLinear>()); break;
    case kPredSmooth: fn(std::integral_constant<int, kPredSmooth>()); break;
    case kPredPeriod: fn(std::integral_constant<int, kPredPeriod>()); break;
    case kPredPeriodPrevious: fn(std::integral_constant<int, kPredPeriodPrevious>()); break;
    default: fn(m);
  }
}

// Codes (or decodes) one window frame by frame, point by point, x, y, z (FORMAT.md 3.3):
// `code(i, pred, ctx, &tok)` returns q[i] and the residual's token. Gap samples are filled so
// histories stay defined. `period` is the window's period T (only read by predictors 8 and 9).
// Coder is trivially copyable: the walk codes through a local copy (kept in registers) and
// stores it back into `coder` at the end.
template <typename Coder>
void walk_window(size_t frames, size_t points, const uint8_t* valid, const uint8_t* modes,
                 const uint32_t* ref, const int32_t* t, int32_t* q, ResidualContexts& contexts,
                 Coder& coder, size_t period = 0) {
  Coder code = coder;
  ResidualContexts::Cursor ctx = contexts.cursor();
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
      // The three predictions first (none reads this point's frame f): one mode dispatch per
      // point, and the loads stay off the coder's chain from token to next context.
      int32_t pred[3];
      if (f == 0) {
        for (int a = 0; a < 3; ++a) pred[a] = transform ? t[i + a] : last[a];
      } else if (uses_ref(m)) {
        const int base = m == kPredRefPrevious ? kPredPrevious : kPredLinear;
        const size_t r = ref[p];
        const bool rv = valid[f * points + r] != 0;
        for (int a = 0; a < 3; ++a) {
          pred[a] = predict_one(base, f, q + i + a, stride, nullptr);
          if (rv) {
            const int32_t* qr = q + f * stride + r * 3 + a;
            pred[a] = wrap_add(pred[a], wrap_sub(*qr, predict_one(base, f, qr, stride, nullptr)));
          }
        }
      } else {
        with_predictor(m, [&](auto mode) {
          for (int a = 0; a < 3; ++a)
            pred[a] = predict_one(mode, f, q + i + a, stride, t ? t + i + a : nullptr, period);
        });
      }
      for (int a = 0; a < 3; ++a) {
        int tok;
        q[i + a] = code(i + a, pred[a], ctx.context(p * 3 + a, tb, m), &tok);
        ctx.update(p * 3 + a, tok);
        tb = tok;
      }
      if (f == 0) std::copy(q + i, q + i + 3, last);
    }
  }
  coder = code;
}

}  // namespace capz
