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
                      std::vector<uint32_t>* ring, std::vector<double>* u) {
  std::vector<size_t> next(r.rings(), 0);
  for (size_t i = 0; i < g.total() && ring->size() < kMaxFitPoints; ++i) {
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

}  // namespace

void fit_shares(const ScanGeometry& g, RingFit* r) {
  r->fire_turn = 0;
  r->share.clear();
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
}

}  // namespace scan
}  // namespace capz
