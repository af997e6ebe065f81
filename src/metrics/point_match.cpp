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
  const PointsView& o;
  const PointsView& d;
  double bound, cell;
  const std::vector<bool>& exact;
  std::vector<std::pair<Key, size_t>> sorted;
  std::vector<size_t> owner;  // per decoded point of the take: its original partner or kNone
  std::vector<size_t> seen;   // per decoded point: the search that last visited it
  size_t search = 0;
};

// The bytes a point of field f of v holds.
size_t bytes_per_point(const PointsView& v, size_t f) {
  const size_t n = v.total();
  return n ? v.fields[f]->size() / n : 0;
}

// Whether original point i and decoded point j agree: coordinates within the bound, the exact
// fields byte for byte.
bool agree(const Frame& fr, size_t i, size_t j) {
  for (size_t a = 0; a < 3; ++a)
    if (!(std::fabs(fr.o.xyz[3 * i + a] - fr.d.xyz[3 * j + a]) <= fr.bound)) return false;
  for (size_t f = 0; f < fr.o.fields.size() && f < fr.d.fields.size(); ++f) {
    if (f >= fr.exact.size() || !fr.exact[f]) continue;
    const size_t bpp = bytes_per_point(fr.o, f);
    if (std::memcmp(fr.o.fields[f]->data() + i * bpp, fr.d.fields[f]->data() + j * bpp, bpp) != 0)
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

}  // namespace

namespace {

// The view of a take or a block; bytes(a): the bytes of one of its attributes.
template <class Frames, class Bytes>
PointsView view_of(const Frames& t, Bytes bytes) {
  PointsView v;
  v.frames = t.frames;
  v.points = t.points;
  v.offsets = t.ragged() ? &t.frame_offsets : nullptr;
  v.xyz = t.xyz.data();
  v.valid = t.valid.data();
  for (const auto& a : t.attributes) v.fields.push_back(&bytes(a));
  return v;
}

}  // namespace

PointsView points_of(const Take& t) {
  return view_of(t, [](const PointAttribute& a) -> const std::vector<uint8_t>& { return a.data; });
}

PointsView points_of(const FrameBlock& b) {
  return view_of(b, [](const std::vector<uint8_t>& a) -> const std::vector<uint8_t>& { return a; });
}

bool same_counts(const PointsView& a, const PointsView& b) {
  if (a.frames != b.frames) return false;
  for (size_t f = 0; f <= a.frames; ++f)
    if (a.begin(f) != b.begin(f)) return false;
  return true;
}

bool match_reordered(const PointsView& original, const PointsView& decoded, double bound,
                     const std::vector<bool>& exact_fields, std::vector<size_t>* partner,
                     std::string* why) {
  const double cell = bound > 0 ? 2 * bound : 1.0;
  Frame fr{original, decoded, bound, cell, exact_fields, {}, {}, {}, 0};
  fr.owner.assign(original.total(), kNone);
  fr.seen.assign(original.total(), 0);
  for (size_t f = 0; f < original.frames; ++f) {
    const size_t p0 = original.begin(f), p1 = original.begin(f + 1);
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
  }
  partner->swap(fr.owner);
  return true;
}

void move_to_partners(const PointsView& v, const std::vector<size_t>& partner,
                      std::vector<double>* xyz, std::vector<uint8_t>* valid,
                      std::vector<std::vector<uint8_t>>* fields) {
  const size_t n = v.total();
  xyz->resize(3 * n);
  valid->resize(n);
  for (size_t j = 0; j < n; ++j) {
    std::copy_n(v.xyz + 3 * partner[j], 3, xyz->data() + 3 * j);
    (*valid)[j] = v.valid[partner[j]];
  }
  fields->resize(v.fields.size());
  for (size_t f = 0; f < v.fields.size(); ++f) {
    const std::vector<uint8_t>& in = *v.fields[f];
    std::vector<uint8_t>& out = (*fields)[f];
    const size_t bpp = bytes_per_point(v, f);
    if (bpp == 0 || in.size() != n * bpp) {
      out = in;
      continue;
    }
    out.resize(in.size());
    for (size_t j = 0; j < n; ++j)
      std::copy_n(in.data() + partner[j] * bpp, bpp, out.data() + j * bpp);
  }
}

}  // namespace capz
