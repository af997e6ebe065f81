// The one coding loop of a scan frame (docs/FORMAT.md "Scans (format 1.1)"), shared by the
// encoder, the decoder and the encoder's cost estimate. Included by scan_shared.h only.
#pragma once

#include <algorithm>
#include <cstdint>
#include <type_traits>

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

// FORMAT's fraction rule: v against pred, the rounding of u (fr = u - pred, known to the
// decoder): the context by |fr| (3 from ctx), the residual's sign flipped when fr < 0.
// (kPlain: the value is one of value_kind's plain ones, coded by io.sym_plain.)
template <bool kPlain = false, class Io>
__attribute__((always_inline)) inline int32_t sym_fraction(Io& io, int32_t v, int32_t pred,
                                                           double fr, int ctx) {
  // Without branches (fr is as likely either way): b by two comparisons, the sign flipped by
  // m, all ones when fr < 0 ((x ^ m) - m is then -x, wrapping, else x).
  const double af = std::fabs(fr);
  const int b = static_cast<int>(af >= 0.1875) + static_cast<int>(af >= 0.375);
  const uint32_t m = 0u - static_cast<uint32_t>(fr < 0);
  const auto flip = [m](int32_t x) {
    return static_cast<int32_t>((static_cast<uint32_t>(x) ^ m) - m);
  };
  if (kPlain) return flip(io.sym_plain(flip(v), flip(pred), ctx + b));
  return flip(io.sym(flip(v), flip(pred), ctx + b));
}

// floor(a / 16) for the smoothed ranges (|a| < 2^40).
inline int64_t floor_div16(int64_t a) {
  return a >= 0 ? a / 16 : -((15 - a) / 16);
}

// sqrt(max(e, 0)): IEEE's correctly rounded square root, the same on every build.
inline double root0(double e) {
  return std::sqrt(e > 0 ? e : 0.0);
}

// The second of x y from the azimuth like the first (FORMAT step 4, a frame without bit 6).
template <class Io>
__attribute__((always_inline)) inline void second_azimuth(Io& io, double rho, double c, double s,
                                                          int i1, int lb, const int32_t* a,
                                                          int32_t* p) {
  const double u1 = rho * (i1 == 0 ? c : s);
  const int32_t h1 = round_clamp(u1);
  p[i1] = sym_fraction(io, a[i1], h1, u1 - h1, kCtxY + 3 * std::min(lb, 15));
}

// The second of x y from the range's hypotenuse with the first (p[i0], predicted h0; FORMAT
// step 4, a frame with bit 6), its context by how many integers lie within half a grid step of
// the range.
template <class Io>
__attribute__((always_inline)) inline void second_hypot(Io& io, double rho, double c, double s,
                                                        int i0, int32_t h0, const int32_t* a,
                                                        int32_t* p) {
  const int i1 = 1 - i0;
  const double half = 0.5;
  const double o = static_cast<double>(p[i0]), oo = o * o;
  const double g = (i1 == 0 ? c : s) < 0 ? -1.0 : 1.0;
  const double u1 = g * root0(rho * rho - oo);
  const int32_t h1 = round_clamp(u1);
  const double hi = (rho + half) * (rho + half) - oo, lo = (rho - half) * (rho - half) - oo;
  const double n = floor_fast(-root0(lo)) - floor_fast(-root0(hi));  // ceil(m(hi)) - ceil(m(lo))
  const int ni = n <= 0 ? 0 : n >= 3 ? 3 : static_cast<int>(n);
  p[i1] = sym_fraction(io, a[i1], h1, u1 - h1, kCtxAxis2 + 3 * (2 * ni + (p[i0] != h0)));
}

// Whether Io codes the second of x y both ways (the encoder's trial: Io::kBothSeconds, the
// hypotenuse's symbol first, in its own contexts), else as the frame's bit 6 says.
template <class Io, class = void>
struct BothSeconds : std::false_type {};
template <class Io>
struct BothSeconds<Io, std::void_t<decltype(Io::kBothSeconds)>>
    : std::integral_constant<bool, Io::kBothSeconds> {};

// x y z of a spherical point (FORMAT "Scan geometry payload", step 4): the axis less aligned
// with the azimuth first, from rho cos or sin; the other from the azimuth as well, or with
// `hypot` (bit 6) from the range's hypotenuse; z on the ring's cone (bent by the table's bow).
// (rho: the range in grid units; lb: the contexts' bit length.)
template <class Io>
__attribute__((always_inline)) inline void code_xyz(Io& io, const Table& t, const Angles& an,
                                                    bool hypot, uint32_t k, int32_t col, double rho,
                                                    int lb, const int32_t* a, int32_t* p) {
  double s, c;
  an.of(k, col, &s, &c);
  const int i0 = std::fabs(c) <= std::fabs(s) ? 0 : 1, i1 = 1 - i0;
  const double u0 = rho * (i0 == 0 ? c : s);
  const int32_t h0 = round_clamp(u0);
  p[i0] = sym_fraction(io, a[i0], h0, u0 - h0, kCtxAxis1 + 3 * lb);
  if (BothSeconds<Io>::value) {
    second_hypot(io, rho, c, s, i0, h0, a, p);
    second_azimuth(io, rho, c, s, i1, lb, a, p);
  } else if (hypot) {
    second_hypot(io, rho, c, s, i0, h0, a, p);
  } else {
    second_azimuth(io, rho, c, s, i1, lb, a, p);
  }
  const double slope = static_cast<double>(t.slope[k]) + static_cast<double>(t.bow) * (1.0 - c);
  const double uz = static_cast<double>(t.z0[k]) + slope * rho;
  const int32_t zh = round_clamp(uz);
  p[2] = sym_fraction(io, a[2], zh, uz - zh, kCtxZFrac + 3 * lb);
}

template <class Io>
__attribute__((always_inline)) inline void code_cartesian(Io& io, State& st, const int32_t* a,
                                                          int32_t* p) {
  for (int ax = 0; ax < 3; ++ax) {
    const int ctx = kCtxCart + ax * 8 + std::min((st.last_bits[ax] + 1) / 2, 7);
    p[ax] = io.sym_plain(a[ax], st.last[ax], ctx);
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
  bool repeat = false;  // ring walk: the point repeated its predecessor's ring
  int64_t firing = 0;   // ring walk: the firing counter F
};

// A point's ring and column as coded (FORMAT steps 1 and 2): `residual` is the ring residual
// its successor sees; `opened` whether it opened its ring's firing one after the ring's last
// (ring walk frames: the ring's step is updated only then).
struct RingColumn {
  uint32_t ring = 0, residual = 0;
  int32_t column = 0;
  bool repeat = false, opened = true;
  int64_t firing = 0;
};

// The firing's base (FORMAT step 2, units bit 3): ring k's column from the active interval,
// after opening a firing when the ring's share is not after the last point's (else p1).
inline int32_t base_predict(State::Base& b, const Table& t, uint32_t k, int32_t p1) {
  if (!b.open) return p1;
  const double s = t.share[k];
  if (s <= b.last_share) {
    const double turn = t.fire_turn, lo = b.lo[b.active] + turn, hi = b.hi[b.active] + turn;
    b.lo[0] = b.lo[1] = lo;
    b.hi[0] = b.hi[1] = hi;
    b.live[0] = b.live[1] = true;
  }
  const double o = b.active == 0 ? static_cast<double>(t.fire_turn) * s : 0.0;
  return round_clamp((b.lo[b.active] + b.hi[b.active]) / 2 + o);
}

// The firing's base takes ring k's column c (FORMAT step 5, units bit 3).
inline void base_update(State::Base& b, const Table& t, uint32_t k, int32_t c) {
  const double s = t.share[k], o[2] = {static_cast<double>(t.fire_turn) * s, 0.0};
  const double cd = static_cast<double>(c);
  bool any = false;
  for (int j = 0; j < 2 && b.open; ++j) {
    if (!b.live[j]) continue;
    const double lo = std::max(b.lo[j], cd - o[j] - 0.5), hi = std::min(b.hi[j], cd - o[j] + 0.5);
    b.live[j] = !(lo > hi);
    if (b.live[j]) b.lo[j] = lo, b.hi[j] = hi, any = true;
  }
  if (!any) {
    for (int j = 0; j < 2; ++j)
      b.lo[j] = cd - o[j] - 0.5, b.hi[j] = cd - o[j] + 0.5, b.live[j] = true;
    if (!b.open) b.active = 0;
    b.open = true;
  }
  if (!b.live[b.active]) b.active = b.live[0] ? 0 : 1;
  b.last_share = s;
}

// floor(a / b) for b > 0.
inline int64_t floor_div(int64_t a, int64_t b) {
  return a >= 0 ? a / b : -((b - 1 - a) / b);
}

// A column on the firing's slots (FORMAT step 2, units bit 6): floor((B N + D m + N) / 2N).
inline int64_t slot_column(int64_t n, int64_t b, int64_t d, int64_t m) {
  return floor_div(b * n + d * m + n, 2 * n);
}

// The column on the firing's slots (FORMAT step 2, units bit 6) of point i: when the ring's slot
// is not after the last point's, a firing opens with its turn D and base B (io.fire(i) when
// encoding); the column against floor((B N + D m_k + N) / 2N).
template <class Io>
__attribute__((always_inline)) inline int32_t code_slots(Io& io, State::Slots& f, const Table& t,
                                                         uint32_t k, const Polar& pa, size_t i,
                                                         bool moved) {
  const uint32_t m = t.slot[k];
  if (!f.open || m <= f.last) {
    const Fire fa = io.fire(i);
    const int32_t d = io.sym(fa.d, f.d, kCtxSlots + (f.d == 0));
    const int32_t b = io.sym(fa.b, wrap_add(f.b, f.d), kCtxSlots + 2 + 2 * (f.d == 0) + (d != f.d));
    f.b = b, f.d = d, f.open = true;
  }
  f.last = m;
  const int64_t p = slot_column(t.slots, f.b, f.d, m);
  return io.sym(pa.column, static_cast<int32_t>(static_cast<uint32_t>(p)), kCtxSlots + 6 + moved);
}

// The ring's column (FORMAT step 2) of point i from p0 and p1 (and with the table's `turn` p2,
// with its shares p3; with its slots the firing's), the context's first part by the residual.
template <class Io>
__attribute__((always_inline)) inline int32_t code_column(Io& io, State& st, State::Ring& r,
                                                          uint32_t k, const Polar& pa, size_t i,
                                                          int32_t p0, int32_t p1, bool moved,
                                                          const Prev* pv) {
  const int32_t col = pa.column;
  if (st.table().slots) return code_slots(io, st.slots, st.table(), k, pa, i, moved);
  if (st.table().turn) {
    // p2: P's column plus the ring's lead on P's ring, or the ring's last column plus how far
    // P's ring turned since.
    const State::Ring& b = st.ring[pv->ring];
    int32_t p2 = p1;
    if (pv->have && r.has_lead && r.lead_ring == pv->ring)
      p2 = wrap_add(pv->column, r.lead);
    else if (pv->have && r.has_last && b.has_before)
      p2 = wrap_add(r.last_column, wrap_sub(pv->column, b.before_column));
    // p3 (the firing's base) only with the table's shares.
    const int n = st.table().share.empty() ? 3 : 4;
    const int32_t p[4] = {p0, p1, p2, n == 4 ? base_predict(st.base, st.table(), k, p1) : p1};
    const int sc = detail::argmin(r.score_col, n);
    const int bl = std::min(bit_length(r.score_col[sc] >> 2), 3);
    const int32_t c =
        io.sym(col, p[sc],
               sc == 3 ? kCtxShare + 4 * moved + bl : kCtxTurn + 8 * (sc == 2) + 4 * moved + bl);
    for (int j = 0; j < n; ++j) score(&r.score_col[j], c, p[j]);
    return c;
  }
  const int sc = detail::argmin(r.score_col, 2);
  const int cctx = kCtxColumn + 4 * moved + std::min(bit_length(r.score_col[sc] >> 2), 3);
  const int32_t c = io.sym(col, sc ? p1 : p0, cctx);
  score(&r.score_col[0], c, p0);
  score(&r.score_col[1], c, p1);
  return c;
}

// The ring of a ring pair frame (FORMAT "Ring pair frames", step 1): its place among the
// candidates khat, `other`, the ring's successor and the ring above P's, else n plus the
// zig-zag of its signed residual against khat. *u: the symbol.
template <class Io>
__attribute__((always_inline)) inline uint32_t pair_ring(Io& io, const State& st, uint32_t want,
                                                         const Prev* pv, uint32_t khat,
                                                         uint32_t other, uint32_t* u) {
  const uint32_t rings = static_cast<uint32_t>(st.table().rings());
  // With the previous sweep's successors, the ring that followed P's cell then comes first.
  uint32_t k0 = 0;
  const bool has_k0 = st.table().successors && st.map_prev_successor(pv->ring, pv->column, &k0);
  uint32_t c[5] = {k0, khat, other, st.succ[pv->ring], pv->ring + 1 == rings ? 0 : pv->ring + 1};
  uint32_t* cc = has_k0 ? c : c + 1;  // the candidates, in order
  const uint32_t all = has_k0 ? 5 : 4;
  // The place of v among the first m candidates (m when absent): a loop of at most 5, inline
  // (std::find's out-of-line unrolled search cost more than the search).
  const auto place = [cc](uint32_t m, uint32_t v) {
    uint32_t j = 0;
    while (j < m && cc[j] != v) ++j;
    return j;
  };
  uint32_t n = 1;
  for (uint32_t j = 1; j < all; ++j)
    if (place(n, cc[j]) == n) cc[n++] = cc[j];
  uint32_t a = place(n, want);
  if (a == n) {  // the encoder's residual (the decoder's `want` is anything)
    const uint32_t d = mod_small(want + rings - khat, rings);
    a = n + zigzag(d <= (rings - 1) / 2 ? static_cast<int32_t>(d)
                                        : static_cast<int32_t>(d) - static_cast<int32_t>(rings));
  }
  *u = io.ring(a, n + rings, kCtxPairRing + static_cast<int>(std::min(pv->ring_residual, 5u)));
  if (*u < n) return cc[*u];
  return mod_small(static_cast<uint32_t>(static_cast<int32_t>(khat + rings) + unzigzag(*u - n)),
                   rings);
}

// Ring and column of point i (pa) in a frame without bit 3: the ring against the successor or
// the run. (pairs: a ring pair frame, FORMAT "Ring pair frames".)
template <class Io>
__attribute__((always_inline)) inline RingColumn ring_successor(Io& io, State& st, const Polar& pa,
                                                                size_t i, const Prev* pv,
                                                                bool pairs) {
  const uint32_t rings = static_cast<uint32_t>(st.table().rings());
  // Ring: the one that followed the previous point's ring last time, or the previous step's
  // continuation (runs of rings up or down), whichever has done better lately.
  // (Rings, and so pv->ring and pv->before, are below `rings`; so is d, which io.ring checks:
  // each % below is a subtraction or two.)
  uint32_t k1 = pv->have ? st.succ[pv->ring] : 0;
  uint16_t* after_pair =
      pairs && pv->have ? &st.pair_ring[st.pair_cell(pv->before, pv->ring)] : nullptr;
  if (after_pair && *after_pair) k1 = *after_pair - 1u;
  const uint32_t k2 = pv->have ? mod_small(2 * pv->ring + rings - pv->before, rings) : 0;
  const int sk = st.ring_score[1] < st.ring_score[0] ? 1 : 0;
  const uint32_t khat = sk ? k2 : k1;
  uint32_t d, k;
  if (after_pair) {
    k = pair_ring(io, st, pa.ring, pv, khat, sk ? k1 : k2, &d);
    if (st.table().successors) st.map_set_successor(pv->ring, pv->column, k);
  } else {
    d = io.ring(mod_small(pa.ring + rings - khat, rings), rings,
                kCtxRing + (pv->ring_residual != 0));
    k = mod_small(khat + d, rings);
  }
  if (pv->have) st.succ[pv->ring] = k;
  ring_score(&st.ring_score[0], k, k1, rings);
  ring_score(&st.ring_score[1], k, k2, rings);
  State::Ring& r = st.ring[k];
  // Column: the previous point's (same firing; in a ring pair frame plus the pair's step) or the
  // ring's last plus its step.
  int32_t* pair_step = nullptr;
  if (after_pair) {
    *after_pair = static_cast<uint16_t>(k + 1);
    pair_step = &st.pair_column[st.pair_cell(pv->ring, k)];
  }
  const int32_t p0 = pv->have ? wrap_add(pv->column, pair_step ? *pair_step : 0)
                              : (r.has_last ? r.last_column : 0);
  const int32_t p1 = r.has_last ? wrap_add(r.last_column, r.step) : p0;
  RingColumn out;
  out.ring = k;
  out.residual = d;
  out.column = code_column(io, st, r, k, pa, i, p0, p1, d != 0, pv);
  if (pair_step) *pair_step = wrap_sub(out.column, pv->column);
  return out;
}

// The ring walk (FORMAT "Ring walk frames", step 1) after the previous point P: the repeat
// flag, else a flag per ring after P's until the point's. Returns the ring; sets *firing (F)
// and *steps (the walk's flags before the one that ended it).
template <class Io>
uint32_t walk_ring(Io& io, const State& st, uint32_t want, const Prev* pv, bool* repeat,
                   int64_t* firing, uint32_t* steps) {
  const uint32_t rings = static_cast<uint32_t>(st.table().rings()), pr = pv->ring;
  const State::Firing& fb = st.firing[pr == 0 ? rings - 1 : pr - 1];
  const int b = fb.last == pv->firing ? static_cast<int>(std::min<uint32_t>(fb.n, 2)) : 3;
  const int rctx = kCtxWalkRepeat + 12 * pv->repeat +
                   4 * static_cast<int>(std::min<uint32_t>(st.firing[pr].m, 2)) + b;
  *steps = 0;
  *firing = pv->firing;
  *repeat = io.flag(want == pr, rctx);
  if (*repeat) return pr;
  uint32_t j = pr + 1 == rings ? 0 : pr + 1;
  int64_t g0 = pv->firing + (j == 0);  // G: the firing ring j would be in
  for (; j != pr; ++*steps) {
    const int64_t fj = st.firing[j].last;
    const int g = fj < 0 ? 3 : static_cast<int>(std::min<int64_t>(g0 - fj, 3));
    const int64_t fi = st.firing[j + 1 == rings ? 0 : j + 1].last;
    const int a = fi >= 0 && fi >= g0 - 1;
    const int band = static_cast<int>(uint64_t{8} * j / rings);
    const int ctx = kCtxWalk + 32 * g + 16 * (*steps == 0) + 8 * a + band;
    if (io.flag(want == j, ctx)) break;
    j = j + 1 == rings ? 0 : j + 1;
    g0 += j == 0;
  }
  *firing = g0;
  return j;
}

// Ring and column of point i (pa) in a ring walk frame (FORMAT "Ring walk frames", steps 1
// and 2).
template <class Io>
__attribute__((always_inline)) inline RingColumn ring_walk(Io& io, State& st, const Polar& pa,
                                                           size_t i, const Prev* pv) {
  RingColumn out;
  if (!pv->have) {  // the frame's first point: its ring as a residual against ring 0
    out.ring = io.ring(pa.ring, static_cast<uint32_t>(st.table().rings()), kCtxRing);
    out.residual = out.ring;
  } else {
    out.ring = walk_ring(io, st, pa.ring, pv, &out.repeat, &out.firing, &out.residual);
  }
  State::Firing& f = st.firing[out.ring];
  const int64_t was = f.last;  // f' (FORMAT)
  if (f.last == out.firing) {
    ++f.n;
  } else {
    f.m = f.last == out.firing - 1 ? f.n : 0;
    f.n = 1;
    f.last = out.firing;
  }
  out.opened = was >= 0 && was == out.firing - 1;
  State::Ring& r = st.ring[out.ring];
  if (out.repeat && st.table().slots) {  // on the firing's slots like every point
    out.column = code_slots(io, st.slots, st.table(), out.ring, pa, i, false);
    return out;
  }
  if (out.repeat) {  // the same firing's second return: P's column
    out.column = io.sym(pa.column, pv->column, kCtxWalkColumn);
    return out;
  }
  const int32_t p0 = pv->have ? pv->column : (r.has_last ? r.last_column : 0);
  int32_t p1 = r.has_last ? wrap_add(r.last_column, r.step) : p0;
  if (was >= 0 && was < out.firing) {  // the ring's step a firing, times the firings since
    const uint64_t gap = static_cast<uint64_t>(out.firing - was);
    const uint64_t prod = gap * static_cast<uint64_t>(static_cast<int64_t>(r.step));
    p1 = wrap_add(r.last_column, static_cast<int32_t>(static_cast<uint32_t>(prod)));
  }
  out.column = code_column(io, st, r, out.ring, pa, i, p0, p1, out.residual != 0, pv);
  return out;
}

// Point i (pa, its integers a) of a spherical frame.
template <class Io>
__attribute__((always_inline)) inline void code_spherical(Io& io, State& st, const Polar& pa,
                                                          size_t i, const int32_t* a, uint8_t flags,
                                                          Prev* pv, int32_t* p) {
  const Table& t = st.table();
  const bool walk = (flags & kRingWalk) != 0, hypot = (flags & kHypot) != 0;
  const RingColumn rc = walk ? ring_walk(io, st, pa, i, pv)
                             : ring_successor(io, st, pa, i, pv, (flags & kRingPairs) != 0);
  const uint32_t k = rc.ring;
  const int32_t col = rc.column;
  if (st.ring_out) st.ring_out[i] = static_cast<uint16_t>(k);
  State::Ring& r = st.ring[k];
  // Range: the ring's last, the previous point's (same column), the previous sweep's; with
  // units bit 7 the ring's range before its last.
  const int32_t w = r.has_last ? r.last_range : (pv->have ? pv->range : 0);
  const int nr = t.before ? 4 : 3;
  int32_t cand[4] = {w, w, w, r.has_before_range ? r.before_range : w};
  if (pv->have && pv->column == col) cand[1] = pv->range;
  // The previous sweep's candidate is its cell's smoothed range, rounded; coded against it, the
  // range takes the fraction rule.
  int64_t smooth = 0;
  const bool mapped = st.map_prev(k, col, &smooth);
  if (mapped) cand[2] = static_cast<int32_t>(floor_div16(smooth + 8));
  const int sr = detail::argmin(r.score_range, nr);
  const int g = std::min(bit_length(r.score_range[sr] >> 1), 15);
  const int32_t range =
      sr == 2 && mapped
          ? sym_fraction<true>(io, pa.range, cand[2],
                               static_cast<double>(smooth - int64_t{cand[2]} * 16) / 16.0,
                               kCtxRangeFrac + 3 * (g >> 1))
          : io.sym_plain(pa.range, cand[sr], kCtxRange + g);
  for (int j = 0; j < nr; ++j) score(&r.score_range[j], range, cand[j]);
  // x y on the column's azimuth at that range, z on the ring's cone.
  const bool units = !t.unit.empty();
  const double rho =
      units ? static_cast<double>(range) * t.unit[k] + t.offset[k] : static_cast<double>(range);
  const int lb = std::min(bit_length(units ? round_clamp(rho) : range), 23);
  code_xyz(io, t, st.angles(), hypot, k, col, rho, lb, a, p);
  if (r.has_last && (!walk || rc.opened)) r.step = wrap_sub(col, r.last_column);
  r.has_lead = pv->have;
  r.lead = wrap_sub(col, pv->column);
  r.lead_ring = pv->ring;
  r.before_column = r.last_column;
  r.has_before = r.has_last;
  r.last_column = col;
  r.before_range = r.last_range;
  r.has_before_range = r.has_last;
  r.last_range = range;
  if (!t.share.empty()) detail::base_update(st.base, t, k, col);
  r.has_last = true;
  st.map_set(k, col, range);
  *pv = Prev{true, k, rc.residual, col, range, pv->have ? pv->ring : k, rc.repeat, rc.firing};
}

}  // namespace detail

template <class Io>
void code_points(Io& io, State& st, uint8_t flags, size_t first, size_t n, int32_t* q_out,
                 uint8_t* valid_out) {
  const uint8_t vmode = flags & 3;
  const bool spherical = (flags & kSpherical) != 0;
  bool prev_valid = true;
  detail::Prev pv;
  if (flags & kRingWalk) std::fill(st.firing.begin(), st.firing.end(), State::Firing{});
  st.slots = State::Slots{};
  if ((flags & kRingPairs) && st.pair_ring.empty()) {
    st.pair_ring.assign(State::kPairCells, 0);
    st.pair_column.assign(State::kPairCells, 0);
  }
  for (size_t i = 0; i < n; ++i) {
    const bool v = point_valid(io, vmode, first + i, &prev_valid);
    valid_out[i] = v;
    int32_t* p = q_out + 3 * i;
    if (!v) {
      p[0] = p[1] = p[2] = 0;
      continue;
    }
    const int32_t* a = io.actual(first + i);
    if (spherical)
      detail::code_spherical(io, st, io.polar(first + i), first + i, a, flags, &pv, p);
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
