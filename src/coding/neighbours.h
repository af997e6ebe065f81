// Nearest earlier points of a window's points, from the window's POSW integers: the search of
// the encoder's POSW reference candidates (docs/FORMAT.md 8, position_modes.cpp) and the
// normative neighbour of ATTR predictors 10 and 11 (FORMAT.md 13.5), one loop for both.
#pragma once

#include <cstddef>
#include <cstdint>
#include <vector>

namespace capz {

// Marks "no point" in the tables below.
constexpr uint32_t kNoPoint = UINT32_MAX;

// Above this many points, a point's candidates are only the kNearWindow points before it.
constexpr size_t kNearBruteForce = 4096;
constexpr size_t kNearWindow = 512;

// The squared Euclidean distance of two integer positions, exactly: each difference is below
// 2^32 in magnitude, so each square fits 64 bits; the three are added with their carries
// counted (the sum is below 3 * 2^64).
struct ExactDistance {
  uint64_t hi = 0, lo = 0;
  bool operator<(const ExactDistance& o) const { return hi < o.hi || (hi == o.hi && lo < o.lo); }
};
inline ExactDistance exact_distance(const int32_t* a, const int32_t* b) {
  ExactDistance d;
  for (int k = 0; k < 3; ++k) {
    const int64_t x = static_cast<int64_t>(a[k]) - static_cast<int64_t>(b[k]);
    const uint64_t m = static_cast<uint64_t>(x < 0 ? -x : x);
    const uint64_t s = m * m;
    d.lo += s;
    d.hi += d.lo < s ? 1 : 0;
  }
  return d;
}

// Calls visit(p, qf, vf, lo) for every point p > 0 of a window valid in some frame: qf and vf
// the positions and mask of p's first valid frame, lo the lowest index among its candidates
// (every earlier point up to kNearBruteForce points, else the kNearWindow before it).
template <typename Visit>
void each_searched_point(const int32_t* q, const uint8_t* valid, size_t frames, size_t points,
                         Visit&& visit) {
  for (size_t p = 1; p < points; ++p) {
    size_t f = 0;
    while (f < frames && !valid[f * points + p]) ++f;
    if (f == frames) continue;
    visit(p, q + f * points * 3, valid + f * points,
          points <= kNearBruteForce || p < kNearWindow ? 0 : p - kNearWindow);
  }
}

// For every point p of a window (q: frames x points x 3 integers, valid: frames x points), up
// to k points r < p nearest to p at p's first valid frame of the window, among the points valid
// there (every r when points <= kNearBruteForce, else r >= p - kNearWindow), nearest first,
// ties to the larger r: out[p * k + j], kNoPoint in unused slots. dist(a, b) gives the
// distance of two positions (3 integers each) as any type with operator<.
template <typename Dist>
std::vector<uint32_t> nearest_earlier(const int32_t* q, const uint8_t* valid, size_t frames,
                                      size_t points, size_t k, Dist&& dist) {
  using D = decltype(dist(q, q));
  std::vector<uint32_t> out(points * k, kNoPoint);
  std::vector<D> d(k);
  each_searched_point(q, valid, frames, points,
                      [&](size_t p, const int32_t* qf, const uint8_t* vf, size_t lo) {
                        uint32_t* c = &out[p * k];
                        size_t n = 0;
                        // From p - 1 down: a later r is kept on equal distance (only a strictly
                        // nearer one moves ahead of it).
                        for (size_t r = p; r-- > lo;) {
                          if (!vf[r]) continue;
                          const D dd = dist(qf + p * 3, qf + r * 3);
                          if (n == k && !(dd < d[n - 1])) continue;
                          size_t j = n < k ? n++ : n - 1;
                          while (j > 0 && dd < d[j - 1]) {
                            d[j] = d[j - 1];
                            c[j] = c[j - 1];
                            --j;
                          }
                          d[j] = dd;
                          c[j] = static_cast<uint32_t>(r);
                        }
                      });
  return out;
}

// nearest_earlier with k = 1 and exact_distance, for q whose coordinates each span less than
// 2^31 (the caller checks): each squared difference is then below 2^62 and their sum fits 64
// bits, so the same points come out of plain sums.
inline std::vector<uint32_t> nearest_earlier_narrow(const int32_t* q, const uint8_t* valid,
                                                    size_t frames, size_t points) {
  std::vector<uint32_t> out(points, kNoPoint);
  each_searched_point(
      q, valid, frames, points, [&](size_t p, const int32_t* qf, const uint8_t* vf, size_t lo) {
        const int64_t x = qf[p * 3], y = qf[p * 3 + 1], z = qf[p * 3 + 2];
        uint64_t best = UINT64_MAX;
        uint32_t c = kNoPoint;
        for (size_t r = p; r-- > lo;) {  // from p - 1 down: on equal distance the later r stays
          // A candidate whose x difference alone reaches the best distance cannot be nearer:
          // most are passed over here, without their y and z.
          const int64_t dx = qf[r * 3] - x;
          const uint64_t dx2 = static_cast<uint64_t>(dx * dx);
          if (dx2 >= best) continue;
          const int64_t dy = qf[r * 3 + 1] - y, dz = qf[r * 3 + 2] - z;
          const uint64_t d = dx2 + static_cast<uint64_t>(dy * dy) + static_cast<uint64_t>(dz * dz);
          if (vf[r] && d < best) {
            best = d;
            c = static_cast<uint32_t>(r);
          }
        }
        out[p] = c;
      });
  return out;
}

}  // namespace capz
