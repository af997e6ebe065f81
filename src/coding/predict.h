// Position predictors and the window coding loop, shared by encoder and decoder so both compute
// identical predictions (docs/FORMAT.md 8). All integer arithmetic wraps modulo 2^32.
//
// Shapes: q, t are frames x points x 3 int32 (frame-major); valid is frames x points.
#pragma once

#include <algorithm>
#include <cmath>
#include <cstddef>
#include <cstdint>
#include <type_traits>
#include <vector>

#include "coding/quantiser.h"

namespace capz {

enum Predictor : uint8_t {
  kPredPrevious = 0,         // q[f-1]
  kPredLinear = 1,           // 2 q[f-1] - q[f-2]
  kPredQuadratic = 2,        // 3 q[f-1] - 3 q[f-2] + q[f-3]
  kPredTransform = 3,        // t[f]  (the transform codec's reconstruction on the grid)
  kPredTransformLinear = 4,  // t[f] + linear extrapolation of (q - t)
  kPredRefPrevious = 5,      // q[f-1] + (q[f][r] - q[f-1][r]): reference point r < p's motion
  kPredRefLinear = 6,        // linear(p) + (q[f][r] - linear(r)): r's deviation from linear
  kPredSmooth = 7,           // least-squares line through the last min(6, f) frames (format 3)
  kPredPeriod = 8,           // q[f-T], T = the window's period (format 3)
  kPredPeriodPrevious = 9,   // q[f-1] + q[f-T] - q[f-T-1]
  kPredCount = 10,           // ids of scheme 3
  kPredRay = 10,             // lead axis q[f-1]; the others along the ray (format 7, 7.1)
};

// What predictor 10's ray rule reads the integers as (FORMAT.md 8.3): not allowed (a stream of
// major 6 or lower, or mode 3), the coordinate times a constant (modes 0, 1, 4), or ordered
// float32 bits (mode 2).
enum class RayKind : uint8_t { kNone = 0, kLinear = 1, kFloat32 = 2 };

// How predictor 10 reads a stream's integers: by major version and position mode (FORMAT.md 8.3).
inline RayKind ray_kind(int major, PosMode mode) {
  if (major < 7 || mode == PosMode::kFloat64) return RayKind::kNone;
  return mode == PosMode::kFloat32 ? RayKind::kFloat32 : RayKind::kLinear;
}

// Predictor ids a stream of position-coding scheme `scheme` may use (FORMAT.md 8), with
// predictor 10 where `ray` allows it (8.3).
inline int predictor_count(int scheme, RayKind ray = RayKind::kNone) {
  if (ray != RayKind::kNone && scheme >= 3) return kPredRay + 1;
  return scheme >= 3 ? kPredCount : scheme == 2 ? kPredSmooth : kPredRefPrevious;
}
// Predictors extrapolating the last two frames' motion: after a step on the grid their next
// residual tends to undo it, so scheme 3 gives them their own contexts.
inline bool extrapolates(int mode) {
  return mode == kPredLinear || mode == kPredQuadratic || mode == kPredTransformLinear ||
         mode == kPredRefLinear;
}
// Predictors that need the window's period field.
inline bool uses_period(int mode) {
  return mode == kPredPeriod || mode == kPredPeriodPrevious;
}

// Predictors that add a reference point's motion (docs/FORMAT.md 8); ref[p] = r < p.
inline bool uses_ref(int mode) {
  return mode == kPredRefPrevious || mode == kPredRefLinear;
}

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

// Predictor 10's lead axis (FORMAT.md 8.3): the axis of the largest |v(c[a])| of the previous
// frame's integers c, the lowest on ties, an unusable (not finite) value counting as 0.
inline int ray_lead(RayKind k, const int32_t* c) {
  double m[3];
  for (int a = 0; a < 3; ++a) {
    if (k == RayKind::kLinear) {
      m[a] = std::fabs(static_cast<double>(c[a]));
    } else {
      const float x = ordered_to_float(c[a]);
      m[a] = std::isfinite(x) ? std::fabs(static_cast<double>(x)) : 0.0;
    }
  }
  int l = 0;
  if (m[1] > m[l]) l = 1;
  if (m[2] > m[l]) l = 2;
  return l;
}

// Predictor 10's prediction of a non-lead axis (FORMAT.md 8.3): the previous frame's ca scaled
// by the lead axis's change cl -> ql, in binary64 (product, then quotient, each rounded);
// ca itself where the ratio is undefined or leaves the integers' range.
inline int32_t ray_predict(RayKind k, int32_t ca, int32_t cl, int32_t ql) {
  if (k == RayKind::kLinear) {
    if (cl == 0) return ca;
    const double u = (static_cast<double>(ca) * static_cast<double>(ql)) / static_cast<double>(cl);
    const double r = std::round(u);
    if (!(std::fabs(r) <= 2147483647.0)) return ca;
    return static_cast<int32_t>(r);
  }
  const float xa = ordered_to_float(ca), xl1 = ordered_to_float(cl), xl = ordered_to_float(ql);
  if (!std::isfinite(xa) || !std::isfinite(xl1) || !std::isfinite(xl) || xl1 == 0.0f) return ca;
  const double u = (static_cast<double>(xa) * static_cast<double>(xl)) / static_cast<double>(xl1);
  // From FLT_MAX + half its ulp up, u rounds to an infinity (the spec's "not finite"); tested
  // first, since converting such a double to float is undefined in C++.
  if (std::fabs(u) >= 0x1.ffffffp+127) return ca;
  return float_to_ordered(static_cast<float>(u));
}

// Predictor 7: the least-squares line through q[f-1] .. q[f-K], K = min(6, f), at frame f, as
// q[f-1] + rdiv(sum_{j=2..K} (4K + 2 - 6j) (q[f-j] - q[f-1]), K (K - 1)) (FORMAT.md 8).
// Differences wrap to int32; the sum (|.| < 5 * 26 * 2^31) cannot overflow int64.
// Always inlined: the walks call it per coordinate, where a call costs about as much as its body.
__attribute__((always_inline)) inline int32_t predict_smooth(size_t f, const int32_t* c,
                                                             size_t stride) {
  const int32_t q1 = *(c - stride);
  auto d = [&](size_t j) { return static_cast<int64_t>(wrap_sub(*(c - j * stride), q1)); };
  int64_t r;
  if (f >= 6) {  // K = 6, the usual case: a constant divisor (no division instruction)
    const int64_t n = 14 * d(2) + 8 * d(3) + 2 * d(4) - 4 * d(5) - 10 * d(6);
    r = n >= 0 ? (n + 15) / 30 : -((-n + 15) / 30);
  } else {
    const int64_t k = static_cast<int64_t>(f);
    if (k < 2) return q1;
    int64_t n = 0;
    for (int64_t j = 2; j <= k; ++j) n += (4 * k + 2 - 6 * j) * d(static_cast<size_t>(j));
    r = round_div(n, k * (k - 1));
  }
  return wrap_add(q1, static_cast<int32_t>(static_cast<uint32_t>(r)));
}

// Prediction of q[f] from the point's history. `c` points at q[f][p][a]; `stride` = points * 3;
// `tc` at t[f][p][a] (may be null when no transform ran); `period` is the window's period T
// (used by predictors 8 and 9 only). Requires f >= 1.
__attribute__((always_inline)) inline int32_t predict_one(int mode, size_t f, const int32_t* c,
                                                          size_t stride, const int32_t* tc,
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

// Scheme 3's refinement of a zero run (FORMAT.md 8.4): 2 h + g by the run z (0..12) and
// run = L << 1 | g (L = 0..16), h the phase of z against the previous run length L.
struct ZeroPhaseTable {
  uint8_t v[13][34];
};
constexpr ZeroPhaseTable zero_phase_table() {
  ZeroPhaseTable t{};
  for (int z = 0; z < 13; ++z)
    for (int run = 0; run < 34; ++run) {
      const int L = run >> 1;
      const int h = L == 0 || z < L - 1 ? 0 : z == L - 1 ? 1 : 2;
      t.v[z][run] = static_cast<uint8_t>(2 * h + (run & 1));
    }
  return t;
}
constexpr ZeroPhaseTable kZeroPhase = zero_phase_table();

// Escape sets by context for schemes 1, 2, 3 (FORMAT.md 2.4; see escape_set()): a table, as
// scheme 3's rule takes a modulo per coded value.
struct EscapeSetTable {
  uint8_t by_scheme[3][448];
};
constexpr EscapeSetTable escape_set_table() {
  EscapeSetTable t{};
  for (int c = 0; c < 448; ++c) {
    t.by_scheme[0][c] = 0;
    t.by_scheme[1][c] = static_cast<uint8_t>(c < 76 ? 0 : c < 80 ? 1 : 2);
    const int u = c % 56;
    t.by_scheme[2][c] = static_cast<uint8_t>(u < 54 ? 0 : u - 53);
  }
  return t;
}
constexpr EscapeSetTable kEscapeSetOfContext = escape_set_table();

// Residual contexts of a window (docs/FORMAT.md 8.4). Per point and axis: `ta`, the token of
// the last residual coded for it in this window, and `z`, the number of zero tokens ending there
// (capped at 12). Scheme 1 (format 1.x): 32 contexts from ta and tb (the token coded just before
// in the same frame). Scheme 2 (format 2.x): 84 contexts from ta or the zero run, and tb.
// Scheme 3 (format 3.x): 448 contexts: a state u (0..55) per point and axis (ta's bucket, or
// the zero run refined by its phase against the previous run length L and that run's sign g),
// tb, and whether the point's predictor extrapolates; u is updated once per coded token.
class ResidualContexts {
 public:
  ResidualContexts(int scheme, size_t points) : scheme_(scheme), st_(points * 3) {}
  static int count(int scheme) { return scheme == 1 ? 32 : scheme == 2 ? 84 : 448; }
  struct State {
    uint8_t ta = 0, z = 0, run = 0, u = 0;  // u: scheme 3's state, from the other three
  };

  // The contexts by raw pointer, trivially copyable (mechanics, not format): the walk works on
  // a local copy the compiler keeps in registers; through the object, every byte the walk
  // stores might alias its members and force reloads.
  class Cursor {
   public:
    // Escape model set of a context (1.3): scheme 2 states 18, 19, 20 use sets 0, 1, 2 (large
    // previous tokens: float-bit data), scheme 3 the same states (u = 53, 54, 55); scheme 1
    // set 0.
    int escape_set(int ctx) const { return eset_[ctx]; }
    // The offset of scheme 3's contexts for a point whose predictor is `mode` (0 otherwise).
    template <int Scheme>
    int family_as(int mode) const {
      return Scheme == 3 && extrapolates(mode) ? 224 : 0;
    }
    // Context of axis a of point p (k = 3 p + a, a = k % 3) when tb was coded last in the
    // frame, `fam` = family_as(the point's predictor); the scheme is fixed at compile time
    // (walk_window dispatches on scheme() once).
    template <int Scheme>
    int context_as(size_t k, int tb, int fam) const {
      const int t = tb < 3 ? tb : 3;
      const State& s = st_[k];
      if (Scheme == 3) return fam + 56 * t + s.u;
      if (Scheme == 1) return std::min<int>(s.ta, 7) * 4 + t;
      return (s.ta ? kTokBucket[s.ta] : kRunBucket[s.z]) * 4 + t;
    }
    int scheme() const { return scheme_; }
    void update(size_t k, int tok) {
      State& s = st_[k];
      if (tok) {
        // run = L << 1 | g: L the previous run length + 1 (capped at 16, 0 = none), g its sign.
        if (!s.ta) s.run = static_cast<uint8_t>((s.z + 1) << 1 | (tok & 1));  // z + 1 <= 13
        s.ta = static_cast<uint8_t>(tok);
        s.z = 0;
        s.u = static_cast<uint8_t>(42 + kTokBucket[tok] - 7);
      } else {
        s.ta = 0;
        s.z = static_cast<uint8_t>(s.z < 12 ? s.z + 1 : 12);
        s.u = static_cast<uint8_t>(6 * kRunBucket[s.z] + kZeroPhase.v[s.z][s.run]);
      }
    }

   private:
    friend class ResidualContexts;
    int scheme_ = 0;
    State* st_ = nullptr;
    const uint8_t* eset_ = nullptr;  // escape set by context (kEscapeSetOfContext)
  };
  Cursor cursor() {
    Cursor c;
    c.scheme_ = scheme_;
    c.st_ = st_.data();
    c.eset_ = kEscapeSetOfContext.by_scheme[scheme_ == 1 ? 0 : scheme_ == 2 ? 1 : 2];
    return c;
  }

  void reset() { std::fill(st_.begin(), st_.end(), State()); }

 private:
  static constexpr uint8_t kRunBucket[13] = {0, 1, 2, 3, 4, 4, 5, 5, 5, 6, 6, 6, 6};
  static constexpr uint8_t kTokBucket[64] = {
      0,  7,  8,  9,  10, 11, 12, 13, 14, 14, 14, 14, 15, 15, 16, 16,  // 0-15
      17, 17, 17, 17, 18, 18, 18, 18, 18, 18, 18, 18, 19, 19, 19, 19,  // 16-31
      19, 19, 19, 19, 20, 20, 20, 20, 20, 20, 20, 20, 20, 20, 20, 20,  // 32-47
      20, 20, 20, 20, 20, 20, 20, 20, 20, 20, 20, 20, 20, 20, 20, 20};
  int scheme_;
  std::vector<State> st_;
};

// Calls fn(std::integral_constant<int, m>()) for predictor m, so a loop over axes inside fn
// has its predictor fixed at compile time (one dispatch per point, not per axis). Ids without
// a case get fn(m) (a plain int).
template <typename Fn>
inline void with_predictor(int m, Fn&& fn) {
  switch (m) {
    case kPredPrevious:
      fn(std::integral_constant<int, kPredPrevious>());
      break;
    case kPredLinear:
      fn(std::integral_constant<int, kPredLinear>());
      break;
    case kPredQuadratic:
      fn(std::integral_constant<int, kPredQuadratic>());
      break;
    case kPredTransform:
      fn(std::integral_constant<int, kPredTransform>());
      break;
    case kPredTransformLinear:
      fn(std::integral_constant<int, kPredTransformLinear>());
      break;
    case kPredSmooth:
      fn(std::integral_constant<int, kPredSmooth>());
      break;
    case kPredPeriod:
      fn(std::integral_constant<int, kPredPeriod>());
      break;
    case kPredPeriodPrevious:
      fn(std::integral_constant<int, kPredPeriodPrevious>());
      break;
    default:
      fn(m);
  }
}

// walk_window with the contexts' scheme fixed at compile time, so the per-value path has no
// branch on it, and predictor 10 compiled in only where the stream may use it (Ray: its code
// in the loop would change how the compiler inlines the coder into the walks of other streams;
// the rule's RayKind is then the coder's `ray`).
template <int Scheme, bool Ray, typename Coder>
void walk_window_as(size_t frames, size_t points, const uint8_t* valid, const uint8_t* modes,
                    const uint32_t* ref, const int32_t* t, int32_t* q, ResidualContexts::Cursor ctx,
                    Coder& coder, size_t period) {
  Coder code = coder;
  const size_t stride = points * 3;
  for (size_t f = 0; f < frames; ++f) {
    int tb = 0;
    int32_t last[3] = {0, 0, 0};
    for (size_t p = 0; p < points; ++p) {
      const size_t i = f * stride + p * 3;
      const int m = modes[p];
      const int fam = ctx.family_as<Scheme>(m);
      const bool transform = m == kPredTransform || m == kPredTransformLinear;
      if (!valid[f * points + p]) {
        for (int a = 0; a < 3; ++a)
          q[i + a] = f == 0 ? (transform ? t[i + a] : last[a]) : q[i + a - stride];
        continue;
      }
      if constexpr (Ray) {
        if (m == kPredRay && f > 0) {  // 7.1: the lead axis first, the others along the ray
          const int32_t* c = q + i - stride;
          const RayKind ray = code.ray;
          const int l = ray_lead(ray, c);
          int tok;
          q[i + l] = code(i + l, c[l], ctx.context_as<Scheme>(p * 3 + l, tb, 0), &tok);
          ctx.update(p * 3 + l, tok);
          tb = tok;
          for (int a = 0; a < 3; ++a) {
            if (a == l) continue;
            const int32_t pa = ray_predict(ray, c[a], c[l], q[i + l]);
            q[i + a] = code(i + a, pa, ctx.context_as<Scheme>(p * 3 + a, tb, 0), &tok);
            ctx.update(p * 3 + a, tok);
            tb = tok;
          }
          continue;
        }
      }
      // The three predictions first (none reads this point's frame f): one mode dispatch per
      // point, and the loads stay off the coder's chain from token to next context.
      int32_t pred[3];
      if (f == 0) {
        for (int a = 0; a < 3; ++a) pred[a] = transform ? t[i + a] : last[a];
      } else if (uses_ref(m)) {
        const size_t r = ref[p];
        const bool rv = valid[f * points + r] != 0;
        with_predictor(m == kPredRefPrevious ? kPredPrevious : kPredLinear, [&](auto base) {
          for (int a = 0; a < 3; ++a) {
            pred[a] = predict_one(base, f, q + i + a, stride, nullptr);
            if (rv) {
              const int32_t* qr = q + f * stride + r * 3 + a;
              pred[a] = wrap_add(pred[a], wrap_sub(*qr, predict_one(base, f, qr, stride, nullptr)));
            }
          }
        });
      } else {
        with_predictor(m, [&](auto mode) {
          for (int a = 0; a < 3; ++a)
            pred[a] = predict_one(mode, f, q + i + a, stride, t ? t + i + a : nullptr, period);
        });
      }
      for (int a = 0; a < 3; ++a) {
        int tok;
        q[i + a] = code(i + a, pred[a], ctx.context_as<Scheme>(p * 3 + a, tb, fam), &tok);
        ctx.update(p * 3 + a, tok);
        tb = tok;
      }
      if (f == 0) std::copy(q + i, q + i + 3, last);
    }
  }
  coder = code;
}

// Codes (or decodes) one window frame by frame, point by point, x, y, z (FORMAT.md 8):
// `code(i, pred, ctx, &tok)` returns q[i] and the residual's token. Gap samples are filled so
// histories stay defined. `period` is the window's period T (only read by predictors 8 and 9).
// Coder is trivially copyable: the walk codes through a local copy (kept in registers) and
// stores it back into `coder` at the end.
// Predictor 10 is not coded here: walk_window_ray is the walk of a stream that may hold it.
template <typename Coder>
void walk_window(size_t frames, size_t points, const uint8_t* valid, const uint8_t* modes,
                 const uint32_t* ref, const int32_t* t, int32_t* q, ResidualContexts& contexts,
                 Coder& coder, size_t period = 0) {
  const ResidualContexts::Cursor ctx = contexts.cursor();
  switch (ctx.scheme()) {
    case 3:
      return walk_window_as<3, false>(frames, points, valid, modes, ref, t, q, ctx, coder, period);
    case 2:
      return walk_window_as<2, false>(frames, points, valid, modes, ref, t, q, ctx, coder, period);
    default:
      return walk_window_as<1, false>(frames, points, valid, modes, ref, t, q, ctx, coder, period);
  }
}

// walk_window for a scheme-3 stream whose points may use predictor 10, which reads the integers
// as coder.ray says (FORMAT.md 8.3): from frame 1 on, such a point's lead axis is coded first,
// then the other two along the ray. Instantiated in its own translation unit
// (positions_ray.cpp), so that its extra coding sites do not change how the compiler inlines the
// coder into the walks of every other stream.
template <typename Coder>
void walk_window_ray(size_t frames, size_t points, const uint8_t* valid, const uint8_t* modes,
                     const uint32_t* ref, const int32_t* t, int32_t* q, ResidualContexts& contexts,
                     Coder& coder, size_t period) {
  walk_window_as<3, true>(frames, points, valid, modes, ref, t, q, contexts.cursor(), coder,
                          period);
}

}  // namespace capz
