// The scan encoder's search for a turning sensor's turns (docs/FORMAT.md "Turns"; informative
// there): the column shift that lines a sweep up with the previous sweep's map.
#include <algorithm>
#include <cmath>
#include <cstdint>
#include <cstdlib>
#include <vector>

#include "coding/scan_trial_gates.h"

namespace capz {

namespace {

constexpr size_t kTurnSample = 1024;                               // points of a frame scored
constexpr double kTurnReach = 6.0 * 3.14159265358979323846 / 180;  // radians either way (6 degrees)
constexpr int64_t kCoarseSteps = 32;                               // coarse shifts each way
constexpr int64_t kFineAll = 128;    // coarse steps up to this many columns searched whole
constexpr uint32_t kTurnLeast = 32;  // points a kept shift scores more than shift 0, at least
constexpr size_t kBeatShare = 32;    // and more than this share of the sample

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

}  // namespace

int32_t find_turn(const ScanGeometry& g, const std::vector<scan::Polar>& polar,
                  const scan::State& st, size_t first, size_t n, size_t* scored) {
  const scan::Table& t = st.table();
  if (t.rings() == 0 || n == 0) return 0;
  std::vector<Sampled> s;
  s.reserve(kTurnSample);
  const size_t stride = std::max<size_t>(1, n / kTurnSample);
  for (size_t i = first; i < first + n && s.size() < kTurnSample; i += stride) {
    if (!g.valid[i]) continue;
    const scan::Polar& p = polar[i];
    const int32_t reach = std::max<int32_t>(4, std::abs(p.range / 64));
    s.push_back({p.ring, p.column, p.range, reach});
  }
  const double reach = kTurnReach / std::fabs(static_cast<double>(t.step));
  const int64_t most = std::min<int64_t>(std::llround(std::min(reach, 1e9)), t.columns / 2);
  if (s.empty() || most < 1) return 0;
  int64_t d = (most + kCoarseSteps - 1) / kCoarseSteps;
  const uint32_t still = score(s, st, 0);
  auto scored_at = [&](int64_t shift) {  // a shift besides 0, counted
    if (scored) ++*scored;
    return score(s, st, shift);
  };
  int64_t best = 0;
  uint32_t top = still;
  for (int64_t j = -(most / d); j <= most / d; ++j) {
    if (j == 0) continue;
    const uint32_t v = scored_at(j * d);
    if (better(j * d, v, best, top)) best = j * d, top = v;
  }
  // Then around the best so far, at finer steps down to one column: every shift within d - 1 of
  // it when d is at most kFineAll (every sensor's table: 6 degrees is a few thousand of its
  // columns at most), else at a 32nd of d, level after level, so that a table fitted to odd
  // points (2^22 columns of a tiny step) costs a few hundred scores, not 2^17.
  while (d > 1) {
    const int64_t next = d <= kFineAll ? 1 : (d + kCoarseSteps - 1) / kCoarseSteps;
    const int64_t centre = best;
    for (int64_t k = -((d - 1) / next); k <= (d - 1) / next; ++k) {
      const int64_t shift = centre + k * next;
      if (k == 0 || shift < -most || shift > most) continue;  // (k 0: scored above)
      const uint32_t v = scored_at(shift);
      if (better(shift, v, best, top)) best = shift, top = v;
    }
    d = next;
  }
  // (A shift kept scores most of the sample: on a still sensor's table whose map predicts
  // poorly, scan_small's at 1 cm, some shift beats none by chance, and costs more than it saves.)
  if (best == 0 || top - still <= std::max<size_t>(kTurnLeast, s.size() / kBeatShare) ||
      2 * size_t{top} <= s.size())
    return 0;
  return static_cast<int32_t>(best);
}

}  // namespace capz
