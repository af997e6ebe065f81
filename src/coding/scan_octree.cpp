// Octree frames, the decoding side (scan_octree.h; docs/FORMAT.md "Octree frames").
#include "coding/scan_octree.h"

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

void crossing(const Cones& c, const int64_t* a, int64_t side, const uint16_t* from, size_t count,
              size_t most, std::vector<uint16_t>* out) {
  double n[2], f[2];  // the box's nearest and farthest |x| and |y|
  for (int e = 0; e < 2; ++e) {
    const double lo = static_cast<double>(a[e]) - 0.5, hi = static_cast<double>(a[e] + side) - 0.5;
    n[e] = lo <= 0 && 0 <= hi ? 0.0 : std::min(std::fabs(lo), std::fabs(hi));
    f[e] = std::max(std::fabs(lo), std::fabs(hi));
  }
  const double rl = std::sqrt(n[0] * n[0] + n[1] * n[1]), rh = std::sqrt(f[0] * f[0] + f[1] * f[1]);
  const double zl = static_cast<double>(a[2]) - 0.5, zh = static_cast<double>(a[2] + side) - 0.5;
  const double *s = c.slope.data(), *z0 = c.z0.data();
  size_t found = 0;
  for (size_t j = 0; j < count && found < most; ++j) {
    const size_t k = from[j];
    const double z1 = z0[k] + s[k] * rl, z2 = z0[k] + s[k] * rh;
    if (std::max(z1, z2) >= zl && std::min(z1, z2) <= zh) out->push_back(from[j]), ++found;
  }
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
  if (l > 3) dec->corrupt("an octree block's flags have unknown bits");
  if ((l & 1) && t.rings() > kMaxConeRings)
    dec->corrupt("an octree block's cones from more than 256 rings");
  return OctreeMode((l & 1) ? table_cones(t) : Cones{}, (l & 2) != 0);
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
      octree::code_tree(io, static_cast<int>(d), m, lo, *prev, mode ? mode->cones() : nullptr);
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
