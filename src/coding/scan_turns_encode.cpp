// The scan encoder's search for a turning or moving sensor's turns and moves (docs/FORMAT.md
// "Turns", "Moves"; informative there): what lines a sweep up with the previous sweep's map.
#include <algorithm>
#include <cmath>
#include <cstdint>
#include <cstdlib>
#include <vector>

#include "coding/scan_trial_gates.h"

namespace capz {

namespace {

constexpr size_t kTurnSample = 1024;  // points of a frame scored for its turn
constexpr size_t kMoveSample = 256;   // for its move
constexpr double kTurnReach = 6.0 * 3.14159265358979323846 / 180;  // radians either way (6 deg)
constexpr int64_t kCoarseSteps = 32;                               // coarse shifts each way
constexpr uint32_t kTurnLeast = 32;  // points a kept shift or move scores more than none, at least
constexpr size_t kBeatShare = 32;    // and more than this share of the sample
constexpr double kMoveSpacing = 0.25;  // metres between the moves first scored
constexpr double kMoveReach = 3.0;     // metres either way, the whole search's

struct Sampled {
  uint32_t ring;
  int32_t column, range, reach;
};

// The points of s whose range is within its reach of the previous sweep's cell at column + shift.
uint32_t score(const std::vector<Sampled>& s, const scan::State& st, int64_t shift) {
  uint32_t hits = 0;
  for (const Sampled& p : s) {
    int64_t smooth = 0;
    if (!st.map_prev_at(p.ring, int64_t{p.column} + shift, &smooth)) continue;
    const int64_t d = int64_t{p.range} - scan::detail::floor_div16(smooth + 8);
    hits += d <= p.reach && d >= -p.reach;
  }
  return hits;
}

// Whether shift a (scoring sa) goes before shift b (scoring sb): the higher score, then the
// least |shift|, then the smaller shift.
bool better(int64_t a, uint32_t sa, int64_t b, uint32_t sb) {
  if (sa != sb) return sa > sb;
  if (std::llabs(a) != std::llabs(b)) return std::llabs(a) < std::llabs(b);
  return a < b;
}

// The best shift within `most` columns by score(shift): every ceil(most / kCoarseSteps)
// columns, then each column within that spacing of the best; *top its score, `still` shift 0's.
template <class Score>
int64_t best_shift(int64_t most, uint32_t still, const Score& score_of, uint32_t* top) {
  const int64_t d = (most + kCoarseSteps - 1) / kCoarseSteps;
  int64_t best = 0;
  *top = still;
  for (int64_t j = -(most / d); j <= most / d; ++j) {
    if (j == 0) continue;
    const uint32_t v = score_of(j * d);
    if (better(j * d, v, best, *top)) best = j * d, *top = v;
  }
  const int64_t coarse = best;
  for (int64_t shift = std::max(-most, coarse - d + 1); shift <= std::min(most, coarse + d - 1);
       ++shift) {
    if (shift % d == 0) continue;  // scored above
    const uint32_t v = score_of(shift);
    if (better(shift, v, best, *top)) best = shift, *top = v;
  }
  return best;
}

// Whether a shift or move that scores `top` of a sample of n, against `still` for none, is kept.
// (It scores most of the sample: on a still sensor's table whose map predicts poorly,
// scan_small's at 1 cm, some shift beats none by chance, and costs more than it saves.)
bool kept(uint32_t top, uint32_t still, size_t n) {
  return top > still && top - still > std::max<size_t>(kTurnLeast, n / kBeatShare) &&
         2 * size_t{top} > n;
}

// The columns a turn is looked for within (0: none).
int64_t turn_reach(const scan::Table& t) {
  const double reach = kTurnReach / std::fabs(static_cast<double>(t.step));
  return std::min<int64_t>(std::llround(std::min(reach, 1e9)), t.columns / 2);
}

// A sample point of a move's search: its grid integers.
struct Point {
  double x, y, z;
};

// Per point of s, whether, turned by `shift` columns and moved by m (into the previous sweep's
// place and axes), it falls in a previous cell whose range is within reach of its own there.
void moved_hits(const std::vector<Point>& s, const scan::State& st, int64_t shift,
                const double m[3], std::vector<uint8_t>* hit) {
  const scan::Table& t = st.table();
  double sn, cs;
  scan::det_sincos(static_cast<double>(shift) * static_cast<double>(t.step), &sn, &cs);
  hit->assign(s.size(), 0);
  for (size_t i = 0; i < s.size(); ++i) {
    const Point& p = s[i];
    const double x = p.x * cs - p.y * sn + m[0], y = p.x * sn + p.y * cs + m[1], z = p.z + m[2];
    uint32_t ring = 0;
    size_t cell = 0;
    int64_t a = 0, smooth = 0;
    if (!scan::cast_point(t, x, y, z, &ring, &cell, &a) || !st.map_prev_cell(cell, &smooth))
      continue;
    const int64_t r = scan::detail::floor_div16(a + 8);
    const int64_t reach = std::max<int64_t>(4, std::llabs(r / 64));
    const int64_t d = r - scan::detail::floor_div16(smooth + 8);
    (*hit)[i] = d <= reach && d >= -reach;
  }
}

}  // namespace

TurnFound find_turn(const ScanGeometry& g, const std::vector<scan::Polar>& polar,
                    const scan::State& st, size_t first, size_t n) {
  const scan::Table& t = st.table();
  if (t.rings() == 0 || n == 0) return {};
  std::vector<Sampled> s;
  s.reserve(kTurnSample);
  const size_t stride = std::max<size_t>(1, n / kTurnSample);
  for (size_t i = first; i < first + n && s.size() < kTurnSample; i += stride) {
    if (!g.valid[i]) continue;
    const scan::Polar& p = polar[i];
    const int32_t reach = std::max<int32_t>(4, std::abs(p.range / 64));
    s.push_back({p.ring, p.column, p.range, reach});
  }
  const int64_t most = turn_reach(t);
  const uint32_t still = score(s, st, 0);
  if (s.empty() || most < 1) return {0, still, s.size()};
  uint32_t top = still;
  const int64_t best = best_shift(
      most, still, [&](int64_t shift) { return score(s, st, shift); }, &top);
  if (best == 0 || !kept(top, still, s.size())) return {0, still, s.size()};
  return {static_cast<int32_t>(best), top, s.size()};
}

scan::Move find_move(const ScanGeometry& g, const scan::State& st, size_t first, size_t n,
                     int32_t turn, const scan::Move& guess, double per_metre) {
  const scan::Table& t = st.table();
  std::vector<Point> s;
  const size_t stride = std::max<size_t>(1, n / kMoveSample);
  for (size_t i = first; i < first + n && s.size() < kMoveSample; i += stride)
    if (g.valid[i])
      s.push_back({static_cast<double>(g.q[3 * i]), static_cast<double>(g.q[3 * i + 1]),
                   static_cast<double>(g.q[3 * i + 2])});
  const double spacing = std::floor(kMoveSpacing * per_metre);
  if (t.rings() == 0 || s.empty() || !(spacing >= 1) || !(spacing < 1e6)) return {};
  // A point counts when the previous sweep's map predicts it either way: without the move (the
  // range's third candidate, right where the surface is the ground) or with it (the fifth).
  std::vector<uint8_t> still_hit, hit;
  const double none[3] = {0, 0, 0};
  moved_hits(s, st, turn, none, &still_hit);
  const auto score_of = [&](const double m[3]) {
    moved_hits(s, st, turn, m, &hit);
    uint32_t v = 0;
    for (size_t i = 0; i < s.size(); ++i) v += still_hit[i] | hit[i];
    return v;
  };
  uint32_t still = 0;
  for (uint8_t h : still_hit) still += h;
  double best[3] = {static_cast<double>(guess.d[0]), static_cast<double>(guess.d[1]), 0};
  uint32_t top = guess.zero() ? still : score_of(best);
  // Scores (best + i d, best + j d) for i, j in -r..r; keeps the best (the first on ties).
  const auto around = [&](double d, int r) {
    const double at[2] = {best[0], best[1]};
    for (int i = -r; i <= r; ++i)
      for (int j = -r; j <= r; ++j) {
        const double m[3] = {at[0] + i * d, at[1] + j * d, 0};
        if ((i == 0 && j == 0) || std::fabs(m[0]) > scan::kMaxMove ||
            std::fabs(m[1]) > scan::kMaxMove)
          continue;
        const uint32_t v = score_of(m);
        if (v > top) best[0] = m[0], best[1] = m[1], top = v;
      }
  };
  around(spacing, 1);  // the frame before's move and its neighbours
  if (top - still <= std::max<size_t>(kTurnLeast, s.size() / kBeatShare)) {  // every move in reach
    best[0] = best[1] = 0;
    top = still;
    around(spacing, static_cast<int>(kMoveReach / kMoveSpacing));
  }
  for (double d = std::floor(spacing / 2); d >= 1; d = std::floor(d / 2)) around(d, 1);
  if (top <= still || top - still <= std::max<size_t>(kTurnLeast, s.size() / kBeatShare)) return {};
  scan::Move out;
  for (int a = 0; a < 2; ++a) out.d[a] = static_cast<int32_t>(best[a]);
  return out;
}

void line_up(const ScanGeometry& g, const std::vector<scan::Polar>& polar, bool spherical, size_t f,
             size_t first, size_t n, double per_metre, scan::State* st, std::vector<int32_t>* turns,
             std::vector<scan::Move>* moves) {
  int32_t turn = 0;
  scan::Move move;
  if (spherical && f > 0) {
    const TurnFound found = find_turn(g, polar, *st, first, n);
    turn = found.turn;
    if (per_metre > 0 && 4 * size_t{found.top} <= 3 * found.sampled) {
      move = find_move(g, *st, first, n, turn, (*moves)[f - 1], per_metre);
    }
  }
  (*turns)[f] = turn;
  (*moves)[f] = move;
  st->set_turn(turn);
  if (!move.zero()) st->recast(move);
}

}  // namespace capz
