// match_reordered (point_match.h).
#include "metrics/point_match.h"

#include <algorithm>
#include <cmath>
#include <cstring>
#include <tuple>

namespace capz {

namespace {

using Key = std::tuple<int64_t, int64_t, int64_t>;

int64_t cell_of(double v, double cell) {
  const double c = std::floor(v / cell);
  return static_cast<int64_t>(std::max(-9.0e18, std::min(9.0e18, c)));
}

// The points of one frame of the decoded take, sorted by cell, with their use.
struct Cells {
  std::vector<std::pair<Key, size_t>> sorted;
  std::vector<bool> used;
};

// Whether original point i and decoded point j agree: coordinates within `bound`, the exact
// fields byte for byte.
bool agree(const Take& o, size_t i, const Take& d, size_t j, double bound,
           const std::vector<bool>& exact) {
  for (size_t a = 0; a < 3; ++a)
    if (!(std::fabs(o.xyz[3 * i + a] - d.xyz[3 * j + a]) <= bound)) return false;
  for (size_t f = 0; f < o.attributes.size() && f < d.attributes.size(); ++f) {
    if (f >= exact.size() || !exact[f]) continue;
    const size_t bpp = o.attributes[f].bytes_per_point();
    if (std::memcmp(&o.attributes[f].data[i * bpp], &d.attributes[f].data[j * bpp], bpp) != 0)
      return false;
  }
  return true;
}

// The decoded partner of original point i in frame [p0, p1), or p1 when none.
size_t partner(const Take& o, size_t i, const Take& d, Cells* c, double bound, double cell,
               const std::vector<bool>& exact, size_t p1) {
  int64_t lo[3], hi[3];
  for (size_t a = 0; a < 3; ++a) {
    lo[a] = cell_of(o.xyz[3 * i + a] - bound, cell);
    hi[a] = cell_of(o.xyz[3 * i + a] + bound, cell);
  }
  size_t best = p1;
  for (int64_t x = lo[0]; x <= hi[0]; ++x)
    for (int64_t y = lo[1]; y <= hi[1]; ++y)
      for (int64_t z = lo[2]; z <= hi[2]; ++z) {
        const Key k{x, y, z};
        auto it =
            std::lower_bound(c->sorted.begin(), c->sorted.end(), std::make_pair(k, size_t{0}));
        for (; it != c->sorted.end() && it->first == k; ++it)
          if (it->second < best && !c->used[it->second] && agree(o, i, d, it->second, bound, exact))
            best = it->second;
      }
  return best;
}

// Copies original point i (with its fields) to place j of *out.
void move_point(const Take& o, size_t i, size_t j, Take* out) {
  std::copy_n(o.xyz.begin() + static_cast<std::ptrdiff_t>(3 * i), 3,
              out->xyz.begin() + static_cast<std::ptrdiff_t>(3 * j));
  out->valid[j] = o.valid[i];
  for (size_t f = 0; f < o.attributes.size(); ++f) {
    const size_t bpp = o.attributes[f].bytes_per_point();
    if (o.attributes[f].data.size() != o.total_points() * bpp) continue;
    std::copy_n(o.attributes[f].data.begin() + static_cast<std::ptrdiff_t>(i * bpp), bpp,
                out->attributes[f].data.begin() + static_cast<std::ptrdiff_t>(j * bpp));
  }
}

}  // namespace

bool match_reordered(const Take& original, const Take& decoded, double bound,
                     const std::vector<bool>& exact_fields, Take* out, std::string* why) {
  *out = original;
  const double cell = bound > 0 ? 2 * bound : 1.0;
  for (size_t f = 0; f < original.frames; ++f) {
    const size_t p0 = original.frame_begin(f), p1 = p0 + original.frame_points(f);
    Cells c;
    c.used.assign(p1, false);
    std::vector<size_t> gaps;
    for (size_t j = p0; j < p1; ++j) {
      if (!decoded.valid[j]) {
        gaps.push_back(j);
        continue;
      }
      c.sorted.push_back(
          {Key{cell_of(decoded.xyz[3 * j], cell), cell_of(decoded.xyz[3 * j + 1], cell),
               cell_of(decoded.xyz[3 * j + 2], cell)},
           j});
    }
    std::sort(c.sorted.begin(), c.sorted.end());
    size_t next_gap = 0;
    for (size_t i = p0; i < p1; ++i) {
      size_t j = p1;
      if (!original.valid[i])
        j = next_gap < gaps.size() ? gaps[next_gap++] : p1;
      else
        j = partner(original, i, decoded, &c, bound, cell, exact_fields, p1);
      if (j == p1) {
        *why = "frame " + std::to_string(f) + ", point " + std::to_string(i - p0) +
               (original.valid[i] ? " has no decoded point within the bound with its fields"
                                  : " is a gap and the decoded frame has fewer") +
               " (points reordered: each frame compared as a set)";
        return false;
      }
      c.used[j] = true;
      move_point(original, i, j, out);
    }
  }
  return true;
}

}  // namespace capz
