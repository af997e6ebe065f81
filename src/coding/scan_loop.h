// The one coding loop of a scan frame (docs/FORMAT.md "Scans (format 1.1)"), shared by the
// encoder, the decoder and the encoder's cost estimate. Included by scan_shared.h only.
#pragma once

#include <algorithm>
#include <cstdint>

#include "coding/predict.h"

namespace capz {
namespace scan {

namespace detail {

// The running score of a predictor: about 8 x its mean absolute error of late.
inline void score(uint32_t* s, int32_t a, int32_t b) {
  const int64_t e = static_cast<int64_t>(a) - b;
  const uint32_t m = static_cast<uint32_t>(std::min<int64_t>(e < 0 ? -e : e, 1 << 20));
  *s = *s - (*s >> 3) + m;
}
// The running score of a ring prediction: misses count.
inline void ring_score(uint32_t* s, uint32_t k, uint32_t khat, uint32_t rings) {
  *s = *s - (*s >> 4) + (k == khat ? 0u : 16u + 0u * rings);
}
// v % n for v < 3 n.
inline uint32_t mod_small(uint32_t v, uint32_t n) {
  if (v >= n) v -= n;
  if (v >= n) v -= n;
  return v;
}
// The least of n scores (the first on ties).
inline int argmin(const uint32_t* s, int n) {
  int b = 0;
  for (int j = 1; j < n; ++j)
    if (s[j] < s[b]) b = j;
  return b;
}

template <class Io>
void code_cartesian(Io& io, State& st, const int32_t* a, int32_t* p) {
  for (int ax = 0; ax < 3; ++ax) {
    const int ctx = kCtxCart + ax * 8 + std::min((st.last_bits[ax] + 1) / 2, 7);
    p[ax] = io.sym(a[ax], st.last[ax], ctx);
    st.last_bits[ax] = bit_length(wrap_sub(p[ax], st.last[ax]));
    st.last[ax] = p[ax];
  }
}

// The frame's running spherical context: the previous valid point of this frame.
struct Prev {
  bool have = false;
  uint32_t ring = 0, ring_residual = 0;
  int32_t column = 0, range = 0;
  uint32_t before = 0;  // the ring of the point before it
};

template <class Io>
void code_spherical(Io& io, State& st, const Polar& pa, const int32_t* a, Prev* pv, int32_t* p) {
  const Table& t = st.table();
  const uint32_t rings = static_cast<uint32_t>(t.rings());
  // Ring: the one that followed the previous point's ring last time, or the previous step's
  // continuation (runs of rings up or down), whichever has done better lately.
  // (Rings, and so pv->ring and pv->before, are below `rings`; so is d, which io.ring checks:
  // each % below is a subtraction or two.)
  const uint32_t k1 = pv->have ? st.succ[pv->ring] : 0;
  const uint32_t k2 = pv->have ? mod_small(2 * pv->ring + rings - pv->before, rings) : 0;
  const int sk = st.ring_score[1] < st.ring_score[0] ? 1 : 0;
  const uint32_t khat = sk ? k2 : k1;
  const uint32_t d =
      io.ring(mod_small(pa.ring + rings - khat, rings), rings, kCtxRing + (pv->ring_residual != 0));
  const uint32_t k = mod_small(khat + d, rings);
  if (pv->have) st.succ[pv->ring] = k;
  ring_score(&st.ring_score[0], k, k1, rings);
  ring_score(&st.ring_score[1], k, k2, rings);
  State::Ring& r = st.ring[k];
  // Column: the previous point's (same firing) or the ring's last plus its step.
  const int32_t p0 = pv->have ? pv->column : (r.has_last ? r.last_column : 0);
  const int32_t p1 = r.has_last ? wrap_add(r.last_column, r.step) : p0;
  const int sc = detail::argmin(r.score_col, 2);
  const int cctx = kCtxColumn + 4 * (d != 0) + std::min(bit_length(r.score_col[sc] >> 2), 3);
  const int32_t col = io.sym(pa.column, sc ? p1 : p0, cctx);
  score(&r.score_col[0], col, p0);
  score(&r.score_col[1], col, p1);
  // Range: the ring's last, the previous point's (same column), the previous sweep's.
  const int32_t w = r.has_last ? r.last_range : (pv->have ? pv->range : 0);
  int32_t cand[3] = {w, w, w};
  if (pv->have && pv->column == col) cand[1] = pv->range;
  int32_t m;
  if (st.map_prev(k, col, &m)) cand[2] = m;
  const int sr = detail::argmin(r.score_range, 3);
  const int rctx = kCtxRange + std::min(bit_length(r.score_range[sr] >> 1), 15);
  const int32_t range = io.sym(pa.range, cand[sr], rctx);
  for (int j = 0; j < 3; ++j) score(&r.score_range[j], range, cand[j]);
  // x y on the column's azimuth at that range, z on the ring's cone.
  const double phi = static_cast<double>(t.azimuth0[k]) + static_cast<double>(col) * t.step;
  double s, c;
  det_sincos(phi, &s, &c);
  const bool units = !t.unit.empty();
  const double rho =
      units ? static_cast<double>(range) * t.unit[k] + t.offset[k] : static_cast<double>(range);
  const int32_t xh = round_clamp(rho * c), yh = round_clamp(rho * s);
  const int32_t zh =
      round_clamp(static_cast<double>(t.z0[k]) + static_cast<double>(t.slope[k]) * rho);
  const int lb = std::min(bit_length(units ? round_clamp(rho) : range), 23);
  p[0] = io.sym(a[0], xh, kCtxX + lb);
  p[1] = io.sym(a[1], yh, kCtxY + 2 * lb + (p[0] != xh));
  p[2] = io.sym(a[2], zh, kCtxZ + lb);
  if (r.has_last) r.step = wrap_sub(col, r.last_column);
  r.last_column = col;
  r.last_range = range;
  r.has_last = true;
  st.map_set(k, col, range);
  *pv = Prev{true, k, d, col, range, pv->have ? pv->ring : k};
}

}  // namespace detail

template <class Io>
void code_points(Io& io, State& st, uint8_t flags, size_t first, size_t n, int32_t* q_out,
                 uint8_t* valid_out) {
  const uint8_t vmode = flags & 3;
  const bool spherical = (flags & kSpherical) != 0;
  bool prev_valid = true;
  detail::Prev pv;
  for (size_t i = 0; i < n; ++i) {
    bool v = vmode == kAllValid;
    if (vmode == kSomeValid) v = io.flag(io.actual_valid(first + i), kCtxValid + prev_valid);
    prev_valid = v;
    valid_out[i] = v;
    int32_t* p = q_out + 3 * i;
    if (!v) {
      p[0] = p[1] = p[2] = 0;
      continue;
    }
    const int32_t* a = io.actual(first + i);
    if (spherical)
      detail::code_spherical(io, st, io.polar(first + i), a, &pv, p);
    else
      detail::code_cartesian(io, st, a, p);
  }
}

template <class Io>
void code_frame(Io& io, State& st, uint8_t flags, size_t first, size_t n, int32_t* q_out,
                uint8_t* valid_out) {
  code_points(io, st, flags, first, n, q_out, valid_out);
  st.end_frame();
}

}  // namespace scan
}  // namespace capz
