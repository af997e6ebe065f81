// Bits per point of an octree code of a sweep's distinct grid cells plus their point counts
// (issue 37, `--point-order any` at 1 cm; docs/lab/2026-11-29-octree-1cm.md). A measuring tool:
// nothing here is a stream format. Each frame is coded intra, on its own.
//
//   scan_octree_bits [--step S] [--frames N] [--occ g6|oct7|oct7c] [--counts octave|nbr|rays]
//                    [--laser] [--dir 1|3] [--bitmodel N] [--dump FILE] [--lib]
//                    [--window [--inter] [--counts-inter]] PATH...
//
// The points are quantised to integers round(x / S) (S = 0.02 m: capz's grid at --max-error
// 1cm); the distinct integer triples are the cells, each with the number of points in it.
// The cells are coded as an octree, level by level from the root, nodes in Morton order, each
// node's 8 child bits one by one (child i = 4 x + 2 y + z of its octant), through capz's own
// range coder and adaptive models (coding/range_coder.h: a SymbolModel started on 2 symbols per
// context); a node's last child is not coded when none before it is occupied. --frames: the
// first N frames of a folder (default 1), each coded on its own.
//
// --occ: the child bit's context (default oct7):
//   g6    the parent's 6 face neighbours at its level (64) x the child's index (8) x the
//         occupied siblings so far (0, 1, 2+) x the level (last, last but one, others);
//   oct7  the 7 parent-level nodes that touch the child's octant (mirrored so every octant
//         shares one map) x the child-level neighbours at -x, -y, -z (always coded before:
//         a sibling with a lower index or a child of a node before in Morton order) x the
//         occupied siblings so far x the level;
//   oct7c oct7 x the count (0, 1, 2+) of the child's other child-level neighbours (edges and
//         corners) earlier in Morton order.
// --counts: the context of each cell's count less one, an unsigned hybrid token
// (coding/entropy.h), cells in Morton order after the tree (default nbr):
//   octave  min(floor(bits(x^2 + y^2 + z^2) / 2), 15) of the cell's integers (as FORMAT.md
//           "Cells with counts");
//   nbr     octave x the mean count of the cell's neighbours coded before it (26-neighbourhood,
//           earlier in Morton order): none, < 1.5, < 2.5, < 4, < 8, 8+;
//   rays    nbr's neighbour class x the rays of the inferred laser table through the cell
//           (--laser only; else as nbr).
// --laser: infer the laser table (coding/scan_table.h, the encoder's own fit) and add to every
// child bit at the last two levels how many rings' cones meet the child's box (0, 1, 2+).
// --dir 1|3: add whether the octant's outward direction points away from the sensor along the
// ray's dominant axis (1) or along each axis (3). --bitmodel N: a counting binary model instead
// of the SymbolModel (BinCoder). --dump FILE: one record of 6 uint32 per coded child bit (the
// bit, level, child, siblings; the parent's 27-neighbourhood; the child-level 27-neighbourhood
// known and occupied; the sensor-side signs and cone class; the depth) for modelling elsewhere.
// --lib: also code each frame through capz's own octree frame coder (coding/scan_octree.h) and
// decode it (its bytes, or a failed round trip). --window: one set of child-bit models over a
// path's frames (as a window codes them); --inter: the previous frame's cells in the child's box
// as one more context bit (FORMAT.md "Octree frames" pv); --counts-inter: the counts in one
// coder over the frames, with the previous frame's count of the cell (0, 1, 2, 3-4, 5-8, 9+)
// as a context.
//
// Prints per sequence: points, cells, bytes of occupancy and counts, bits per point and per cell.
#include <algorithm>
#include <array>
#include <cmath>
#include <cstdio>
#include <map>
#include <memory>
#include <string>
#include <unordered_set>
#include <vector>

#include "coding/entropy.h"
#include "coding/range_coder.h"
#include "coding/scan_geometry.h"
#include "coding/scan_octree.h"
#include "coding/scan_table.h"
#include "scan_frames.h"

namespace {

using scan_tools::Frame;

std::string occ_model = "oct7", counts_model = "nbr";
bool use_laser = false;
bool inter = false;          // --inter: the previous frame's cells as a context bit
bool counts_inter = false;   // --counts-inter: the previous frame's count of the cell too
bool window_models = false;  // --window: one set of models over a path's frames
class BinCoder;
std::vector<BinCoder>* window_coders = nullptr;
std::vector<int64_t> prev_cells;  // the previous frame's cells (grid integers)
bool use_library = false;         // --lib: also the library coder's block (library_bytes)
size_t lib_bytes = 0;
std::FILE* dump_file = nullptr;  // --dump FILE
int dir_bits = 0;  // --dir 1 or 3: the octant against the sensor ray (dominant axis, or all)
size_t level_bytes[3] = {0, 0, 0};  // occupancy bytes: children are cells, next, others

// Morton keys, x the high bit of a child index (coding/scan_octree.h's, as FORMAT.md's).
uint64_t morton(int64_t x, int64_t y, int64_t z) {
  return capz::scan::octree::key(uint64_t(x), uint64_t(y), uint64_t(z));
}
void unmorton(uint64_t k, int64_t* c) {
  capz::scan::octree::coords(k, c);
}

int bit_limit = 0;  // --bitmodel N: counting binary models, rate 1/(n + 2) up to n = N

// Binary decisions through capz's range coder: one SymbolModel on 2 symbols per context, or
// (--bitmodel N) a counting model: p(1) in 1/2^15, moved by (target - p) / (n + 2) after its
// n-th decision, n capped at N (so it learns a sparse context's skew within a few decisions).
class BinCoder {
 public:
  explicit BinCoder(size_t contexts) : m_(contexts), p_(contexts, 1 << 14), n_(contexts, 0) {
    for (auto& s : m_) s.restrict(2);
  }
  void put(bool b, size_t ctx) {
    if (bit_limit == 0) return m_[ctx].encode(&enc_, b ? 1 : 0);
    int p = p_[ctx];
    const uint32_t f1 = uint32_t(std::min(std::max(p, 16), int(capz::kTotal) - 16));
    if (b)
      enc_.encode(capz::kTotal - f1, f1);
    else
      enc_.encode(0, capz::kTotal - f1);
    const int n = n_[ctx];
    p += ((b ? int(capz::kTotal) : 0) - p) / (n + 2);
    p_[ctx] = p;
    if (n < bit_limit) ++n_[ctx];
  }
  size_t bytes() { return enc_.finish().size(); }

 private:
  capz::RangeEncoder enc_;
  std::vector<capz::SymbolModel> m_;
  std::vector<int> p_, n_;
};

// The cells of one frame: integers relative to `lo` (all >= 0), sorted by Morton code.
struct Cells {
  std::vector<uint64_t> key;
  std::vector<uint32_t> count;
  int64_t lo[3] = {0, 0, 0};
  int depth = 0;  // levels below the root: every coordinate < 2^depth
};

Cells make_cells(const std::vector<int64_t>& q) {  // q: n x 3 integers
  Cells c;
  const size_t n = q.size() / 3;
  if (n == 0) return c;
  int64_t hi[3];
  for (int a = 0; a < 3; ++a) c.lo[a] = hi[a] = q[size_t(a)];
  for (size_t i = 0; i < n; ++i)
    for (int a = 0; a < 3; ++a) {
      c.lo[a] = std::min(c.lo[a], q[3 * i + size_t(a)]);
      hi[a] = std::max(hi[a], q[3 * i + size_t(a)]);
    }
  int64_t ext = 1;
  for (int a = 0; a < 3; ++a) ext = std::max(ext, hi[a] - c.lo[a] + 1);
  while ((int64_t{1} << c.depth) < ext) ++c.depth;
  std::vector<uint64_t> k(n);
  for (size_t i = 0; i < n; ++i)
    k[i] = morton(q[3 * i] - c.lo[0], q[3 * i + 1] - c.lo[1], q[3 * i + 2] - c.lo[2]);
  std::sort(k.begin(), k.end());
  for (size_t i = 0; i < n; ++i) {
    if (c.key.empty() || c.key.back() != k[i]) {
      c.key.push_back(k[i]);
      c.count.push_back(0);
    }
    ++c.count.back();
  }
  return c;
}

// The laser cones of an inferred table, in grid units: ring k's points satisfy
// z = z0_k + slope_k * rho (rho the horizontal range), the table's cone.
struct Cones {
  std::vector<double> slope, z0;  // sorted by slope
  double step = 0;                // the azimuth step found in the data (radians), 0: none
};

// Rings whose cone meets the box [a, a + s)^3 (grid integers relative to the sensor, the cell
// at integer v covering [v - 1/2, v + 1/2)): 0, 1 or 2 (2 or more).
int cones_meeting(const Cones& cn, const double* a, double s) {
  if (cn.slope.empty()) return 2;
  // rho range of the box
  double rlo2 = 0, rhi2 = 0;
  for (int d = 0; d < 2; ++d) {
    const double l = a[d] - 0.5, h = a[d] + s - 0.5;
    const double m = (l <= 0 && h >= 0) ? 0 : std::min(std::fabs(l), std::fabs(h));
    const double M = std::max(std::fabs(l), std::fabs(h));
    rlo2 += m * m;
    rhi2 += M * M;
  }
  const double rlo = std::sqrt(rlo2), rhi = std::sqrt(rhi2);
  const double zl = a[2] - 0.5, zh = a[2] + s - 0.5;
  int n = 0;
  for (size_t k = 0; k < cn.slope.size() && n < 2; ++k) {
    const double z1 = cn.z0[k] + cn.slope[k] * rlo, z2 = cn.z0[k] + cn.slope[k] * rhi;
    if (std::max(z1, z2) >= zl && std::min(z1, z2) <= zh) ++n;
  }
  return n;
}

// Rays of the table through a cell: per ring meeting the cell, the azimuth extent of the cell
// at that range over the table's step. Returns a class 0..5.
int ray_class(const Cones& cn, double step, const int64_t* v) {
  const double a[3] = {double(v[0]), double(v[1]), double(v[2])};
  const int m = cones_meeting(cn, a, 1.0);
  const double rho = std::max(0.5, std::hypot(a[0], a[1]));
  const double cols = step > 0 ? (1.0 / rho) / step : 1;  // columns across the cell
  const double rays = m * cols;
  return rays < 0.5 ? 0 : rays < 1.5 ? 1 : rays < 3 ? 2 : rays < 6 ? 3 : rays < 12 ? 4 : 5;
}

struct Level {
  std::vector<uint64_t> key;  // sorted
  std::unordered_set<uint64_t> set;
  bool has(int64_t x, int64_t y, int64_t z, int64_t side) const {
    if (x < 0 || y < 0 || z < 0 || x >= side || y >= side || z >= side) return false;
    return set.count(morton(x, y, z)) != 0;
  }
};

struct Sizes {
  size_t occ = 0, counts = 0;
};

int level_class(int l, int depth) {
  const int below = depth - 1 - l;  // 0: the children are the cells
  return below == 0 ? 0 : below == 1 ? 1 : 2;
}

// The octree's child bits of one frame's cells.
// One child bit's place: its frame's cells and child level, the tree's depth, the parent's
// level l and level class, the parent p and its 27-neighbourhood, the child i and its
// coordinates, the occupied siblings before it.
struct Child {
  const Cells& c;
  const Level& C;
  int D, l, lc, i, coded;
  const int64_t* p;
  const int* nb;
  int64_t cx, cy, cz, cs;  // the child and its level's side
};

// --occ's context of the child bit (g6, oct7, oct7c).
size_t model_context(const Child& k) {
  const int ox = (k.i >> 2) & 1, oy = (k.i >> 1) & 1, oz = k.i & 1;
  const int sib = std::min(k.coded, 2);
  const int* nb = k.nb;
  if (occ_model == "g6") {
    const int f = nb[4] | nb[22] << 1 | nb[10] << 2 | nb[16] << 3 | nb[12] << 4 | nb[14] << 5;
    return ((size_t(f) * 8 + size_t(k.i)) * 3 + size_t(sib)) * 3 + size_t(k.lc);
  }
  // the 7 parent-level nodes touching the octant, mirrored
  const int sx = ox ? 1 : -1, sy = oy ? 1 : -1, sz = oz ? 1 : -1;
  int o7 = 0, b = 0;
  for (int d = 1; d < 8; ++d) {
    const int dx = (d >> 2) & 1, dy = (d >> 1) & 1, dz = d & 1;
    o7 |= nb[(sx * dx + 1) * 9 + (sy * dy + 1) * 3 + sz * dz + 1] << b++;
  }
  const int64_t cx = k.cx, cy = k.cy, cz = k.cz, cs = k.cs;
  int cn = k.C.has(cx - 1, cy, cz, cs) | k.C.has(cx, cy - 1, cz, cs) << 1 |
           k.C.has(cx, cy, cz - 1, cs) << 2;
  if (occ_model == "oct7c") {  // plus the other child-level neighbours coded before
    int n = 0;
    const uint64_t me = morton(cx, cy, cz);
    for (int dx = -1; dx <= 1; ++dx)
      for (int dy = -1; dy <= 1; ++dy)
        for (int dz = -1; dz <= 1; ++dz) {
          if (std::abs(dx) + std::abs(dy) + std::abs(dz) < 2) continue;
          const int64_t x = cx + dx, y = cy + dy, z = cz + dz;
          if (x < 0 || y < 0 || z < 0 || x >= cs || y >= cs || z >= cs) continue;
          const uint64_t key = morton(x, y, z);
          if (key < me && k.C.set.count(key)) ++n;
        }
    cn += 8 * std::min(n, 2);
  }
  return ((size_t(o7) * 24 + size_t(cn)) * 3 + size_t(sib)) * 3 + size_t(k.lc);
}

// Whether the parent's centre is on the positive side of the sensor on each axis.
void sensor_side(const Child& k, double* r) {
  const double side = double(int64_t{1} << (k.D - k.l));  // the parent's side in cells
  for (int d = 0; d < 3; ++d) r[d] = (double(k.p[d]) + 0.5) * side + double(k.c.lo[d]) - 0.5;
}

// The cone class of the child's box (cones_meeting); 2 above the last two levels unless `all`.
int cone_class(const Child& k, const Cones& cones, bool all = false) {
  if (k.lc > 1 && !all) return 2;
  const int64_t side = int64_t{1} << (k.D - k.l - 1);  // the child's side in cells
  const double a[3] = {double(k.cx * side + k.c.lo[0]), double(k.cy * side + k.c.lo[1]),
                       double(k.cz * side + k.c.lo[2])};
  return cones_meeting(cones, a, double(side));
}

// The full context: --occ's, then --dir, --inter and --laser's bits.
size_t child_context(const Child& k, const Cones* cones,
                     const std::vector<std::unordered_set<uint64_t>>& prev) {
  size_t ctx = model_context(k);
  if (dir_bits) {  // the octant's outward directions against the ray from the sensor
    double r[3];
    sensor_side(k, r);
    const int o[3] = {(k.i >> 2) & 1, (k.i >> 1) & 1, k.i & 1};
    if (dir_bits == 1) {
      int d = 0;
      for (int e = 1; e < 3; ++e)
        if (std::fabs(r[e]) > std::fabs(r[d])) d = e;
      ctx = ctx * 2 + size_t(o[d] == (r[d] > 0));
    } else {
      for (int d = 0; d < 3; ++d) ctx = ctx * 2 + size_t(o[d] == (r[d] > 0));
    }
  }
  if (inter) ctx = ctx * 2 + prev[size_t(k.l) + 1].count(morton(k.cx, k.cy, k.cz));
  if (cones) ctx = ctx * 3 + size_t(cone_class(k, *cones));
  return ctx;
}

// --dump: one record of the child bit.
void dump_child(const Child& k, bool bit, const Cones* cones) {
  uint32_t rec[6] = {uint32_t(bit) | uint32_t(k.lc) << 1 | uint32_t(k.i) << 3 |
                         uint32_t(std::min(k.coded, 3)) << 6,
                     0,
                     0,
                     0,
                     0,
                     uint32_t(k.D - k.l)};
  for (int j = 0; j < 27; ++j) rec[1] |= uint32_t(k.nb[j]) << j;
  const uint64_t me = morton(k.cx, k.cy, k.cz);
  int b = 0;
  for (int dx = -1; dx <= 1; ++dx)
    for (int dy = -1; dy <= 1; ++dy)
      for (int dz = -1; dz <= 1; ++dz, ++b) {
        const int64_t x = k.cx + dx, y = k.cy + dy, z = k.cz + dz;
        if (x < 0 || y < 0 || z < 0 || x >= k.cs || y >= k.cs || z >= k.cs) {
          rec[2] |= 1u << b;  // known: outside
          continue;
        }
        const uint64_t key = morton(x, y, z);
        if (key < me) {
          rec[2] |= 1u << b;
          if (k.C.set.count(key)) rec[3] |= 1u << b;
        }
      }
  double r[3];
  sensor_side(k, r);
  for (int d = 0; d < 3; ++d) rec[4] |= uint32_t(r[d] > 0) << d;
  rec[4] |= uint32_t(cones ? cone_class(k, *cones, true) : 2) << 3;
  std::fwrite(rec, sizeof rec, 1, dump_file);
}

// The tree's levels of a frame's cells, root first.
std::vector<Level> make_levels(const Cells& c) {
  std::vector<Level> lv(size_t(c.depth) + 1);
  lv[size_t(c.depth)].key = c.key;
  for (int l = c.depth - 1; l >= 0; --l) {
    auto& k = lv[size_t(l)].key;
    for (uint64_t x : lv[size_t(l) + 1].key)
      if (k.empty() || k.back() != (x >> 3)) k.push_back(x >> 3);
  }
  for (auto& L : lv) L.set.insert(L.key.begin(), L.key.end());
  return lv;
}

// --inter: per child level, the previous frame's cells on that level's grid from this lo.
std::vector<std::unordered_set<uint64_t>> previous_sets(const Cells& c) {
  const int D = c.depth;
  std::vector<std::unordered_set<uint64_t>> prev(size_t(D) + 1);
  for (int L = 1; inter && L <= D; ++L) {
    const int sh = D - L;
    for (size_t j = 0; j + 2 < prev_cells.size(); j += 3) {
      int64_t r[3];
      bool in = true;
      for (int a = 0; a < 3; ++a) {
        r[a] = prev_cells[j + size_t(a)] - c.lo[a];
        in = in && r[a] >= 0 && r[a] < (int64_t{1} << D);
      }
      if (in) prev[size_t(L)].insert(morton(r[0] >> sh, r[1] >> sh, r[2] >> sh));
    }
  }
  return prev;
}

// The octree's child bits of one frame's cells; its bytes (0 with --window: the caller's).
size_t code_occupancy(const Cells& c, const Cones* cones) {
  const int D = c.depth;
  const std::vector<Level> lv = make_levels(c);
  // one coder per level class (its contexts apart anyway): the breakdown by level; with
  // --window the models of the path's frames (window_coders), finished by the caller
  std::vector<BinCoder> own;
  if (!window_coders) own.assign(3, BinCoder(size_t(128) * 64 * 3 * 3 * (cones ? 3 : 1) * 8));
  std::vector<BinCoder>& bcs = window_coders ? *window_coders : own;
  const std::vector<std::unordered_set<uint64_t>> prev = previous_sets(c);
  for (int l = 0; l < D; ++l) {
    const Level& P = lv[size_t(l)];
    const Level& C = lv[size_t(l) + 1];
    const int64_t ps = int64_t{1} << l;
    size_t ci = 0;  // cursor into C.key
    for (uint64_t pk : P.key) {
      int64_t p[3];
      unmorton(pk, p);
      int nb[27];
      for (int dx = -1; dx <= 1; ++dx)
        for (int dy = -1; dy <= 1; ++dy)
          for (int dz = -1; dz <= 1; ++dz)
            nb[(dx + 1) * 9 + (dy + 1) * 3 + dz + 1] = P.has(p[0] + dx, p[1] + dy, p[2] + dz, ps);
      unsigned mask = 0;
      while (ci < C.key.size() && (C.key[ci] >> 3) == pk) mask |= 1u << (C.key[ci++] & 7);
      int coded = 0;
      for (int i = 0; i < 8; ++i) {
        const bool bit = (mask >> i) & 1;
        if (i == 7 && coded == 0) break;  // inferred
        const Child k{c,
                      C,
                      D,
                      l,
                      level_class(l, D),
                      i,
                      coded,
                      p,
                      nb,
                      2 * p[0] + ((i >> 2) & 1),
                      2 * p[1] + ((i >> 1) & 1),
                      2 * p[2] + (i & 1),
                      ps << 1};
        bcs[size_t(k.lc)].put(bit, child_context(k, cones, prev));
        if (dump_file) dump_child(k, bit, cones);
        coded += bit;
      }
    }
  }
  prev_cells.clear();
  for (size_t j = 0; j < c.key.size(); ++j) {
    int64_t v[3];
    unmorton(c.key[j], v);
    for (int a = 0; a < 3; ++a) prev_cells.push_back(v[a] + c.lo[a]);
  }
  if (window_coders) return 0;
  size_t total = 0;
  for (int k = 0; k < 3; ++k) {
    const size_t b = bcs[size_t(k)].bytes();
    level_bytes[k] += b;
    total += b;
  }
  return total;
}

// The cells' counts less one, in Morton order.
// --counts-inter: the previous frame's cells' counts by grid integers (a window's models kept).
std::map<std::array<int64_t, 3>, uint32_t> prev_counts;
std::unique_ptr<capz::IntEncoder> window_counts;

size_t code_counts(const Cells& c, const Cones* cones) {
  capz::IntEncoder own(16 * 6 * 6 * 6);
  capz::IntEncoder& enc = counts_inter ? *window_counts : own;
  std::map<std::array<int64_t, 3>, uint32_t> mine;
  const size_t n = c.key.size();
  for (size_t i = 0; i < n; ++i) {
    int64_t v[3];
    unmorton(c.key[i], v);
    int64_t a[3];
    for (int d = 0; d < 3; ++d) a[d] = v[d] + c.lo[d];
    const uint64_t r2 = uint64_t(a[0] * a[0] + a[1] * a[1] + a[2] * a[2]);
    const int oct = std::min((r2 ? 64 - __builtin_clzll(r2) : 0) / 2, 15);
    int ctx = oct;
    if (counts_model != "octave") {
      uint64_t sum = 0, num = 0;
      for (int dx = -1; dx <= 1; ++dx)
        for (int dy = -1; dy <= 1; ++dy)
          for (int dz = -1; dz <= 1; ++dz) {
            if ((!dx && !dy && !dz) || v[0] + dx < 0 || v[1] + dy < 0 || v[2] + dz < 0) continue;
            const uint64_t k = morton(v[0] + dx, v[1] + dy, v[2] + dz);
            if (k >= c.key[i]) continue;
            auto it = std::lower_bound(c.key.begin(), c.key.begin() + long(i), k);
            if (it != c.key.begin() + long(i) && *it == k) {
              sum += c.count[size_t(it - c.key.begin())];
              ++num;
            }
          }
      const double m = num ? double(sum) / double(num) : -1;
      const int nc = m < 0 ? 0 : m < 1.5 ? 1 : m < 2.5 ? 2 : m < 4 ? 3 : m < 8 ? 4 : 5;
      ctx = oct * 6 + nc;
      if (counts_model == "rays" && cones)
        ctx = 16 * 6 + ray_class(*cones, cones->step, a) * 6 + nc;
    }
    if (counts_inter) {
      mine[{a[0], a[1], a[2]}] = c.count[i];
      const auto it = prev_counts.find({a[0], a[1], a[2]});
      const uint32_t pc = it == prev_counts.end() ? 0 : it->second;
      const int pcl = pc == 0 ? 0 : pc == 1 ? 1 : pc == 2 ? 2 : pc <= 4 ? 3 : pc <= 8 ? 4 : 5;
      ctx = ctx * 6 + pcl;
    }
    enc.put(c.count[i] - 1, ctx);
  }
  if (counts_inter) {
    prev_counts.swap(mine);
    return 0;
  }
  return enc.finish().size();
}

// --lib: the frame through capz's own octree frame coder (coding/scan_octree.h, FORMAT.md
// "Octree frames") in octree order, decoded again; the block's bytes, or 0 when the round trip
// is not exact.
size_t library_bytes(const std::vector<int64_t>& q) {
  capz::ScanGeometry g;
  const size_t n = q.size() / 3;
  g.counts.push_back(uint32_t(n));
  g.valid.assign(n, 1);
  for (int64_t v : q) g.q.push_back(int32_t(v));
  const std::vector<uint32_t> order = capz::octree_frame_order(g, 0, n);
  capz::ScanGeometry s = g;
  for (size_t j = 0; j < n; ++j)
    for (int a = 0; a < 3; ++a) s.q[3 * j + size_t(a)] = g.q[3 * order[j] + size_t(a)];
  uint32_t copies = 0;
  for (size_t j = 1; j < n; ++j)
    copies += std::equal(&s.q[3 * j], &s.q[3 * j] + 3, &s.q[3 * j - 3]);
  capz::IntEncoder enc(capz::scan::kOctreeContexts);
  capz::scan::start_octree_block(&enc);
  std::vector<int32_t> prev;
  capz::encode_octree_frame(s, 0, n, copies, &prev, &enc);
  const std::vector<uint8_t> block = enc.finish();
  capz::IntDecoder dec(block.data(), block.size(), capz::scan::kOctreeContexts, "octree");
  capz::scan::start_octree_block(&dec);
  std::vector<int32_t> back(3 * n);
  std::vector<uint8_t> valid(n);
  prev.clear();
  size_t cells_left = capz::kMaxSymbolsPerByte * block.size();
  capz::scan::decode_octree_frame(&dec, n, copies, false, &cells_left, &prev, back.data(),
                                  valid.data());
  return back == s.q && dec.at_end() ? block.size() : 0;
}

Cones cones_of(const Frame& fr, double step) {
  capz::ScanGeometry g;
  capz::ScanHints h;
  const size_t n = fr.xyz.size() / 3;
  g.counts.push_back(uint32_t(n));
  for (size_t i = 0; i < n; ++i) {
    const double* x = &fr.xyz[3 * i];
    const bool ok = std::isfinite(x[0]) && std::isfinite(x[1]) && std::isfinite(x[2]);
    g.valid.push_back(ok);
    for (int k = 0; k < 3; ++k) {
      h.xyz.push_back(float(x[k]));
      g.q.push_back(ok ? int32_t(std::floor(x[k] / step + 0.5)) : 0);
    }
  }
  h.ring = fr.ring;
  h.grid_per_unit = 1.0 / step;
  const capz::scan::RingFit r = capz::scan::fit_rings(g, h, false);
  Cones c;
  c.step = r.step;
  std::vector<size_t> idx(r.rings());
  for (size_t k = 0; k < idx.size(); ++k) idx[k] = k;
  std::sort(idx.begin(), idx.end(), [&](size_t a, size_t b) { return r.slope[a] < r.slope[b]; });
  for (size_t k : idx) {
    c.slope.push_back(r.slope[k]);
    c.z0.push_back(r.z0[k]);
  }
  return c;
}

}  // namespace

// One line of the table: the first `frames` frames of path p on the grid of `step`.
void measure_path(const std::string& p, double step, size_t frames) {
  std::vector<std::string> files = scan_tools::list_frames(p);
  if (files.size() > frames) files.resize(frames);
  size_t points = 0, cells = 0;
  Sizes s;
  for (size_t& b : level_bytes) b = 0;
  lib_bytes = 0;
  prev_cells.clear();
  prev_counts.clear();
  window_counts.reset(new capz::IntEncoder(16 * 6 * 6 * 6));
  std::vector<BinCoder> path_coders;
  if (window_models) {
    path_coders.assign(3, BinCoder(size_t(128) * 64 * 3 * 3 * 3 * 8));
    window_coders = &path_coders;
  }
  for (const std::string& f : files) {
    const Frame fr = scan_tools::read_frame(f, true);
    std::vector<int64_t> q;
    for (size_t i = 0; i < fr.xyz.size() / 3; ++i) {
      const double* x = &fr.xyz[3 * i];
      if (!std::isfinite(x[0]) || !std::isfinite(x[1]) || !std::isfinite(x[2])) continue;
      for (int k = 0; k < 3; ++k) q.push_back(int64_t(std::floor(x[k] / step + 0.5)));
    }
    const Cells c = make_cells(q);
    Cones cones;
    if (use_laser) cones = cones_of(fr, step);
    points += q.size() / 3;
    cells += c.key.size();
    s.occ += code_occupancy(c, use_laser ? &cones : nullptr);
    s.counts += code_counts(c, use_laser ? &cones : nullptr);
    if (use_library) lib_bytes += library_bytes(q);
  }
  if (window_models) {
    for (int k = 0; k < 3; ++k) {
      const size_t b = path_coders[size_t(k)].bytes();
      level_bytes[k] += b;
      s.occ += b;
    }
    window_coders = nullptr;
  }
  if (counts_inter) s.counts += window_counts->finish().size();
  std::string name = p;
  while (!name.empty() && name.back() == '/') name.pop_back();
  name = name.substr(name.find_last_of('/') + 1);
  std::printf("%-24s %8zu %8zu %8zu %8zu %8.3f %8.3f %8.3f  %zu %zu %zu\n", name.c_str(), points,
              cells, s.occ, s.counts, 8.0 * double(s.occ + s.counts) / double(points),
              8.0 * double(s.occ) / double(cells), 8.0 * double(s.counts) / double(cells),
              level_bytes[0], level_bytes[1], level_bytes[2]);
  if (use_library)
    std::printf("%-24s library octree frames: %zu bytes, %.3f bits/pt%s\n", name.c_str(), lib_bytes,
                8.0 * double(lib_bytes) / double(points),
                lib_bytes ? "" : " (ROUND TRIP NOT EXACT)");
}

int main(int argc, char** argv) {
  double step = 0.02;
  size_t frames = 1;
  std::vector<std::string> paths;
  for (int i = 1; i < argc; ++i) {
    const std::string a = argv[i];
    if (a == "--step" && i + 1 < argc) {
      step = std::atof(argv[++i]);
    } else if (a == "--frames" && i + 1 < argc) {
      frames = size_t(std::atol(argv[++i]));
    } else if (a == "--occ" && i + 1 < argc) {
      occ_model = argv[++i];
    } else if (a == "--counts" && i + 1 < argc) {
      counts_model = argv[++i];
    } else if (a == "--bitmodel" && i + 1 < argc) {
      bit_limit = std::atoi(argv[++i]);
    } else if (a == "--dir" && i + 1 < argc) {
      dir_bits = std::atoi(argv[++i]);
    } else if (a == "--dump" && i + 1 < argc) {
      dump_file = std::fopen(argv[++i], "wb");
    } else if (a == "--lib") {
      use_library = true;
    } else if (a == "--counts-inter") {
      counts_inter = true;
    } else if (a == "--inter") {
      inter = true;
    } else if (a == "--window") {
      window_models = true;
    } else if (a == "--laser") {
      use_laser = true;
    } else {
      paths.push_back(a);
    }
  }
  std::printf("%-24s %8s %8s %8s %8s %8s %8s %8s  %s\n", "sequence", "points", "cells", "occ_B",
              "cnt_B", "bits/pt", "occ/cell", "cnt/cell", "occ_B by level (last, next, rest)");
  for (const std::string& p : paths) measure_path(p, step, frames);
  return 0;
}
