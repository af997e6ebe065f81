// Octree frames' mix (docs/FORMAT.md "Octree frames", "Mixing", L bit 2): squash and stretch
// against the spec's numbers, the mixer against the spec's arithmetic written out here on its
// own, the walk's side contexts and weight sets against lookups of the tree's coordinates, and
// damaged mixed payloads.
#include <gtest/gtest.h>

#include <algorithm>
#include <array>
#include <cmath>
#include <cstdint>
#include <cstdio>
#include <random>

#include "capz/error.h"
#include "coding/scan_octree.h"
#include "coding/scan_shared.h"
#include "scan_geometry_expect.h"

namespace capz {
namespace {

using scan::OctreeMixer;
namespace mix = scan::mix;

TEST(ScanOctreeMix, GivenTheSpecsTableThenSquashAndStretchAreItsNumbers) {
  EXPECT_EQ(mix::squash(0), 2047);
  EXPECT_EQ(mix::squash(-1), 2043);   // (1546 + 2047 * 127 + 64) / 128
  EXPECT_EQ(mix::squash(1), 2051);    // (2047 * 127 + 2549 + 64) / 128
  EXPECT_EQ(mix::squash(100), 2439);  // (2047 * 28 + 2549 * 100 + 64) / 128
  EXPECT_EQ(mix::squash(-2047), 1);
  EXPECT_EQ(mix::squash(2047), 4094);
  EXPECT_EQ(mix::squash(-5000), 1);  // clamped
  EXPECT_EQ(mix::squash(5000), 4094);
  for (int d = -2047; d < 2047; ++d) ASSERT_LE(mix::squash(d), mix::squash(d + 1)) << d;
  // stretch(v): the least d with squash(d) >= v, 2047 when none
  EXPECT_EQ(mix::stretch(0), -2047);
  EXPECT_EQ(mix::stretch(2047), 0);
  EXPECT_EQ(mix::stretch(2048), 1);
  EXPECT_EQ(mix::stretch(4095), 2047);
  for (int v = 0; v < 4096; ++v) {
    int d = -2047;
    while (d < 2047 && mix::squash(d) < v) ++d;
    ASSERT_EQ(mix::stretch(v), d) << v;
  }
}

// FORMAT.md "Mixing" as written: three weight sets of 4 per bit, summed, the inputs the
// stretched counting models, then the steps, the weights wrapping modulo 2^32.
struct SpecMix {
  std::vector<std::array<int64_t, 4>> w =
      std::vector<std::array<int64_t, 4>>(555, {65536, 0, 0, 0});
  std::vector<int64_t> p1 = std::vector<int64_t>(24576, 16384), n1 = std::vector<int64_t>(24576, 0);
  std::vector<int64_t> p2 = std::vector<int64_t>(3456, 16384), n2 = std::vector<int64_t>(3456, 0);
  int64_t x[4] = {};
  int64_t p = 0;
  size_t set[3] = {};
  size_t s1 = 0, s2 = 0;
  int64_t f(int64_t own, const int* side, const int* sets) {
    s1 = static_cast<size_t>(side[0]), s2 = static_cast<size_t>(side[1]);
    set[0] = static_cast<size_t>(sets[0]);
    set[1] = static_cast<size_t>(27 + sets[1]);
    set[2] = static_cast<size_t>(219 + sets[2]);
    x[0] = mix::stretch(static_cast<int>(own / 8));
    x[1] = mix::stretch(static_cast<int>(p1[s1] / 8));
    x[2] = mix::stretch(static_cast<int>(p2[s2] / 8));
    x[3] = 256;
    int64_t t = 0;
    for (int k = 0; k < 4; ++k) t += (w[set[0]][k] + w[set[1]][k] + w[set[2]][k]) * x[k];
    p = mix::squash(static_cast<int>(t / 196608));
    return std::min<int64_t>(std::max<int64_t>(8 * p, 16), 32768 - 16);
  }
  static void count(int64_t* pp, int64_t* n, int b) {
    *pp += (32768 * b - *pp) / (*n + 2);
    *n = std::min<int64_t>(*n + 1, 62);
  }
  void update(int b) {
    const int64_t err = (4096 * b - p) * 120;
    for (int k = 0; k < 4; ++k)
      for (size_t s : set) {  // modulo 2^32, two's complement
        const int64_t v = (w[s][k] + x[k] * err / 65536) & 0xFFFFFFFF;
        w[s][k] = v >= (int64_t{1} << 31) ? v - (int64_t{1} << 32) : v;
      }
    count(&p1[s1], &n1[s1], b);
    count(&p2[s2], &n2[s2], b);
  }
};

TEST(ScanOctreeMix, GivenAWeightPastInt32ThenItWrapsAsTwosComplement) {
  EXPECT_EQ(mix::wrapped(5, -7), -2);
  EXPECT_EQ(mix::wrapped(INT32_MAX, 1), INT32_MIN);
  EXPECT_EQ(mix::wrapped(INT32_MIN, -1), INT32_MAX);
  EXPECT_EQ(mix::wrapped(INT32_MAX - 10, 15351), INT32_MIN + 15340);
  EXPECT_EQ(mix::wrapped(-65536, -15351), -80887);
}

TEST(ScanOctreeMix, GivenTheFirstBitThenItsProbabilityIsTheHandWorkedOne) {
  OctreeMixer m;
  const int side[2] = {0, 0}, sets[3] = {0, 0, 0};
  m.set(side, sets);
  // every model at 2^14: x = stretch(2048) = 1, the bias 256; W = (3 * 65536, 0, 0, 0):
  // p = squash(196608 / 196608) = 2051, F = 8 p
  EXPECT_EQ(m.one(16384), 16408u);
}

// Random contexts and bits, first skewed by context (the weights learn), then each bit the one
// the mix finds less likely, then a weight run far (past 2^22) and back: the mixer's frequencies
// are the spec's at every bit. Fails if any step of the arithmetic changes.
TEST(ScanOctreeMix, GivenBitsThenTheMixersFrequenciesAreTheSpecsArithmetic) {
  std::mt19937 rng(23);
  OctreeMixer m;
  SpecMix spec;
  std::vector<int64_t> own(64, 16384), own_n(64, 0);  // the context's own counting models
  uint32_t far = 0;
  for (int j = 0; j < 60000; ++j) {
    const int c = static_cast<int>(rng() % 64);
    const int side[2] = {static_cast<int>(rng() % 24576) / (j < 30000 ? 512 : 1),
                         static_cast<int>(rng() % 3456) / 64};
    const int sets[3] = {static_cast<int>(rng() % 27), static_cast<int>(rng() % 192) / 8,
                         static_cast<int>(rng() % 336)};
    m.set(side, sets);
    const uint32_t f = m.one(static_cast<uint32_t>(own[static_cast<size_t>(c)]));
    ASSERT_EQ(int64_t{f}, spec.f(own[static_cast<size_t>(c)], side, sets)) << j;
    const int b = j < 30000 ? static_cast<int>(rng() % 8 < static_cast<uint32_t>(c % 8))
                            : static_cast<int>(f < 16384);
    m.update(b != 0);
    spec.update(b);
    SpecMix::count(&own[static_cast<size_t>(c)], &own_n[static_cast<size_t>(c)], b);
  }
  // The context's model sure of the bit the stream does not give, both ways in turn: the mix
  // stays within 1 of 4096 of it, so its weight keeps moving the same way, far.
  const int side[2] = {7, 7}, sets[3] = {5, 5, 5};
  for (int j = 0; j < 1500000; ++j) {
    const int b = j % 2;
    const int64_t p = b ? 0 : 32767;
    m.set(side, sets);
    ASSERT_EQ(int64_t{m.one(static_cast<uint32_t>(p))}, spec.f(p, side, sets)) << j;
    m.update(b != 0);
    spec.update(b);
  }
  for (const auto& w : spec.w)
    for (int64_t v : w) far += v > (1 << 22) || v < -(1 << 22);
  EXPECT_GT(far, 0u);
  // Then the bits the model is sure of: the weight comes back, at the spec's pace.
  for (int j = 0; j < 3000; ++j) {
    m.set(side, sets);
    ASSERT_EQ(int64_t{m.one(32767)}, spec.f(32767, side, sets)) << j;
    m.update(true);
    spec.update(1);
  }
  EXPECT_GT(spec.p, 4000);
}

// A recording walk: each coded child bit's context, level and key, the actual tree's bit.
struct Io {
  std::vector<std::vector<uint64_t>> levels;
  std::vector<int> ctx, lv;
  std::vector<uint64_t> key;
  bool bit(int c, int l, uint64_t k) {
    ctx.push_back(c), lv.push_back(l), key.push_back(k);
    const std::vector<uint64_t>& n = levels[static_cast<size_t>(l) + 1];
    return std::binary_search(n.begin(), n.end(), k);
  }
  [[noreturn]] void too_many() { throw Error(ErrorCode::kInternal, "too many"); }
  [[noreturn]] void too_much() { throw Error(ErrorCode::kInternal, "too much"); }
};
// What the walk asks of the mix.
struct Recorded {
  std::vector<std::array<int, 5>> got;
  void set(const int* side, const int* sets) {
    got.push_back({side[0], side[1], sets[0], sets[1], sets[2]});
  }
};

// The walk's side contexts and weight sets against FORMAT.md "Mixing" worked out from the
// coordinates: q from the level's nodes with a lower key (coded before), a from the corner and
// the parent, the rest from the bit's context (r = 2, no cones), on random trees of random
// corners (the origin inside, outside, on a face).
TEST(ScanOctreeMix, GivenRandomTreesThenTheWalksMixInputsAreTheSpecs) {
  std::mt19937 rng(41);
  size_t asked = 0;
  for (int t = 0; t < 10; ++t) {
    const int d = 3 + t % 4;
    const int64_t side = int64_t{1} << d;
    const int64_t lo[3] = {-side / 2 - t, t % 3 == 0 ? 0 : 5, -(side << (t % 2)) / 3};
    std::vector<uint64_t> cells;
    std::uniform_int_distribution<int64_t> u(0, side - 1);
    for (int j = 0; j < (20 << (t % 4)); ++j) {
      int64_t v[3] = {u(rng), u(rng), u(rng)};
      if (j % 2) v[2] = (v[0] + v[1] / 2) % side;  // a slanted plane: neighbours
      cells.push_back(scan::octree::key(uint64_t(v[0]), uint64_t(v[1]), uint64_t(v[2])));
    }
    std::sort(cells.begin(), cells.end());
    cells.erase(std::unique(cells.begin(), cells.end()), cells.end());
    Io io;
    io.levels.resize(static_cast<size_t>(d) + 1);
    io.levels.back() = cells;
    for (int l = d - 1; l >= 0; --l)
      for (uint64_t k : io.levels[size_t(l) + 1])
        if (io.levels[size_t(l)].empty() || io.levels[size_t(l)].back() != k >> 3)
          io.levels[size_t(l)].push_back(k >> 3);
    Recorded mx;
    ASSERT_EQ(scan::octree::code_tree(io, d, cells.size(), lo, {}, nullptr, &mx), cells);
    ASSERT_EQ(mx.got.size(), io.ctx.size());
    for (size_t j = 0; j < io.ctx.size(); ++j) {
      const int l = io.lv[j];
      const uint64_t ck = io.key[j];
      const int i = static_cast<int>(ck & 7);
      int64_t c[3], p[3];
      scan::octree::coords(ck, c);
      scan::octree::coords(ck >> 3, p);
      const std::vector<uint64_t>& below = io.levels[size_t(l) + 1];
      int q = 0, k = 0;
      for (int dx = -1; dx <= 0; ++dx)
        for (int dy = -1; dy <= 1; ++dy)
          for (int dz = -1; dz <= 1; ++dz) {
            if (dx == 0 && (dy > 0 || (dy == 0 && dz >= 0))) continue;
            const int64_t e[3] = {c[0] + dx, c[1] + dy, c[2] + dz};
            const int64_t s = int64_t{2} << l;
            bool node = false;
            if (e[0] >= 0 && e[1] >= 0 && e[2] >= 0 && e[0] < s && e[1] < s && e[2] < s) {
              const uint64_t ek = scan::octree::key(uint64_t(e[0]), uint64_t(e[1]), uint64_t(e[2]));
              node = ek < ck && std::binary_search(below.begin(), below.end(), ek);
            }
            q |= int{node} << k++;
          }
      ASSERT_EQ(k, 13);
      int a = 0;
      for (int x = 0; x < 3; ++x) {
        const int64_t sp = int64_t{1} << (d - l);
        const int h = 2 * (lo[x] + sp * p[x]) + sp > 0;
        a = 2 * a + (((i >> (2 - x)) & 1) == h);
      }
      // the bit's context 578 + 2 (((o7 8 + cn) 3 + sib) 3 + lc) + pv, r = 2
      const int v = (io.ctx[j] - scan::kOctBitCtx) / 2, pv = (io.ctx[j] - scan::kOctBitCtx) % 2;
      const int lc = v % 3, sib = (v / 3) % 3, cn = (v / 9) % 8, o7 = v / 72;
      ASSERT_EQ(lc, l == d - 1 ? 0 : l == d - 2 ? 1 : 2);
      const std::array<int, 5> want = {
          q * 3 + lc, ((((2 * 8 + a) * 8 + i) * 3 + lc) * 3 + sib) * 2 + pv, (lc * 3 + sib) * 3 + 2,
          (__builtin_popcount(unsigned(o7)) * 8 + cn) * 3 + lc,
          (__builtin_popcount(unsigned(q)) * 8 + i) * 3 + lc};
      ASSERT_EQ(mx.got[j], want) << "tree " << t << " bit " << j << " level " << l;
      ++asked;
    }
  }
  EXPECT_GT(asked, 3000u);
}

// A window of two sweeps of a wall at about a metre under a table of 16 rings, in octree order.
ScanGeometry wall(scan::Table* t) {
  std::mt19937 rng(9);
  std::uniform_real_distribution<double> u(0, 1);
  t->step = 1;
  t->columns = 1;
  ScanGeometry g;
  for (int k = 0; k < 16; ++k) {
    t->azimuth0.push_back(0.0f);
    t->slope.push_back(static_cast<float>(std::tan(-0.3 + 0.04 * k)));
    t->z0.push_back(0.0f);
  }
  for (int f = 0; f < 2; ++f) {
    ScanGeometry one;
    for (int c = 0; c < 400; ++c)
      for (int k = 0; k < 16; ++k) {
        const double az = 0.0157 * c, el = -0.3 + 0.04 * k;
        const double range = 1.0 + 0.2 * std::sin(2 * az) + 0.003 * u(rng);
        const double p[3] = {range * std::cos(el) * std::cos(az),
                             range * std::cos(el) * std::sin(az), range * std::sin(el)};
        one.valid.push_back(u(rng) > 0.02);
        for (double v : p)
          one.q.push_back(one.valid.back() ? static_cast<int32_t>(std::floor(v / 0.02 + 0.5)) : 0);
      }
    for (uint32_t j : octree_frame_order(one, 0, one.valid.size())) {
      g.valid.push_back(one.valid[j]);
      g.q.insert(g.q.end(), &one.q[3 * j], &one.q[3 * j] + 3);
    }
    g.counts.push_back(static_cast<uint32_t>(one.valid.size()));
  }
  return g;
}

// A mixed payload comes back exactly, and each of 300 cuts or bit flips of it is corrupt or
// decodes within its point limit (never another error).
TEST(ScanOctreeMix, GivenAMixedPayloadThenItComesBackAndItsDamageIsCorrupt) {
  scan::Table t;
  const ScanGeometry g = wall(&t);
  const std::vector<uint8_t> mixed = encode_scan_octree(g, &t, 7),
                             plain = encode_scan_octree(g, &t, 3);
  const scan::Header h = scan::read_header(mixed.data(), mixed.size(), "mix", SIZE_MAX);
  ASSERT_GT(h.octree_size, 0u);
  const ScanGeometry d = decode_scan_geometry(mixed.data(), mixed.size(), "mix");
  EXPECT_EQ(d.q, g.q);
  EXPECT_EQ(d.valid, g.valid);
  EXPECT_NE(mixed, plain);
  std::printf("wall window: %zu B with L = 3, %zu B with L = 7\n", plain.size(), mixed.size());
  std::mt19937 rng(3);
  size_t corrupt = 0;
  for (int j = 0; j < 300; ++j) {
    std::vector<uint8_t> bad = mixed;
    const size_t at = h.octree + rng() % h.octree_size;
    if (j % 3 == 0)
      bad.resize(at);
    else
      bad[at] ^= static_cast<uint8_t>(1u << (rng() % 8));
    try {
      const ScanGeometry x = decode_scan_geometry(bad.data(), bad.size(), "mix");
      EXPECT_EQ(x.valid.size(), g.valid.size());
    } catch (const Error& e) {
      ASSERT_EQ(e.code(), ErrorCode::kCorrupt) << e.what();
      ++corrupt;
    }
  }
  EXPECT_GT(corrupt, 100u);
}

}  // namespace
}  // namespace capz
