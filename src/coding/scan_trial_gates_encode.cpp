// The scan encoder's trial gates (scan_trial_gates.h).
#include <algorithm>
#include <cstdint>

#include "coding/predict.h"
#include "coding/scan_trial_gates.h"

namespace capz {

size_t ring_passes(const std::vector<uint8_t>& valid, const std::vector<scan::Polar>& polar,
                   size_t rings, size_t first, size_t n, size_t* up, size_t* down) {
  size_t points = 0, u = 0, d = 0;
  uint32_t prev = 0;
  for (size_t i = first; i < first + n; ++i) {
    if (!valid[i]) continue;
    const uint32_t k = polar[i].ring;
    if (points++ > 0 && k != prev) {
      u += k > prev ? k - prev : k + rings - prev;
      d += k < prev ? prev - k : prev + rings - k;
    }
    prev = k;
  }
  *up = u;
  *down = d;
  return points;
}

bool walk_worth_trying(const ScanGeometry& g, const std::vector<scan::Polar>& polar, size_t rings,
                       size_t first, size_t n, size_t* passed) {
  size_t down = 0;
  const size_t valid = ring_passes(g.valid, polar, rings, first, n, passed, &down);
  return *passed < kWalkFlags * valid;
}

bool pairs_worth_trying(const ScanGeometry& g, const std::vector<scan::Polar>& polar,
                        const scan::State& st, size_t first, size_t n) {
  std::vector<int32_t> step(scan::State::kPairCells);
  std::vector<uint8_t> seen(scan::State::kPairCells);
  size_t valid = 0, pair = 0, same = 0;
  const scan::Polar* prev = nullptr;
  for (size_t i = first; i < first + n; ++i) {
    if (!g.valid[i]) continue;
    ++valid;
    const scan::Polar& p = polar[i];
    if (prev) {
      const uint32_t h = st.pair_cell(prev->ring, p.ring);
      const int32_t d = wrap_sub(p.column, prev->column);
      pair += seen[h] && step[h] == d;
      same += d == 0;
      seen[h] = 1;
      step[h] = d;
    }
    prev = &p;
  }
  return pair > same + valid / 8;
}

uint64_t cartesian_raw_bits(const scan::State& st, const ScanGeometry& g, size_t first, size_t n) {
  int32_t last[3] = {st.last[0], st.last[1], st.last[2]};
  uint64_t bits = 0;
  for (size_t i = first; i < first + n; ++i) {
    if (!g.valid[i]) continue;
    const int32_t* a = &g.q[3 * i];
    for (int ax = 0; ax < 3; ++ax) {
      const uint32_t u = zigzag(wrap_sub(a[ax], last[ax]));
      bits += u < 4 ? 0u : static_cast<uint32_t>(30 - __builtin_clz(u));  // token_of's extra
      last[ax] = a[ax];
    }
  }
  return bits;
}

bool has_pair_frames(const std::vector<uint8_t>& p) {
  const scan::Header h = scan::read_header(p.data(), p.size(), "scan geometry", SIZE_MAX);
  return std::any_of(h.flags.begin(), h.flags.end(),
                     [](uint8_t f) { return !scan::octree_frame(f) && (f & scan::kRingPairs); });
}

ScanGeometry trial_sample(const ScanGeometry& g, size_t frames, std::vector<size_t>* from) {
  constexpr size_t kSampleShare = 4, kSampleMin = 16384;
  ScanGeometry s;
  from->clear();
  size_t first = 0;
  for (size_t f = 0; f < std::min(frames, g.counts.size()); ++f) {
    const size_t n = g.counts[f], m = std::min(n, std::max(kSampleMin, n / kSampleShare));
    s.counts.push_back(static_cast<uint32_t>(m));
    for (size_t i = first; i < first + m; ++i) from->push_back(i);
    first += n;
  }
  s.valid.resize(from->size());
  s.q.resize(3 * from->size());
  for (size_t j = 0; j < from->size(); ++j) {
    const size_t i = (*from)[j];
    s.valid[j] = g.valid[i];
    std::copy(&g.q[3 * i], &g.q[3 * i] + 3, &s.q[3 * j]);
  }
  return s;
}

}  // namespace capz
