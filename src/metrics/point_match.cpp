// match_reordered (point_match.h).
#include "metrics/point_match.h"

#include <algorithm>
#include <cmath>
#include <cstring>
#include <tuple>

namespace capz {

namespace {

using Key = std::tuple<int64_t, int64_t, int64_t>;
constexpr size_t kNone = static_cast<size_t>(-1);

int64_t cell_of(double v, double cell) {
  const double c = std::floor(v / cell);
  return static_cast<int64_t>(std::max(-9.0e18, std::min(9.0e18, c)));
}

// One frame's pairing: the decoded valid points sorted by cell, and which original point holds
// each decoded point.
struct Frame {
  const Take& o;
  const Take& d;
  double bound, cell;
  const std::vector<bool>& exact;
  std::vector<std::pair<Key, size_t>> sorted;
  std::vector<size_t> owner;  // per decoded point of the take: its original partner or kNone
  std::vector<size_t> seen;   // per decoded point: the search that last visited it
  size_t search = 0;
};

// Whether original point i and decoded point j agree: coordinates within the bound, the exact
// fields byte for byte.
bool agree(const Frame& fr, size_t i, size_t j) {
  for (size_t a = 0; a < 3; ++a)
    if (!(std::fabs(fr.o.xyz[3 * i + a] - fr.d.xyz[3 * j + a]) <= fr.bound)) return false;
  for (size_t f = 0; f < fr.o.attributes.size() && f < fr.d.attributes.size(); ++f) {
    if (f >= fr.exact.size() || !fr.exact[f]) continue;
    const size_t bpp = fr.o.attributes[f].bytes_per_point();
    if (std::memcmp(&fr.o.attributes[f].data[i * bpp], &fr.d.attributes[f].data[j * bpp], bpp) != 0)
      return false;
  }
  return true;
}

// The decoded points original point i agrees with, the nearest first (max-norm).
std::vector<size_t> candidates(const Frame& fr, size_t i) {
  int64_t lo[3], hi[3];
  for (size_t a = 0; a < 3; ++a) {
    lo[a] = cell_of(fr.o.xyz[3 * i + a] - fr.bound, fr.cell);
    hi[a] = cell_of(fr.o.xyz[3 * i + a] + fr.bound, fr.cell);
  }
  std::vector<std::pair<double, size_t>> found;
  for (int64_t x = lo[0]; x <= hi[0]; ++x)
    for (int64_t y = lo[1]; y <= hi[1]; ++y)
      for (int64_t z = lo[2]; z <= hi[2]; ++z) {
        const Key k{x, y, z};
        auto it =
            std::lower_bound(fr.sorted.begin(), fr.sorted.end(), std::make_pair(k, size_t{0}));
        for (; it != fr.sorted.end() && it->first == k; ++it) {
          const size_t j = it->second;
          if (!agree(fr, i, j)) continue;
          double dist = 0;
          for (size_t a = 0; a < 3; ++a)
            dist = std::max(dist, std::fabs(fr.o.xyz[3 * i + a] - fr.d.xyz[3 * j + a]));
          found.emplace_back(dist, j);
        }
      }
  std::sort(found.begin(), found.end());
  std::vector<size_t> out;
  for (const auto& f : found) out.push_back(f.second);
  return out;
}

// Gives original point i a partner: the decoded point at its own place when free and agreeing
// (an archive that kept the order: a decoder that moves points within the bound, as raster
// frames on their rays do, puts others' partners nearer than their own), else a free candidate,
// or one whose holder can move to another (an augmenting path, Kuhn's algorithm),
// depth-bounded. True when it found one.
bool assign(Frame* fr, size_t i, int depth) {
  if (fr->d.valid[i] && fr->owner[i] == kNone && agree(*fr, i, i)) return fr->owner[i] = i, true;
  const std::vector<size_t> cand = candidates(*fr, i);
  for (size_t j : cand)
    if (fr->owner[j] == kNone) return fr->owner[j] = i, true;
  if (depth == 0) return false;
  for (size_t j : cand) {
    if (fr->seen[j] == fr->search) continue;
    fr->seen[j] = fr->search;
    if (assign(fr, fr->owner[j], depth - 1)) return fr->owner[j] = i, true;
  }
  return false;
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
  Frame fr{original, decoded, bound, cell, exact_fields, {}, {}, {}, 0};
  fr.owner.assign(original.total_points(), kNone);
  fr.seen.assign(original.total_points(), 0);
  for (size_t f = 0; f < original.frames; ++f) {
    const size_t p0 = original.frame_begin(f), p1 = p0 + original.frame_points(f);
    fr.sorted.clear();
    std::vector<size_t> gaps;
    for (size_t j = p0; j < p1; ++j) {
      if (!decoded.valid[j]) {
        gaps.push_back(j);
        continue;
      }
      fr.sorted.push_back(
          {Key{cell_of(decoded.xyz[3 * j], cell), cell_of(decoded.xyz[3 * j + 1], cell),
               cell_of(decoded.xyz[3 * j + 2], cell)},
           j});
    }
    std::sort(fr.sorted.begin(), fr.sorted.end());
    size_t next_gap = 0;
    for (size_t i = p0; i < p1; ++i) {
      bool ok;
      if (!original.valid[i]) {
        ok = next_gap < gaps.size();
        if (ok) fr.owner[gaps[next_gap++]] = i;
      } else {
        ++fr.search;
        ok = assign(&fr, i, 64);
      }
      if (!ok) {
        *why = "frame " + std::to_string(f) + ", point " + std::to_string(i - p0) +
               (original.valid[i] ? " has no decoded point within the bound with its fields"
                                  : " is a gap and the decoded frame has fewer") +
               " (points reordered: each frame compared as a set)";
        return false;
      }
    }
    for (size_t j = p0; j < p1; ++j) move_point(original, fr.owner[j], j, out);
  }
  return true;
}

}  // namespace capz
