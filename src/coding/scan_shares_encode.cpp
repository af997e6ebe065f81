// The scan encoder's fit of the firing's base (docs/FORMAT.md "Scan geometry payload", units
// bit 3; docs/lab/2026-11-29-any-1mm-2.md): the firing's turn and each ring's share of it, for a
// driver that computed each laser's azimuth as the firing's plus the turn times the laser's
// firing time, rounded to the azimuths' quantum. Encoder side only.
#include <algorithm>
#include <cmath>
#include <map>

#include "coding/scan_table.h"

namespace capz {
namespace scan {

namespace {

constexpr double kTwoPi = 6.283185307179586;
constexpr size_t kMaxFitPoints = 4096;  // the window's first valid points
constexpr int kRefinements = 3;

// The valid points' rings and azimuths in columns of the quantum (point order, up to
// kMaxFitPoints), as place_points meets them.
void columns_in_order(const ScanGeometry& g, const RingFit& r, double step,
                      std::vector<uint32_t>* ring, std::vector<double>* u,
                      size_t most = kMaxFitPoints) {
  std::vector<size_t> next(r.rings(), 0);
  for (size_t i = 0; i < g.total() && ring->size() < most; ++i) {
    if (!g.valid[i]) continue;
    const uint32_t k = r.polar[i].ring;
    if (k >= r.rings() || next[k] >= r.phi[k].size()) continue;
    const int32_t* p = &g.q[3 * i];
    if (std::llabs(static_cast<long long>(p[0])) >= kMaxSphericalCoord ||
        std::llabs(static_cast<long long>(p[1])) >= kMaxSphericalCoord ||
        std::llabs(static_cast<long long>(p[2])) >= kMaxSphericalCoord)
      continue;
    ring->push_back(k);
    u->push_back(r.phi[k][next[k]++] / step);
  }
}

double wrap(double d, double cols) {
  return d - cols * std::floor(d / cols + 0.5);
}

// The firing's turn: the median step of a ring from one point to its next, in columns, among
// steps of more than half a column and under a quarter turn (0 when none).
double firing_turn(const std::vector<uint32_t>& ring, const std::vector<double>& u, size_t rings,
                   double cols) {
  std::vector<double> last(rings, NAN), d;
  for (size_t i = 0; i < ring.size(); ++i) {
    const double s = wrap(u[i] - last[ring[i]], cols);
    if (s > 0.5 && s < cols / 4) d.push_back(s);
    last[ring[i]] = u[i];
  }
  if (d.empty()) return 0;
  std::nth_element(d.begin(), d.begin() + static_cast<std::ptrdiff_t>(d.size() / 2), d.end());
  return d[d.size() / 2];
}

// First offsets (columns after the firing's first laser): each ring's most frequent
// predecessor within a firing and its mean lead on it, chained from the ring with the largest
// lead (the firing's first laser, whose predecessor fired a firing before).
std::vector<double> chained_offsets(const std::vector<uint32_t>& ring, const std::vector<double>& u,
                                    size_t rings, double turn, double cols) {
  std::map<uint64_t, std::pair<size_t, double>> pair;  // (a, b) -> count, sum of leads
  for (size_t i = 1; i < ring.size(); ++i) {
    const double d = wrap(u[i] - u[i - 1], cols);
    if (ring[i] == ring[i - 1] || d < 0 || d >= turn) continue;
    auto& e = pair[uint64_t{ring[i - 1]} * rings + ring[i]];
    ++e.first, e.second += d;
  }
  std::vector<size_t> count(rings, 0), pred(rings, rings);
  std::vector<double> lead(rings, 0);
  for (const auto& e : pair) {
    const size_t b = e.first % rings;
    if (e.second.first > count[b])
      count[b] = e.second.first, pred[b] = e.first / rings,
      lead[b] = e.second.second / double(e.second.first);
  }
  std::vector<double> off(rings, NAN);
  size_t first = rings;
  for (size_t b = 0; b < rings; ++b)
    if (pred[b] < rings && (first == rings || lead[b] > lead[first])) first = b;
  if (first == rings) return std::vector<double>(rings, 0);
  off[first] = 0;
  for (size_t b = 0; b < rings; ++b) {  // follow each ring's chain back to a known offset
    std::vector<size_t> path;
    size_t k = b;
    while (k < rings && std::isnan(off[k]) && path.size() <= rings) path.push_back(k), k = pred[k];
    double o = k < rings && !std::isnan(off[k]) ? off[k] : 0;
    for (auto it = path.rbegin(); it != path.rend(); ++it) o += lead[*it], off[*it] = o;
  }
  return off;
}

// One pass of the base interval (the lasers spread by `off`) over the points: per ring the
// mean of its columns less the middle of its firing's final interval, over firings of three
// points or more; rings never seen keep their offset. Also counts the exact predictions
// (*hits, with the all-on-the-base interval as the decoder's second).
std::vector<double> refine(const std::vector<uint32_t>& ring, const std::vector<double>& u,
                           double turn, const std::vector<double>& off, size_t* hits) {
  const size_t rings = off.size();
  std::vector<double> sum(rings, 0);
  std::vector<size_t> n(rings, 0), firing;  // the firing's points
  Table t;
  t.fire_turn = static_cast<float>(turn);
  for (double o : off) t.share.push_back(static_cast<float>(o / turn));
  State::Base b;
  auto flush = [&] {
    const double mid = (b.lo[0] + b.hi[0]) / 2;
    if (firing.size() >= 3)
      for (size_t i : firing) sum[ring[i]] += std::floor(u[i] + 0.5) - mid, ++n[ring[i]];
    firing.clear();
  };
  bool broken = false;  // the firing's points left the spread interval
  *hits = 0;
  for (size_t i = 0; i < ring.size(); ++i) {
    const int32_t c = round_clamp(u[i]);
    if (b.open && t.share[ring[i]] <= b.last_share) flush(), broken = false;
    const int32_t p = detail::base_predict(b, t, ring[i], c + 1);
    *hits += p == c;
    const double o = static_cast<double>(t.fire_turn) * t.share[ring[i]];
    if (b.open && b.live[0] && std::max(b.lo[0], c - o - 0.5) > std::min(b.hi[0], c - o + 0.5))
      broken = true;
    detail::base_update(b, t, ring[i], c);
    if (broken)
      firing.clear();
    else
      firing.push_back(i);
  }
  flush();
  std::vector<double> out = off;
  for (size_t k = 0; k < rings; ++k)
    if (n[k] > 0) out[k] = sum[k] / double(n[k]);
  const double least = *std::min_element(out.begin(), out.end());
  for (double& o : out) o -= least;
  return out;
}

// Exact predictions of the ring's lead on the previous point's ring (FORMAT p2's first form).
size_t lead_hits(const std::vector<uint32_t>& ring, const std::vector<double>& u, size_t rings) {
  std::vector<int32_t> lead(rings, 0);
  std::vector<uint32_t> lead_ring(rings, UINT32_MAX);
  size_t hits = 0;
  for (size_t i = 1; i < ring.size(); ++i) {
    const int32_t c = round_clamp(u[i]), pc = round_clamp(u[i - 1]);
    const uint32_t k = ring[i];
    hits += lead_ring[k] == ring[i - 1] && pc + lead[k] == c;
    lead[k] = c - pc, lead_ring[k] = ring[i - 1];
  }
  return hits;
}

// The firing's slots (FORMAT step 2, units bit 6), for a driver like the VLP-16's: kSlots slots
// of half a firing's turn (its firing of 55.296 us is 24 slots of 2.304 us).
constexpr uint32_t kSlots = 24;

// A firing's columns c[i] of slots m[i] against (b, d) (FORMAT's p each).
bool fits(const int32_t* c, const uint32_t* m, size_t len, int64_t b, int64_t d) {
  for (size_t i = 0; i < len; ++i)
    if (detail::slot_column(kSlots, b, d, m[i]) != c[i]) return false;
  return true;
}

// The turns D that can give a firing's columns c[i] of slots m[i] all (some B fitting every
// point), found cheaply: between each point and the first, 2N c_0 - N <= B N + D m_0 < 2N c_0 + N
// and the same for point i give (m_i - m_0) D within 2N (c_i - c_0) -+ (2N - 1). Every such D
// lies in [*lo, *hi] (empty when *lo > *hi); not every D there fits.
void turn_range(const int32_t* c, const uint32_t* m, size_t len, int64_t* lo, int64_t* hi) {
  const int64_t n2 = 2 * int64_t{kSlots};
  *lo = INT64_MIN, *hi = INT64_MAX;
  for (size_t i = 1; i < len && *lo <= *hi; ++i) {
    int64_t dm = int64_t{m[i]} - m[0], dc = n2 * (int64_t{c[i]} - c[0]);
    if (dm < 0) dm = -dm, dc = -dc;
    const int64_t a = dc - n2 + 1, z = dc + n2 - 1;  // dm D within [a, z]
    if (dm == 0) {
      if (a > 0 || z < 0) *lo = 1, *hi = 0;
      continue;
    }
    *lo = std::max(*lo, -detail::floor_div(-a, dm));
    *hi = std::min(*hi, detail::floor_div(z, dm));
  }
}

// The firing's (B, D) that gives all its columns, preferring B on its prediction bp, then D on
// dp, then the nearest: among D within 2 of dp, of the last nonzero dn and 0 (the first of them
// on ties), else (`wide`, or before a nonzero D) any |D| <= kWideTurn (the least on ties); false
// (and bp, dp) when none does. Only the D in turn_range are tried (no other fits), those of
// the wide search from dp outward until no farther one can cost less: the same answer.
constexpr int64_t kWideTurn = 64;
bool fire_fit(const int32_t* c, const uint32_t* m, size_t len, int64_t bp, int64_t dp, int64_t dn,
              bool wide, int32_t* b, int32_t* d) {
  *b = static_cast<int32_t>(bp), *d = static_cast<int32_t>(dp);
  if (fits(c, m, len, bp, dp)) return true;
  int64_t lo, hi;
  turn_range(c, m, len, &lo, &hi);
  if (lo > hi) return false;
  constexpr int64_t kTurnCost = int64_t{1} << 40;  // a B or D off its prediction, before both
  int64_t best = -1;
  // D = dd with its B of the least cost (of the two B's that put the first column right, the
  // nearer bp if it fits all points, else the other), kept when it costs less than the best, or
  // as much with a smaller D (`least`).
  const auto try_turn = [&](int64_t dd, bool least) {
    // The first column right: 2N c0 <= B N + D m0 + N < 2N c0 + 2N, so B is b1 - 1 or b1.
    const int64_t n = kSlots, b1 = detail::floor_div(2 * n * c[0] + n - 1 - dd * m[0], n);
    const int64_t bn = bp >= b1 ? b1 : b1 - 1, bf = bn == b1 ? b1 - 1 : b1;
    for (const int64_t bb : {bn, bf}) {
      if (bb < INT32_MIN || bb > INT32_MAX || !fits(c + 1, m + 1, len - 1, bb, dd)) continue;
      const int64_t db = bb > bp ? bb - bp : bp - bb, dt = dd > dp ? dd - dp : dp - dd;
      const int64_t cost = ((db != 0) + (dt != 0)) * kTurnCost + db + dt;
      if (best < 0 || cost < best || (least && cost == best && dd < *d)) {
        best = cost;
        *b = static_cast<int32_t>(bb), *d = static_cast<int32_t>(dd);
      }
      return;  // the other B, farther from bp, costs more
    }
  };
  const bool first = dp == 0 && dn == 0;
  if (!first) {
    const int64_t near[11] = {0,      dp - 2, dp - 1, dp,     dp + 1, dp + 2,
                              dn - 2, dn - 1, dn,     dn + 1, dn + 2};
    for (int j = 0; j < 11; ++j)
      if (near[j] >= lo && near[j] <= hi && std::find(near, near + j, near[j]) == near + j)
        try_turn(near[j], false);
  }
  if (best >= 0 || !(wide || first)) return best >= 0;
  // The wide search: D in [l, h] at distance t from dp costs at least kTurnCost + t (t > 0).
  const int64_t l = std::max(lo, -kWideTurn), h = std::min(hi, kWideTurn);
  const int64_t t0 = dp < l ? l - dp : dp > h ? dp - h : 0, t1 = std::max(dp - l, h - dp);
  for (int64_t t = t0; t <= t1; ++t) {
    if (best >= 0 && (t > 0 ? kTurnCost : 0) + t > best) break;
    if (dp - t >= l && dp - t <= h) try_turn(dp - t, true);
    if (t > 0 && dp + t >= l && dp + t <= h) try_turn(dp + t, true);
  }
  return best >= 0;
}

// Splits points (columns c, slots m, the first len) into firings as the decoder does from a
// frame's start, and gives each its (B, D) (fire_fit); calls out(first, len, b, d, fitted), which
// returns whether to go on.
template <class Out>
void split_firings(const int32_t* c, const uint32_t* m, size_t len, bool wide, Out out) {
  int64_t b = 0, d = 0, dn = 0;
  for (size_t i = 0; i < len;) {
    size_t j = i + 1;
    while (j < len && m[j] > m[j - 1]) ++j;
    int32_t fb, fd;
    const bool ok = fire_fit(&c[i], &m[i], j - i, b + d, d, dn, wide, &fb, &fd);
    if (!out(i, j - i, fb, fd, ok)) return;
    b = fb, d = fd;
    if (d != 0) dn = d;
    i = j;
  }
}

constexpr size_t kSlotFitPoints = 16, kShiftFitPoints = 1024, kMaxSlotFitPoints = 65536;

// The bits the slots would cost the first len points, roughly: a firing's turn and base (their
// residuals' bit lengths), and two bits a point of a firing they do not fit.
// (Counting stops above `bound`.)
size_t slot_cost(const std::vector<int32_t>& c, const std::vector<uint32_t>& ring,
                 const std::vector<uint8_t>& slot, size_t len, std::vector<uint32_t>* m,
                 size_t bound = SIZE_MAX) {
  for (size_t i = 0; i < len; ++i) (*m)[i] = slot[ring[i]];
  size_t bits = 0;
  int64_t b = 0, d = 0;
  split_firings(c.data(), m->data(), len, false,
                [&](size_t, size_t n, int32_t fb, int32_t fd, bool ok) {
                  bits += 2 + bit_cost(static_cast<int32_t>(fd - d)) +
                          bit_cost(static_cast<int32_t>(fb - b - d)) + (ok ? 0 : 2 * n);
                  b = fb, d = fd;
                  return bits <= bound;
                });
  return bits;
}

// All the slots moved together to the least slot_cost on the first kShiftFitPoints points: the
// slots count from the firing's own start, which the shares (from its first laser) do not know.
void shift_slots(const std::vector<int32_t>& c, const std::vector<uint32_t>& ring, size_t n,
                 std::vector<uint8_t>* slot, std::vector<uint32_t>* m) {
  const size_t few = std::min(n, kShiftFitPoints);
  const int lo = *std::min_element(slot->begin(), slot->end()),
            hi = *std::max_element(slot->begin(), slot->end());
  std::vector<uint8_t> moved = *slot;
  size_t least = slot_cost(c, ring, *slot, few, m);
  int shift = 0;
  for (int v = -lo; v < static_cast<int>(kSlots) - hi; ++v) {
    for (size_t k = 0; k < slot->size(); ++k) moved[k] = static_cast<uint8_t>((*slot)[k] + v);
    const size_t bits = slot_cost(c, ring, moved, few, m, least);
    if (bits < least) least = bits, shift = v;
  }
  for (uint8_t& k : *slot) k = static_cast<uint8_t>(k + shift);
}

// Whether the points' rings (in file order) look like firings: a firing holds several rings, so
// the ring changes from one point to the next at least at a quarter of the points. A cloud in
// rows (an organized sweep, Ouster's; a file written ring by ring) changes ring once a row: each
// of its "firings" is one point, which the slots fit at a base and turn of its own, slowly (the
// search below is quadratic in its rings) and at a cost (Ouster-like 128 x 2048 frames,
// --lossless: 965,480 -> 855,135 B; docs/lab/2026-11-30-slots-in-rows.md).
bool in_firing_order(const std::vector<uint32_t>& ring) {
  size_t changes = 0;
  for (size_t i = 1; i < ring.size(); ++i) changes += ring[i] != ring[i - 1];
  return 4 * changes >= ring.size();
}

// The rings' slots: from the shares, then each ring's slot in turn set to the one (of 0..N-1)
// of the least slot_cost on the points up to the ring's kSlotFitPoints-th. Kept
// when nine in ten of the sample's firings fit (else empty).
std::vector<uint8_t> fit_slots(const std::vector<uint32_t>& ring, const std::vector<double>& u,
                               const std::vector<double>& share) {
  std::vector<uint8_t> slot;
  if (!in_firing_order(ring)) return slot;
  for (double s : share)
    slot.push_back(
        static_cast<uint8_t>(std::min(std::max(std::floor(s * kSlots + 0.5), 0.0), kSlots - 1.0)));
  std::vector<int32_t> c(u.size());
  std::vector<uint32_t> m(u.size());
  for (size_t i = 0; i < u.size(); ++i) c[i] = round_clamp(u[i]);
  shift_slots(c, ring, u.size(), &slot, &m);
  for (size_t pass = 0; pass < slot.size(); ++pass) {
    const size_t k = pass % slot.size();
    size_t few = 0, seen = 0;  // up to ring k's kSlotFitPoints-th point
    while (few < u.size() && seen < kSlotFitPoints) seen += ring[few++] == k;
    if (seen == 0) continue;  // a ring without points keeps its slot
    uint8_t best = slot[k];
    size_t least = 0;  // the slots as they are, counted at the first candidate (if any)
    bool counted = false;
    for (uint32_t v = 0; v < kSlots; ++v) {  // a slot of another ring's left out (lasers apart)
      if (std::find(slot.begin(), slot.end(), v) != slot.end()) continue;
      if (!counted) least = slot_cost(c, ring, slot, few, &m), counted = true;
      slot[k] = static_cast<uint8_t>(v);
      const size_t bits = slot_cost(c, ring, slot, few, &m, least);
      if (bits < least) least = bits, best = slot[k];
    }
    slot[k] = best;
  }
  shift_slots(c, ring, u.size(), &slot, &m);
  size_t firings = 0, fitted = 0;
  for (size_t i = 0; i < u.size(); ++i) m[i] = slot[ring[i]];
  split_firings(c.data(), m.data(), u.size(), true, [&](size_t, size_t, int32_t, int32_t, bool ok) {
    ++firings, fitted += ok;
    return true;
  });
  if (fitted * 10 < firings * 9) slot.clear();
  return slot;
}

}  // namespace

void fire_points(const ScanGeometry& g, const Table& t, size_t n, Placement* placed) {
  placed->fire.assign(n, Fire{});
  std::vector<int32_t> c;
  std::vector<uint32_t> m;
  std::vector<size_t> at;
  size_t first = 0;
  for (size_t f = 0; f < g.counts.size() && first < n; ++f) {
    const size_t end = std::min<size_t>(n, first + g.counts[f]);
    c.clear(), m.clear(), at.clear();
    for (size_t i = first; i < end; ++i) {
      if (!g.valid[i]) continue;
      const Polar& p = placed->polar[i];
      if (p.ring >= t.slot.size()) continue;
      c.push_back(p.column), m.push_back(t.slot[p.ring]), at.push_back(i);
    }
    split_firings(c.data(), m.data(), c.size(), true,
                  [&](size_t i, size_t len, int32_t b, int32_t d, bool) {
                    for (size_t j = i; j < i + len; ++j) placed->fire[at[j]] = Fire{b, d};
                    return true;
                  });
    first += g.counts[f];
  }
}

void fit_shares(const ScanGeometry& g, RingFit* r) {
  r->fire_turn = 0;
  r->share.clear();
  r->slots = 0;
  r->slot.clear();
  if (r->quantum <= 0 || r->rings() == 0) return;
  const double step = std::copysign(r->quantum, r->step), cols = kTwoPi / r->quantum;
  std::vector<uint32_t> ring;
  std::vector<double> u;
  columns_in_order(g, *r, step, &ring, &u);
  const size_t rings = r->rings();
  const double turn = firing_turn(ring, u, rings, cols);
  if (!(turn > 0 && turn <= kMaxFireTurn)) return;
  std::vector<double> off = chained_offsets(ring, u, rings, turn, cols);
  size_t hits = 0;
  for (int pass = 0; pass < kRefinements; ++pass) off = refine(ring, u, turn, off, &hits);
  refine(ring, u, turn, off, &hits);
  // Kept when the firing's base predicts more columns exactly than the ring's lead does.
  if (hits <= lead_hits(ring, u, rings)) return;
  r->fire_turn = static_cast<float>(turn);
  for (double o : off) r->share.push_back(static_cast<float>(std::min(o / turn, kMaxShare)));
  // The firing's slots in the base's place when they fit (fit_slots).
  std::vector<double> share(r->share.begin(), r->share.end());
  ring.clear(), u.clear();
  columns_in_order(g, *r, step, &ring, &u, kMaxSlotFitPoints);
  r->slot = fit_slots(ring, u, share);
  if (r->slot.empty()) return;
  r->slots = kSlots;
  r->fire_turn = 0;
  r->share.clear();
}

}  // namespace scan
}  // namespace capz
