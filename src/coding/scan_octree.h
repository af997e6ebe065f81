// Octree frames (docs/FORMAT.md "Scans (format 1.1)", "Octree frames"): a frame's valid points
// as the distinct cells of an octree, each with its count of points, in an entropy-coded block
// of their own. The walk over the tree both sides run is here (code_tree); the decoder in
// scan_octree.cpp, the encoder in scan_octree_encode.cpp.
#pragma once

#include <algorithm>
#include <cstddef>
#include <cstdint>
#include <memory>
#include <utility>
#include <vector>

#include "coding/entropy.h"
#include "coding/scan_geometry.h"
#include "coding/scan_octree_mix.h"
#include "coding/scan_shared.h"

namespace capz {
namespace scan {

// The octree block's contexts: the depth 0, the gaps and the corner 1, the counts 2..577, the
// child bits 578..19009, the block's flags 19010, the child bits with a cone class 0 or 1
// 19011..43586.
constexpr int kOctDepthCtx = 0, kOctCornerCtx = 1, kOctCountCtx = 2, kOctBitCtx = 578;
constexpr int kOctFlagsCtx = kOctBitCtx + 128 * 8 * 3 * 3 * 2, kOctConeCtx = kOctFlagsCtx + 1;
constexpr int kOctreeContexts = kOctConeCtx + 128 * 8 * 3 * 2 * 2 * 2;
constexpr int kMaxOctreeDepth = 21;
// The most rings of a table whose cones the child bits may use (FORMAT.md "The cone flag").
constexpr size_t kMaxConeRings = 256;

// The cone classes' work a window's octree block may ask for: K for each node of the last two
// levels' parents, at most this much a byte of the block (FORMAT.md "The block's flags").
constexpr uint64_t kMaxConeWorkPerByte = 4096;

namespace octree {
class ConeIndex;
}

// A laser table's cones for the child bits' cone class (FORMAT.md step 4, r): per ring its
// slope and z offset, the table's f32 values widened. Empty: no cone class. work: the window's
// cone work so far (K per parent classed), at most budget. index: their ConeIndex, built once a
// window by the first frame whose walk classes children (which that frame's work pays for; a
// frame of depth 0 classes none and costs nothing), so slope and z0 do not change after.
struct Cones {
  std::vector<double> slope, z0;
  uint64_t work = 0, budget = UINT64_MAX;
  std::shared_ptr<const octree::ConeIndex> index;
  size_t rings() const { return slope.size(); }
};

// An octree block's coding of its child bits (FORMAT.md "The block's flags", L): the cones
// (bit 0) and the counting models (bit 1) with their state, one per child-bit context.
class OctreeMode {
 public:
  static constexpr int kMaxCount = 62;
  OctreeMode() = default;
  // mixing (L bit 2) only with counting.
  OctreeMode(Cones cones, bool counting, bool mixing = false)
      : cones_(std::move(cones)), counting_(counting) {
    if (mixing && counting) mixer_ = std::make_unique<OctreeMixer>();
    if (!counting_) return;
    p_.assign(static_cast<size_t>(kOctreeContexts - kOctBitCtx), 1 << 14);
    n_.assign(p_.size(), 0);
  }
  Cones* cones() { return cones_.rings() > 0 ? &cones_ : nullptr; }
  bool counting() const { return counting_; }
  uint32_t flags() const {
    return (cones_.rings() > 0 ? 1u : 0u) | (counting_ ? 2u : 0u) | (mixer_ ? 4u : 0u);
  }
  OctreeMixer* mixer() { return mixer_.get(); }
  // Context ctx's frequency of a 1 (of kTotal); with the mixer, the mix's (its inputs set).
  uint32_t one(int ctx) {
    const uint32_t p = p_[static_cast<size_t>(ctx - kOctBitCtx)];
    if (mixer_) return mixer_->one(p);
    return std::min(std::max(p, 16u), kTotal - 16);
  }
  // After a bit b of context ctx.
  void update(int ctx, bool b) {
    const size_t k = static_cast<size_t>(ctx - kOctBitCtx);
    if (mixer_) mixer_->update(b);
    const int p = p_[k], n = n_[k];
    p_[k] = static_cast<uint16_t>(p + ((b ? static_cast<int>(kTotal) : 0) - p) / (n + 2));
    if (n < kMaxCount) ++n_[k];
  }

 private:
  Cones cones_;
  bool counting_ = false;
  std::unique_ptr<OctreeMixer> mixer_;
  std::vector<uint16_t> p_;
  std::vector<uint8_t> n_;
};

namespace octree {

// The rings among `from` (indices into c) that cross the box of side `side` cells whose least
// cell has the grid integers a (FORMAT.md step 4, r), appended to *out in from's order. A ring that
// crosses a box crosses every box holding it (the binary64 steps are monotone), so a child's rings
// are among its parent's. In scan_octree.cpp (compiled without contraction).
void crossing(const Cones& c, const int64_t* a, int64_t side, const uint16_t* from, size_t count,
              std::vector<uint16_t>* out);

// The rings of c that cross a box (crossing's a and side), found among those a bisection leaves:
// the rings sorted by slope, each bounded above by its slope and the greatest offset at or before
// it, below by its slope and the least offset at or after it (both nondecreasing along the
// order, and the box test's binary64 steps monotone), so the rings that can cross are one run of
// the order; each is then tested as crossing tests it. The same rings as crossing from every ring
// in index order (ScanOctreeCones tests it against crossing on random and real tables).
class ConeIndex {
 public:
  explicit ConeIndex(const Cones& c);
  // Appends the crossing rings to *out in index order.
  void crossing_all(const Cones& c, const int64_t* a, int64_t side,
                    std::vector<uint16_t>* out) const;

 private:
  std::vector<uint16_t> order_;        // ring indices by slope
  std::vector<double> s_, top_, bot_;  // their slopes, greatest z0 up to, least z0 from each
};

// Morton keys of 21-bit coordinates: bit 3b + 2 is x's bit b, 3b + 1 y's, 3b z's.
inline uint64_t spread(uint64_t v) {
  v &= 0x1FFFFF;
  v = (v | v << 32) & 0x1F00000000FFFFull;
  v = (v | v << 16) & 0x1F0000FF0000FFull;
  v = (v | v << 8) & 0x100F00F00F00F00Full;
  v = (v | v << 4) & 0x10C30C30C30C30C3ull;
  v = (v | v << 2) & 0x1249249249249249ull;
  return v;
}
inline uint64_t compact(uint64_t v) {
  v &= 0x1249249249249249ull;
  v = (v ^ (v >> 2)) & 0x10C30C30C30C30C3ull;
  v = (v ^ (v >> 4)) & 0x100F00F00F00F00Full;
  v = (v ^ (v >> 8)) & 0x1F0000FF0000FFull;
  v = (v ^ (v >> 16)) & 0x1F00000000FFFFull;
  v = (v ^ (v >> 32)) & 0x1FFFFF;
  return v;
}
inline uint64_t key(uint64_t x, uint64_t y, uint64_t z) {
  return spread(x) << 2 | spread(y) << 1 | spread(z);
}
inline void coords(uint64_t k, int64_t* c) {
  c[0] = static_cast<int64_t>(compact(k >> 2));
  c[1] = static_cast<int64_t>(compact(k >> 1));
  c[2] = static_cast<int64_t>(compact(k));
}
// The key's bits of each axis (x, y, z), and the key one step (-1, 0 or 1) along an axis, the
// coordinate staying within [0, 2^21): the neighbours' keys without spreading coordinates.
constexpr uint64_t kAxisBits[3] = {0x1249249249249249ull << 2, 0x1249249249249249ull << 1,
                                   0x1249249249249249ull};
inline uint64_t step_key(uint64_t k, int axis, int step) {
  const uint64_t m = kAxisBits[axis], low = uint64_t{1} << (2 - axis);
  if (step > 0) return (((k | ~m) + low) & m) | (k & ~m);
  if (step < 0) return (((k & m) - low) & m) | (k & ~m);
  return k;
}
// The 26 neighbours of the node of key k at coordinates v whose coordinates lie in [0, side):
// each(f, skip) calls f(e, key) for each in the order of e = 9 (dx + 1) + 3 (dy + 1) + dz + 1
// but those whose bit e is set in skip (bit 13, the node, always).
class Around {
 public:
  Around(uint64_t k, const int64_t* v, int64_t side) {
    for (int a = 0; a < 3; ++a) {
      const uint64_t m = kAxisBits[a], low = uint64_t{1} << (2 - a);  // step_key's, unrolled
      part_[a][0] = ((k & m) - low) & m;
      part_[a][1] = k & m;
      part_[a][2] = ((k | ~m) + low) & m;
      ok_[a][0] = v[a] > 0;
      ok_[a][1] = v[a] >= 0 && v[a] < side;
      ok_[a][2] = v[a] + 1 < side;
    }
  }
  template <class F>
  void each(F&& f, uint32_t skip = 1u << 13) const {
    for (int x = 0; x < 3; ++x) {
      if (!ok_[0][x]) continue;
      for (int y = 0; y < 3; ++y) {
        if (!ok_[1][y]) continue;
        const uint64_t xy = part_[0][x] | part_[1][y];
        for (int z = 0; z < 3; ++z) {
          const int e = 9 * x + 3 * y + z;
          if (ok_[2][z] && !((skip >> e) & 1)) f(e, xy | part_[2][z]);
        }
      }
    }
  }

 private:
  uint64_t part_[3][3];  // the bits of axis a of the key at step t - 1
  bool ok_[3][3];        // whether that coordinate lies in [0, side)
};

// The neighbours e (Around's) with dx, dy, dz >= 0: their keys are above the node's (a key grows
// with each coordinate), the node's own included.
constexpr uint32_t kUpperNeighbours = [] {
  uint32_t b = 0;
  for (int e = 0; e < 27; ++e)
    b |= static_cast<uint32_t>(e / 9 >= 1 && (e / 3) % 3 >= 1 && e % 3 >= 1) << e;
  return b;
}();
// For a node at position o in its parent (key & 7): at[o][s] the e of its sibling at position s,
// skip[o] those e and the node's own.
struct Siblings {
  int at[8][8] = {};
  uint32_t skip[8] = {};
  constexpr Siblings() {
    for (int o = 0; o < 8; ++o)
      for (int s = 0; s < 8; ++s) {
        at[o][s] = 9 * (((s >> 2) & 1) - ((o >> 2) & 1) + 1) +
                   3 * (((s >> 1) & 1) - ((o >> 1) & 1) + 1) + (s & 1) - (o & 1) + 1;
        skip[o] |= uint32_t{1} << at[o][s];
      }
  }
};
constexpr Siblings kSiblings;

// A set of Morton keys (each below 2^63) with an index each: open addressing, at most half
// full. The walk's and the counts' neighbour lookups (a binary search in the sorted keys
// answers the same, several times slower).
class KeySet {
 public:
  // Room for n keys; emptied.
  void reset(size_t n) {
    size_t cap = 16;
    while (cap < 2 * n) cap <<= 1;
    shift_ = 64 - __builtin_ctzll(cap);
    keys_.assign(cap, kEmpty);
    index_.resize(cap);
    size_ = 0;
  }
  bool empty() const { return size_ == 0; }
  void insert(uint64_t k, uint32_t index) {
    size_t at = slot(k);
    while (keys_[at] != kEmpty) at = (at + 1) & (keys_.size() - 1);
    keys_[at] = k;
    index_[at] = index;
    ++size_;
  }
  // The key's index, or -1.
  int64_t find(uint64_t k) const {
    for (size_t at = slot(k);; at = (at + 1) & (keys_.size() - 1)) {
      if (keys_[at] == k) return index_[at];
      if (keys_[at] == kEmpty) return -1;
    }
  }

 private:
  static constexpr uint64_t kEmpty = ~uint64_t{0};
  size_t slot(uint64_t k) const {
    return static_cast<size_t>((k * 0x9E3779B97F4A7C15ull) >> shift_);
  }
  int shift_ = 60;
  size_t size_ = 0;
  std::vector<uint64_t> keys_;
  std::vector<uint32_t> index_;
};

// o7's bit k - 1: the neighbour at (2 o - 1) a for k's bits a (o child i's), by a table
struct Toward {
  int at[8][8] = {};
  constexpr Toward() {
    for (int j = 0; j < 8; ++j)
      for (int k = 1; k < 8; ++k)
        for (int e = 0; e < 3; ++e)
          at[j][k] = at[j][k] * 3 + (2 * ((j >> (2 - e)) & 1) - 1) * ((k >> (2 - e)) & 1) + 1;
  }
};
constexpr Toward kToward;

// The child bit's context from its parts (FORMAT.md step 4).
inline int context_of(int o7, int cn, int sib, int lc, int pv, int r) {
  if (r < 2) return kOctConeCtx + 2 * ((((o7 * 8 + cn) * 3 + sib) * 2 + lc) * 2 + r) + pv;
  return kOctBitCtx + 2 * (((o7 * 8 + cn) * 3 + sib) * 3 + lc) + pv;
}

// The child bit's context (FORMAT.md step 4) of child i (key ck, coordinates c) of a node at
// level l of a tree of depth d: nb[k] is P of the parent's neighbour (dx, dy, dz) at k = 9 (dx +
// 1) + 3 (dy + 1) + dz + 1; next the level l + 1 coded so far; coded the bits of the children
// before i (bit j: child j is a node), ones how many; before the level l + 1 nodes of the
// previous frame's cells; r the cone class (2 without one).
inline int child_context(const int* nb, const KeySet& next, const KeySet& before, uint64_t ck,
                         const int64_t* c, int l, int d, int i, int coded, int ones, int r = 2) {
  int o7 = 0;
  for (int k = 1; k < 8; ++k) o7 |= nb[kToward.at[i][k]] << (k - 1);
  int cn = 0;  // the child's neighbours one below on each axis (within the cube: c >= 0)
  for (int e = 0; e < 3; ++e) {
    const int bit = 1 << (2 - e);  // a sibling when the child is the upper half on axis e
    if (i & bit)
      cn |= ((coded >> (i ^ bit)) & 1) << e;
    else
      cn |= static_cast<int>(c[e] > 0 && next.find(step_key(ck, e, -1)) >= 0) << e;
  }
  const int sib = std::min(ones, 2);
  const int lc = l == d - 1 ? 0 : l == d - 2 ? 1 : 2;
  const int pv = !before.empty() && before.find(ck) >= 0;
  return context_of(o7, cn, sib, lc, pv, r);
}

// The cone classes of a walk's last two levels: a parent's crossing rings (crossing) at level
// D - 2 from every ring (ConeIndex), at D - 1 from its own parent's (kept by index); each
// child's class from its parent's rings, stopping at 2 (the children's box reaches worked out
// once a parent, as crossing works them out). In scan_octree.cpp, compiled without contraction.
class ConeWalk {
 public:
  ConeWalk(Cones* c, int d, const int64_t* lo) : c_(c), d_(d), lo_(lo) {}
  bool on() const { return c_ != nullptr && c_->rings() > 0; }
  // Before the parents of level l (whose children are the nodes of level l + 1).
  void start_level(int l) {
    first_ = l == std::max(d_ - 2, 0);
    if (!first_) return;  // level D - 1 reads what level D - 2 kept
    if (!c_->index) c_->index = std::make_shared<const ConeIndex>(*c_);
    pool_.clear();
    span_.assign(1, 0);
    parent_of_.clear();
  }
  // Before the children of the parent at p, the j-th node of level l; false when that takes the
  // window's cone work past its budget.
  bool start_parent(const int64_t* p, int l, size_t j);
  // The class of child c (its coordinates at level l + 1) of the parent started last.
  int child_class(const int64_t* c) const;
  // The child last classed is a node (the next of level l + 1).
  void keep_child() {
    if (first_) parent_of_.push_back(j_);
  }

 private:
  Cones* c_;
  int d_;
  size_t j_ = 0;
  const int64_t* lo_;
  bool first_ = false;
  std::vector<uint16_t> mine_, pool_;
  std::vector<size_t> span_, parent_of_;
  // The children's nearest and farthest horizontal distance by x half 2 + y half, z range by z
  // half (crossing's rl, rh, zl, zh of each child's box).
  double rl_[4], rh_[4], zl_[2], zh_[2];
};

// Whether the grid integers u lie in the cube [lo, lo + side)^3, and *k their key from lo.
inline bool inside(const int32_t* u, const int64_t* lo, int64_t side, uint64_t* k) {
  int64_t r[3];
  for (int a = 0; a < 3; ++a) {
    r[a] = u[a] - lo[a];
    if (r[a] < 0 || r[a] >= side) return false;
  }
  *k = key(static_cast<uint64_t>(r[0]), static_cast<uint64_t>(r[1]), static_cast<uint64_t>(r[2]));
  return true;
}

// The previous frame's cells (x y z grid integers and points, 4 a cell) as the nodes of each
// level 1..d of a tree of depth d with corner lo (those inside its cube), each level's keys
// sorted: (*out)[l].
inline void previous_levels(const std::vector<int32_t>& prev, const int64_t* lo, int d,
                            std::vector<std::vector<uint64_t>>* out) {
  out->assign(static_cast<size_t>(d) + 1, {});
  if (prev.empty()) return;
  std::vector<uint64_t>& cells = (*out)[static_cast<size_t>(d)];
  const int64_t side = int64_t{1} << d;
  uint64_t k;
  for (size_t j = 0; j + 3 < prev.size(); j += 4)
    if (inside(&prev[j], lo, side, &k)) cells.push_back(k);
  std::sort(cells.begin(), cells.end());
  cells.erase(std::unique(cells.begin(), cells.end()), cells.end());
  for (int l = d - 1; l >= 1; --l)
    for (uint64_t below : (*out)[static_cast<size_t>(l) + 1]) {
      std::vector<uint64_t>& up = (*out)[static_cast<size_t>(l)];
      if (up.empty() || up.back() != below >> 3) up.push_back(below >> 3);
    }
}

// nb[e] (child_context's) of the node of key pk at p of a level of side `side` whose nodes are
// `here`; siblings: its parent's child bits (-1: no parent).
inline void parent_neighbours(const KeySet& here, uint64_t pk, const int64_t* p, int64_t side,
                              int siblings, int* nb, size_t j = 0, const uint8_t* kids = nullptr,
                              int* km = nullptr) {
  std::fill(nb, nb + 27, 0);
  if (km) std::fill(km, km + 27, 0);
  uint32_t skip = 1u << 13;
  if (siblings >= 0) {
    const size_t o = pk & 7;
    for (size_t s = 0; s < 8; ++s) {
      nb[kSiblings.at[o][s]] = (siblings >> s) & 1;
      // a sibling before the node: the nodes from it up to the node's own are its index's lead
      if (km && s < o && ((siblings >> s) & 1))
        km[kSiblings.at[o][s]] =
            kids[j - static_cast<size_t>(kOnes[siblings & ((1 << o) - (1 << s))])];
    }
    skip = kSiblings.skip[o];
  }
  nb[13] = 1;
  Around(pk, p, side)
      .each(
          [&](int at, uint64_t k) {
            const int64_t x = here.find(k);
            nb[at] = x >= 0;
            if (km && x >= 0 && static_cast<size_t>(x) < j) km[at] = kids[x];
          },
          skip);
}

// The offset of a parent's neighbour one step along axis a in nb's index.
constexpr int kFace[3] = {9, 3, 1};

// The walk over a tree of depth d and corner lo (FORMAT.md step 4) both sides run: io.bit(ctx,
// level, key of the child) gives each coded child bit (the encoder's actual one, or the decoded
// one); the inferred ones are not asked. prev: the previous frame's cells (empty: none); cones:
// the table's cones with L bit 0 (null or empty: without).
// Returns the cells' keys in Morton order, or stops with io.too_many() (which throws) when a
// level has more than m nodes, or with io.too_much() (which throws) past the cone work's
// budget.
template <class Io, class Mix = OctreeMixer>
std::vector<uint64_t> code_tree(Io& io, int d, size_t m, const int64_t* lo,
                                const std::vector<int32_t>& prev, Cones* cones = nullptr,
                                Mix* mx = nullptr) {
  std::vector<uint64_t> level{0}, next;
  KeySet here, there, before;  // level's keys, next's so far, the previous frame's at next's
  std::vector<std::vector<uint64_t>> earlier;
  previous_levels(prev, lo, d, &earlier);
  ConeWalk cw(cones, d, lo);
  octree::MixWalk mw;
  // level's parents' child bits (by index), level's nodes' parents (by index); next's, so far
  std::vector<uint8_t> kids_up, kids;
  std::vector<uint32_t> up, up_next;
  here.reset(1);
  here.insert(0, 0);
  for (int l = 0; l < d; ++l) {
    const bool classed = cw.on() && l >= d - 2;
    if (classed) cw.start_level(l);
    const std::vector<uint64_t>& e = earlier[static_cast<size_t>(l) + 1];
    before.reset(e.size());
    for (uint64_t k : e) before.insert(k, 0);
    next.clear();
    there.reset(std::min(m, 8 * level.size()));
    const int64_t side = int64_t{1} << l;
    for (size_t j = 0; j < level.size(); ++j) {
      const uint64_t pk = level[j];
      int64_t p[3];
      coords(pk, p);
      if (classed && !cw.start_parent(p, l, j)) io.too_much();
      int nb[27];
      int km[27];
      parent_neighbours(here, pk, p, side, l > 0 ? kids_up[up[j]] : -1, nb, j, kids.data(), km);
      int ones = 0, coded = 0;
      if (mx) mw.start_parent(km, lo, p, l, d);
      const int lc = l == d - 1 ? 0 : l == d - 2 ? 1 : 2;
      for (int i = 0; i < 8; ++i) {
        const uint64_t ck = pk << 3 | static_cast<uint64_t>(i);
        const int64_t c[3] = {2 * p[0] + (i >> 2), 2 * p[1] + ((i >> 1) & 1), 2 * p[2] + (i & 1)};
        bool bit = true;
        const int r = classed ? cw.child_class(c) : 2;
        if (i < 7 || ones > 0) {
          // child_context's parts; cn from the child bits of the parent's earlier neighbours
          int o7 = 0, cn = 0;
          for (int k = 1; k < 8; ++k) o7 |= nb[kToward.at[i][k]] << (k - 1);
          for (int a = 0; a < 3; ++a) {
            const int half = 1 << (2 - a);
            cn |= (((i & half) ? coded : km[13 - kFace[a]]) >> (i ^ half) & 1) << a;
          }
          const int sib = std::min(ones, 2), pv = !before.empty() && before.find(ck) >= 0;
          if (mx) mw.child(mx, i, o7, cn, sib, lc, pv, r);
          bit = io.bit(context_of(o7, cn, sib, lc, pv, r), l, ck);
        }
        if (!bit) continue;
        if (mx) mw.keep_child(i);
        if (next.size() >= m) io.too_many();
        if (classed) cw.keep_child();
        there.insert(ck, static_cast<uint32_t>(next.size()));
        next.push_back(ck);
        up_next.push_back(static_cast<uint32_t>(j));
        coded |= 1 << i;
        ++ones;
      }
      kids.push_back(static_cast<uint8_t>(coded));
    }
    level.swap(next);
    std::swap(here, there);  // next's keys, all of them now
    kids_up.swap(kids);
    kids.clear();
    up.swap(up_next);
    up_next.clear();
  }
  return level;
}

// The previous frame's cells (4 ints a cell, previous_levels') inside the cube of corner lo
// and depth d, by key from lo, each with its index in prev.
inline void previous_cells(const std::vector<int32_t>& prev, const int64_t* lo, int d,
                           KeySet* out) {
  out->reset(prev.size() / 4);
  const int64_t side = int64_t{1} << d;
  uint64_t k;
  for (size_t j = 0; j + 3 < prev.size(); j += 4)
    if (inside(&prev[j], lo, side, &k)) out->insert(k, static_cast<uint32_t>(j / 4));
}

// A cell's count context (FORMAT.md step 5): cells sorted and `set` them with their indices,
// j the cell's index, points its cells' points so far (valid up to j), abs the cell's grid
// integers; before: the previous frame's cells by key (previous_cells), prev its cells.
inline int count_context(const std::vector<uint64_t>& cells, const KeySet& set,
                         const std::vector<uint32_t>& points, size_t j, const int64_t* abs,
                         const KeySet& before, const std::vector<int32_t>& prev) {
  uint64_t s2 = 0;
  for (int a = 0; a < 3; ++a) {
    const uint64_t v = static_cast<uint64_t>(abs[a] < 0 ? -abs[a] : abs[a]);
    s2 += v * v;
  }
  const int bits = s2 == 0 ? 0 : 64 - __builtin_clzll(s2);
  const int oct = std::min(bits / 2, 15);
  int64_t v[3];
  coords(cells[j], v);
  uint64_t k = 0, sum = 0;
  // outside [0, 2^21) (at depth 21, 2^21 has no 21-bit key: it would be taken for 0)
  // (those above in key order are not before this one: not asked)
  Around(cells[j], v, int64_t{1} << kMaxOctreeDepth)
      .each(
          [&](int, uint64_t c) {
            const int64_t at = set.find(c);
            if (at < 0 || static_cast<size_t>(at) >= j) return;  // not a cell, or not before
            ++k;
            sum += points[static_cast<size_t>(at)];
          },
          kUpperNeighbours);
  const int nc = k == 0            ? 0
                 : 2 * sum < 3 * k ? 1
                 : 2 * sum < 5 * k ? 2
                 : sum < 4 * k     ? 3
                 : sum < 8 * k     ? 4
                                   : 5;
  const int64_t at = prev.empty() ? -1 : before.find(cells[j]);
  const int32_t was = at < 0 ? 0 : prev[4 * static_cast<size_t>(at) + 3];
  const int pc = was == 0 ? 0 : was == 1 ? 1 : was == 2 ? 2 : was <= 4 ? 3 : was <= 8 ? 4 : 5;
  return kOctCountCtx + 6 * (6 * oct + nc) + pc;
}

}  // namespace octree

// Starts every child-bit context of an octree block on 2 symbols (FORMAT.md step 4).
template <class Coder>
void start_octree_block(Coder* c) {
  for (int k = kOctBitCtx; k < kOctreeContexts; ++k)
    if (k != kOctFlagsCtx) c->restrict_context(k, 2);
}

// The cones of table t (its slopes and offsets widened; FORMAT.md "The cone flag").
Cones table_cones(const Table& t);

// Decodes octree frame of n points (copies of them copies; with gaps, G is read) into q (3 per
// point) and valid, per FORMAT.md; mode: the block's (read_octree_flags; null: L = 0). *prev: the
// previous frame's cells (grid integers and points, 4 a cell; empty: it was not an octree frame),
// then this frame's. *cells_left: the cells the block can still hold (2900 a byte less the earlier
// frames'), less this frame's. Throws Error(kCorrupt) through dec.
void decode_octree_frame(IntDecoder* dec, size_t n, uint32_t copies, bool gaps, size_t* cells_left,
                         std::vector<int32_t>* prev, int32_t* q, uint8_t* valid,
                         OctreeMode* mode = nullptr);
// Reads the octree block's flags L (FORMAT.md "The block's flags") for a window with table t.
// Throws Error(kCorrupt) through dec.
OctreeMode read_octree_flags(IntDecoder* dec, const Table& t);

}  // namespace scan

// Encoder side (scan_octree_encode.cpp).
// Whether points [first, first + n) of g can be an octree frame (some valid point, every valid
// point within a cube of side 2^21).
bool octree_frame_ok(const ScanGeometry& g, size_t first, size_t n);
// The octree order of points [first, first + n) of g: its valid points by the Morton key of
// their integers less the frame's least, equal ones together in their order, then its gaps.
// Indices from `first`.
std::vector<uint32_t> octree_frame_order(const ScanGeometry& g, size_t first, size_t n);
// Codes points [first, first + n) of g, in octree_frame_order's order (else throws
// Error(kInternal)), as an octree frame with `copies` copies (0: no counts) and gaps when some
// point is not valid. *prev as decode_octree_frame's.
void encode_octree_frame(const ScanGeometry& g, size_t first, size_t n, uint32_t copies,
                         std::vector<int32_t>* prev, IntEncoder* enc,
                         scan::OctreeMode* mode = nullptr);
// The scan geometry payload of g (FORMAT.md) with every frame that has a valid point an octree
// frame, each frame's points in octree_frame_order's order; empty when a frame is too wide.
// With a table of some rings, the payload carries it and the octree block's flags L = l
// (FORMAT.md "The block's flags"; bit 0 left out for more than kMaxConeRings rings or past the
// cone work's bound, bit 2 without bit 1); without one, L = 0.
std::vector<uint8_t> encode_scan_octree(const ScanGeometry& g, const scan::Table* table = nullptr,
                                        uint32_t l = 0);
// A window of split frames (FORMAT.md "Split frames"; scan_nearfar_encode.cpp). near: one frame
// per window frame, its near part (points in octree_frame_order's order, its gaps last), or no
// point; far[f]: whether window frame f has a far part, a frame of far_payload (a payload of
// encode_scan_geometry or encode_scan_cells, one frame per f with far[f], in order). A frame with
// no valid near point must have far[f] and no near point; one with near points and far[f] is
// split, one without far[f] an octree frame. l: the octree block's L (FORMAT.md "The block's
// flags") when far_payload has a table. Empty when a near part is too wide for an octree, or
// far_payload has a fine shift or octree frames.
std::vector<uint8_t> encode_scan_split(const ScanGeometry& near,
                                       const std::vector<uint8_t>& far_payload,
                                       const std::vector<uint8_t>& far, uint32_t l = 3);
// The table of g's cones (FORMAT.md "The capz encoder"): fit_rings' slopes and offsets, packed
// when smaller; no rings when none are found or more than kMaxConeRings.
scan::Table octree_cone_table(const ScanGeometry& g, const ScanHints& hints);

}  // namespace capz
