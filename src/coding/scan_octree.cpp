// Octree frames, the decoding side (scan_octree.h; docs/FORMAT.md "Octree frames").
#include "coding/scan_octree.h"

#include <limits>

namespace capz {
namespace scan {

namespace {

class DecodeBits {
 public:
  explicit DecodeBits(IntDecoder* dec) : dec_(dec) {}
  bool bit(int ctx, int, uint64_t) {
    const int s = dec_->get_symbol(ctx);
    if (s > 1) dec_->corrupt("an octree child bit is neither 0 nor 1");
    return s == 1;
  }
  [[noreturn]] void too_many() { dec_->corrupt("an octree level has more nodes than cells"); }

 private:
  IntDecoder* dec_;
};

}  // namespace

void decode_octree_frame(IntDecoder* dec, size_t n, uint32_t copies, bool gaps, size_t* cells_left,
                         std::vector<int32_t>* prev, int32_t* q, uint8_t* valid) {
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
  DecodeBits io(dec);
  const std::vector<uint64_t> cells = octree::code_tree(io, static_cast<int>(d), m, lo, *prev);
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
