// Octree frames' mixed child bits (docs/FORMAT.md "Octree frames", L bit 2): the counting model
// of the child bit's context and two more counting models on other contexts, mixed by an
// integer logistic mixer. Everything here is integer arithmetic, the same on every build.
#pragma once

#include <algorithm>
#include <array>
#include <cstddef>
#include <cstdint>
#include <vector>

namespace capz {
namespace scan {

namespace mix {

// squash(d) = 4096 / (1 + e^(-d / 256)) for d in [-2047, 2047], by linear interpolation of 33
// points 128 apart (rounded), 0..4095 (FORMAT.md "Mixing").
inline int squash(int d) {
  static constexpr int kT[33] = {1,    2,    3,    6,    10,   16,   27,   45,   73,   120,  194,
                                 310,  488,  747,  1101, 1546, 2047, 2549, 2994, 3348, 3607, 3785,
                                 3901, 3975, 4022, 4050, 4068, 4079, 4085, 4089, 4092, 4093, 4094};
  if (d > 2047) d = 2047;
  if (d < -2047) d = -2047;
  const int u = d + 2048, w = u & 127, j = u >> 7;
  return (kT[j] * (128 - w) + kT[j + 1] * w + 64) >> 7;
}

// w + step modulo 2^32, as a two's-complement int32 (the weights' sum: FORMAT.md "Mixing").
// Without a bound on the weights a hostile block could take them past int32; the sum wraps
// instead, the same on every build (no signed overflow, no implementation-defined conversion).
inline int32_t wrapped(int32_t w, int32_t step) {
  const uint32_t u = static_cast<uint32_t>(w) + static_cast<uint32_t>(step);
  return u < 0x80000000u ? static_cast<int32_t>(u) : -static_cast<int32_t>(~u) - 1;
}

// stretch(p), p 0..4095: the least d in [-2047, 2047] with squash(d) >= p (2047 when none).
struct Stretch {
  int16_t t[4096] = {};
  Stretch() {
    int d = -2047;
    for (int p = 0; p < 4096; ++p) {
      while (d < 2047 && squash(d) < p) ++d;
      t[p] = static_cast<int16_t>(d);
    }
  }
};
inline const Stretch kStretch;
inline int stretch(int p) {
  return kStretch.t[p];
}

}  // namespace mix

namespace octree {

// The bits 1 of 0..255.
constexpr struct Ones {
  int n[256] = {};
  constexpr Ones() {
    for (int v = 0; v < 256; ++v) n[v] = (v & 1) + n[v >> 1];
  }
  int operator[](int v) const { return n[v]; }
} kOnes;

// The children coded so far around a node (km: parent_neighbours', and its own children so far)
// as the bits 16 x + 4 y + z of a 4 x 4 x 4 block at the child level, x y z from one below the
// node's first child: a neighbour's child bits by half a mask at a time (kBlock).
struct Block {
  uint64_t t[27][2][16] = {};
  Block() {
    for (int e = 0; e < 27; ++e)
      for (int h = 0; h < 2; ++h)
        for (int m = 0; m < 16; ++m)
          for (int b = 0; b < 4; ++b) {
            if (!((m >> b) & 1)) continue;
            const int j = 4 * h + b, d[3] = {e / 9 - 1, (e / 3) % 3 - 1, e % 3 - 1};
            int at = 0;
            bool in = true;
            for (int a = 0; a < 3; ++a) {
              const int g = 2 * d[a] + ((j >> (2 - a)) & 1) + 1;
              in = in && g >= 0 && g < 4;
              at = at * 4 + g;
            }
            if (in) t[e][h][m] |= uint64_t{1} << at;
          }
  }
};
inline const Block kBlock;

// The block of the node whose parent_neighbours' km this is, before its children.
inline uint64_t child_block(const int* km) {
  uint64_t b = 0;
  for (int e = 0; e < 27; ++e)
    if (km[e]) b |= kBlock.t[e][1][km[e] >> 4] | kBlock.t[e][0][km[e] & 15];
  return b;
}
// Child i's place in the block.
inline int block_at(int i) {
  return 16 * (1 + (i >> 2)) + 4 * (1 + ((i >> 1) & 1)) + 1 + (i & 1);
}

// Q of child i's 13 backward neighbours e (dx < 0; or dx = 0, dy < 0; or dx = dy = 0, dz < 0),
// bit k for the k-th in order of x, then y, then z, from the block so far.
inline int backward_pattern(uint64_t block, int i) {
  const int b = block_at(i) - 21;  // (-1, -1, -1) from the child
  return static_cast<int>((block >> b & 7) | (block >> (b + 4) & 7) << 3 |
                          (block >> (b + 8) & 7) << 6 | (block >> (b + 16) & 7) << 9 |
                          (block >> (b + 20) & 1) << 12);
}

// The mix's inputs (FORMAT.md "Mixing") in the walk: at each parent the block of the children
// coded around it and the sides of its centre, at each coded child bit the side contexts and
// weight sets (given the bit's context parts).
class MixWalk {
 public:
  // Before the children of the parent at p (level l of a tree of depth d and corner lo), km its
  // neighbours' child bits (parent_neighbours').
  void start_parent(const int* km, const int64_t* lo, const int64_t* p, int l, int d) {
    block_ = child_block(km);
    sign_ = 0;
    for (int a = 0; a < 3; ++a)  // whether the parent's centre is above the origin on axis a
      sign_ = sign_ * 2 + (2 * (lo[a] + (p[a] << (d - l))) + (int64_t{1} << (d - l)) > 0);
  }
  // Sets mx's inputs for child i's bit, of context parts o7 cn sib lc pv r.
  template <class Mix>
  void child(Mix* mx, int i, int o7, int cn, int sib, int lc, int pv, int r) const {
    const int away = 7 & ~(i ^ sign_);  // per axis: the child's half is the one away from 0
    const int q = backward_pattern(block_, i);
    const int side[2] = {q * 3 + lc, ((((r * 8 + away) * 8 + i) * 3 + lc) * 3 + sib) * 2 + pv};
    const int sets[3] = {(lc * 3 + sib) * 3 + r, (kOnes[o7] * 8 + cn) * 3 + lc,
                         ((kOnes[q & 255] + kOnes[q >> 8]) * 8 + i) * 3 + lc};
    mx->set(side, sets);
  }
  // Child i is a node.
  void keep_child(int i) { block_ |= uint64_t{1} << block_at(i); }

 private:
  uint64_t block_ = 0;
  int sign_ = 0;
};

}  // namespace octree

// The mixer of one octree block (FORMAT.md "Octree frames", step 4 with L bit 2): the side
// models' state and the weights (int32, wrapping), and the inputs of the bit being coded (set() by
// the walk before each mixed bit, then one() and update()).
class OctreeMixer {
 public:
  // The inputs: the context's own model, the side models, a bias.
  static constexpr int kSides = 2, kInputs = kSides + 2;
  static constexpr int kSide[kSides] = {8192 * 3, 3 * 8 * 8 * 3 * 3 * 2};
  // The weight sets: three sets of kInputs weights each, one of each chosen per bit.
  static constexpr int kSets = 27 + 192 + 336, kSetAt[3] = {0, 27, 27 + 192};
  static constexpr int kRate = 120;  // weights of 2^16 move by st err rate / 2^16
  OctreeMixer() : w_(static_cast<size_t>(kSets)) {
    for (int k = 0; k < kSides; ++k) {
      p_[k].assign(static_cast<size_t>(kSide[k]), 1 << 14);
      n_[k].assign(static_cast<size_t>(kSide[k]), 0);
    }
    for (Weights& w : w_) w = {{1 << 16, 0, 0, 0}};
  }
  // The side contexts and the weight sets (each within its own count) of the next bit.
  void set(const int* side, const int* sets) {
    for (int k = 0; k < kSides; ++k) s_[k] = static_cast<size_t>(side[k]);
    for (int k = 0; k < 3; ++k) ws_[k] = static_cast<size_t>(kSetAt[k] + sets[k]);
  }
  // The frequency of a 1 (of 2^15) from the context's own model P (of 2^15, below 2^15).
  uint32_t one(uint32_t p) {
    st_[0] = mix::stretch(static_cast<int>(p >> 3));
    for (int k = 0; k < kSides; ++k) st_[k + 1] = mix::stretch(p_[k][s_[k]] >> 3);
    st_[kInputs - 1] = 256;
    const Weights &a = w_[ws_[0]], &b = w_[ws_[1]], &c = w_[ws_[2]];
    int64_t t = 0;  // the three sets' dot products
    for (size_t k = 0; k < kInputs; ++k) t += (int64_t{a[k]} + b[k] + c[k]) * st_[k];
    pr_ = mix::squash(static_cast<int>(t / (3 * 65536)));
    const uint32_t f = static_cast<uint32_t>(pr_) << 3;
    return f < 16 ? 16 : f > 32752 ? 32752 : f;
  }
  // After bit b.
  void update(bool b) {
    const int err = ((b ? 4096 : 0) - pr_) * kRate;
    for (size_t k = 0; k < kInputs; ++k) {
      const int32_t step = st_[k] * err / 65536;  // the same for the three sets
      for (size_t set : ws_) w_[set][k] = mix::wrapped(w_[set][k], step);
    }
    for (int k = 0; k < kSides; ++k) {
      uint16_t& p = p_[k][s_[k]];
      uint8_t& n = n_[k][s_[k]];
      p = static_cast<uint16_t>(p + ((b ? 32768 : 0) - p) / (n + 2));
      if (n < 62) ++n;
    }
  }

 private:
  using Weights = std::array<int32_t, kInputs>;
  std::vector<uint16_t> p_[kSides];  // the side models' P and N, as the context's own
  std::vector<uint8_t> n_[kSides];
  std::vector<Weights> w_;
  size_t s_[kSides] = {}, ws_[3] = {};
  int st_[kInputs] = {};
  int pr_ = 2048;
};

}  // namespace scan
}  // namespace capz
