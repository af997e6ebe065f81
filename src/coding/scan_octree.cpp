// Octree frames, the decoding side (scan_octree.h; docs/FORMAT.md "Octree frames").
#include "coding/scan_octree.h"

#include <algorithm>
#include <cmath>
#include <limits>

namespace capz {
namespace scan {

namespace {

class DecodeBits {
 public:
  DecodeBits(IntDecoder* dec, OctreeMode* mode) : dec_(dec), mode_(mode) {}
  bool bit(int ctx, int, uint64_t) {
    if (mode_ && mode_->counting()) {
      const uint32_t one = mode_->one(ctx), zero = kTotal - one;
      const bool b = dec_->target() >= zero;
      dec_->consume(b ? zero : 0, b ? one : zero);
      mode_->update(ctx, b);
      return b;
    }
    const int s = dec_->get_symbol(ctx);
    if (s > 1) dec_->corrupt("an octree child bit is neither 0 nor 1");
    return s == 1;
  }
  [[noreturn]] void too_many() { dec_->corrupt("an octree level has more nodes than cells"); }
  [[noreturn]] void too_much() {
    dec_->corrupt("the octree's cone classes take more work than its block's bytes allow");
  }

 private:
  IntDecoder* dec_;
  OctreeMode* mode_;
};

}  // namespace

namespace octree {

namespace {

// A box's nearest and farthest horizontal distance and its z range (FORMAT.md step 4, r).
// The nearest and farthest |v| over [a - 1/2, a + side - 1/2].
void extent(int64_t a, int64_t side, double* n, double* f) {
  const double lo = static_cast<double>(a) - 0.5, hi = static_cast<double>(a + side) - 0.5;
  *n = lo <= 0 && 0 <= hi ? 0.0 : std::min(std::fabs(lo), std::fabs(hi));
  *f = std::max(std::fabs(lo), std::fabs(hi));
}

// Whether the cone z = z0 + s rho crosses the box of nearest and farthest horizontal distance
// rl, rh and z range [zl, zh].
bool crossed(double s, double z0, double rl, double rh, double zl, double zh) {
  const double z1 = z0 + s * rl, z2 = z0 + s * rh;
  return std::max(z1, z2) >= zl && std::min(z1, z2) <= zh;
}

// A box's nearest and farthest horizontal distance and its z range (FORMAT.md step 4, r).
struct Reach {
  double rl, rh, zl, zh;
  Reach(const int64_t* a, int64_t side) {
    double n[2], f[2];  // the box's nearest and farthest |x| and |y|
    for (int e = 0; e < 2; ++e) extent(a[e], side, &n[e], &f[e]);
    rl = planar_length(n[0], n[1]);
    rh = planar_length(f[0], f[1]);
    zl = static_cast<double>(a[2]) - 0.5;
    zh = static_cast<double>(a[2] + side) - 0.5;
  }
  bool crossed(double s, double z0) const { return octree::crossed(s, z0, rl, rh, zl, zh); }
};

}  // namespace

void crossing(const Cones& c, const int64_t* a, int64_t side, const uint16_t* from, size_t count,
              std::vector<uint16_t>* out) {
  const Reach b(a, side);
  const double *s = c.slope.data(), *z0 = c.z0.data();
  for (size_t j = 0; j < count; ++j) {
    const size_t k = from[j];
    if (b.crossed(s[k], z0[k])) out->push_back(from[j]);
  }
}

ConeIndex::ConeIndex(const Cones& c) : order_(c.rings()) {
  for (size_t k = 0; k < order_.size(); ++k) order_[k] = static_cast<uint16_t>(k);
  std::stable_sort(order_.begin(), order_.end(),
                   [&](uint16_t i, uint16_t j) { return c.slope[i] < c.slope[j]; });
  const size_t n = order_.size();
  s_.resize(n), top_.resize(n), bot_.resize(n);
  for (size_t i = 0; i < n; ++i) {
    s_[i] = c.slope[order_[i]];
    top_[i] = i == 0 ? c.z0[order_[i]] : std::max(top_[i - 1], c.z0[order_[i]]);
  }
  for (size_t i = n; i-- > 0;)
    bot_[i] = i + 1 == n ? c.z0[order_[i]] : std::min(bot_[i + 1], c.z0[order_[i]]);
}

void ConeIndex::crossing_all(const Cones& c, const int64_t* a, int64_t side,
                             std::vector<uint16_t>* out) const {
  const Reach b(a, side);
  // Ring i (by slope) reaches at most top_[i] + s rho at rho = rh (s >= 0) or rl (s < 0), at
  // least bot_[i] + s rho at the other end; each computed as the box test computes z1 and z2,
  // so not below its largest z (nor above its least): those below zl, then those above zh, are
  // runs at the two ends of the order.
  const auto below = [&](size_t i) { return top_[i] + s_[i] * (s_[i] >= 0 ? b.rh : b.rl) < b.zl; };
  const auto above = [&](size_t i) { return bot_[i] + s_[i] * (s_[i] >= 0 ? b.rl : b.rh) > b.zh; };
  const auto first = [](size_t i, size_t end, auto is) {  // the first of [i, end) that `is`
    while (i < end) {
      const size_t mid = i + (end - i) / 2;
      if (is(mid))
        end = mid;
      else
        i = mid + 1;
    }
    return i;
  };
  const size_t lo = first(0, order_.size(), [&](size_t i) { return !below(i); });
  const size_t hi = first(lo, order_.size(), above);
  const size_t start = out->size();
  const double *s = c.slope.data(), *z0 = c.z0.data();
  for (size_t i = lo; i < hi; ++i) {
    const uint16_t k = order_[i];
    if (b.crossed(s[k], z0[k])) out->push_back(k);
  }
  std::sort(out->begin() + static_cast<std::ptrdiff_t>(start), out->end());
}

bool ConeWalk::start_parent(const int64_t* p, int l, size_t j) {
  j_ = j;
  c_->work += c_->rings();
  if (c_->work > c_->budget) return false;
  const int64_t side = int64_t{1} << (d_ - l);
  const int64_t a[3] = {lo_[0] + side * p[0], lo_[1] + side * p[1], lo_[2] + side * p[2]};
  mine_.clear();
  if (first_) {
    c_->index->crossing_all(*c_, a, side, &mine_);
    pool_.insert(pool_.end(), mine_.begin(), mine_.end());
    span_.push_back(pool_.size());
  } else {
    const size_t up = parent_of_[j];
    if (span_[up + 1] > span_[up])
      crossing(*c_, a, side, pool_.data() + span_[up], span_[up + 1] - span_[up], &mine_);
  }
  if (mine_.empty()) return true;  // every child's class is 0
  const int64_t half = side / 2;
  double n[2][2], f[2][2];  // by axis and half
  for (int e = 0; e < 2; ++e)
    for (int h = 0; h < 2; ++h) extent(a[e] + h * half, half, &n[e][h], &f[e][h]);
  for (int h = 0; h < 4; ++h) {
    rl_[h] = planar_length(n[0][h >> 1], n[1][h & 1]);
    rh_[h] = planar_length(f[0][h >> 1], f[1][h & 1]);
  }
  for (int h = 0; h < 2; ++h) {
    zl_[h] = static_cast<double>(a[2] + h * half) - 0.5;
    zh_[h] = static_cast<double>(a[2] + h * half + half) - 0.5;
  }
  return true;
}

int ConeWalk::child_class(const int64_t* c) const {
  const size_t xy = static_cast<size_t>((c[0] & 1) * 2 + (c[1] & 1)),
               z = static_cast<size_t>(c[2] & 1);
  const double *s = c_->slope.data(), *z0 = c_->z0.data();
  int found = 0;
  for (size_t j = 0; j < mine_.size() && found < 2; ++j)
    found += crossed(s[mine_[j]], z0[mine_[j]], rl_[xy], rh_[xy], zl_[z], zh_[z]);
  return found;
}

}  // namespace octree

Cones table_cones(const Table& t) {
  Cones c;
  c.slope.assign(t.slope.begin(), t.slope.end());
  c.z0.assign(t.z0.begin(), t.z0.end());
  return c;
}

OctreeMode read_octree_flags(IntDecoder* dec, const Table& t) {
  if (t.rings() == 0) return {};
  const uint32_t l = dec->get(kOctFlagsCtx);
  if (l > 7) dec->corrupt("an octree block's flags have unknown bits");
  if ((l & 4) && !(l & 2)) dec->corrupt("an octree block's mix without counting models");
  if ((l & 1) && t.rings() > kMaxConeRings)
    dec->corrupt("an octree block's cones from more than 256 rings");
  return OctreeMode((l & 1) ? table_cones(t) : Cones{}, (l & 2) != 0, (l & 4) != 0);
}

void decode_octree_frame(IntDecoder* dec, size_t n, uint32_t copies, bool gaps, size_t* cells_left,
                         std::vector<int32_t>* prev, int32_t* q, uint8_t* valid, OctreeMode* mode) {
  size_t g = 0;
  if (gaps) {
    g = dec->get(kOctCornerCtx);
    if (g == 0 || g + copies + 1 > n) dec->corrupt("an octree frame's gaps are out of range");
  }
  const size_t m = n - copies - g;
  if (m > *cells_left) dec->corrupt("more cells than the octree block can hold");
  *cells_left -= m;
  const uint32_t d = dec->get(kOctDepthCtx);
  if (d > static_cast<uint32_t>(kMaxOctreeDepth)) dec->corrupt("an octree deeper than 21 levels");
  if (d == 0 && m != 1) dec->corrupt("an octree of depth 0 with more than one cell");
  int64_t lo[3];
  for (int64_t& v : lo) {
    v = dec->get_signed(kOctCornerCtx);
    if (v + (int64_t{1} << d) - 1 > std::numeric_limits<int32_t>::max())
      dec->corrupt("an octree's cube beyond the grid integers' range");
  }
  DecodeBits io(dec, mode);
  const std::vector<uint64_t> cells =
      octree::code_tree(io, static_cast<int>(d), m, lo, *prev, mode ? mode->cones() : nullptr,
                        mode ? mode->mixer() : nullptr);
  if (cells.size() != m) dec->corrupt("an octree with fewer cells than the frame's");
  std::vector<uint32_t> points(m, 1);
  octree::KeySet set, before;
  if (copies > 0) {
    set.reset(m);
    for (size_t j = 0; j < m; ++j) set.insert(cells[j], static_cast<uint32_t>(j));
    octree::previous_cells(*prev, lo, static_cast<int>(d), &before);
  }
  std::vector<int32_t> mine;  // this frame's cells, for the next
  mine.reserve(4 * m);
  uint32_t left = copies;
  size_t at = 0;
  for (size_t j = 0; j < m; ++j) {
    int64_t v[3];
    octree::coords(cells[j], v);
    for (int a = 0; a < 3; ++a) {
      v[a] += lo[a];
      mine.push_back(static_cast<int32_t>(v[a]));
    }
    uint32_t c = 0;
    if (copies > 0) {
      c = dec->get(octree::count_context(cells, set, points, j, v, before, *prev));
      if (c > left) dec->corrupt("a cell's count exceeds the frame's copies");
      left -= c;
      points[j] = c + 1;
    }
    mine.push_back(static_cast<int32_t>(c + 1));
    for (uint32_t k = 0; k <= c; ++k, ++at) {
      for (int a = 0; a < 3; ++a) q[3 * at + static_cast<size_t>(a)] = static_cast<int32_t>(v[a]);
      valid[at] = 1;
    }
  }
  if (left != 0) dec->corrupt("the cells' counts fall short of the frame's copies");
  prev->swap(mine);
  for (; at < n; ++at) {
    q[3 * at] = q[3 * at + 1] = q[3 * at + 2] = 0;
    valid[at] = 0;
  }
}

}  // namespace scan
}  // namespace capz
