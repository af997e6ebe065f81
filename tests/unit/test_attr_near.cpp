// ATTR predictors 10 and 11 (FORMAT.md 13.5): the nearest earlier point of each point (the rule
// of coding/neighbours.h: first valid frame, exact distances, ties to the larger index, the
// 512-point window above 4096 points), round trips of integer, float and colour lanes that use
// them, and what a decoder refuses (a 6.x stream, no position integers).
#include <gtest/gtest.h>

#include <algorithm>
#include <cstring>
#include <numeric>
#include <random>
#include <string>
#include <vector>

#include "capz/codec.h"
#include "capz/error.h"
#include "capz/take.h"
#include "coding/attributes.h"
#include "coding/bytes.h"
#include "coding/neighbours.h"
#include "support/stream_pieces.h"
#include "test_util.h"

using capz::AttrSpec;
using capz::ErrorCode;
using capz::kNoPoint;

namespace {

std::vector<uint32_t> nearest(const std::vector<int32_t>& q, const std::vector<uint8_t>& valid,
                              size_t frames, size_t points) {
  return capz::nearest_earlier(q.data(), valid.data(), frames, points, 1, capz::exact_distance);
}

TEST(NearestEarlier, NearestByExactDistanceTiesToTheLaterPoint) {
  // One frame, points on a line: 0 at 0, 1 at 10, 2 at 5 (equally far from 0 and 1: the later,
  // 1), 3 at 9 (nearest 1), 4 at 0 (nearest 0 exactly, though later points are nearer in index).
  const std::vector<int32_t> q = {0, 0, 0, 10, 0, 0, 5, 0, 0, 9, 0, 0, 0, 0, 0};
  const std::vector<uint8_t> valid(5, 1);
  const std::vector<uint32_t> n = nearest(q, valid, 1, 5);
  EXPECT_EQ(n, (std::vector<uint32_t>{kNoPoint, 0, 1, 1, 0}));
}

TEST(NearestEarlier, FirstValidFrameAndOnlyPointsValidThere) {
  // Two frames of 4 points. Point 3 is a gap in frame 0: its neighbour is found at frame 1,
  // where point 2 (its nearest at frame 0) is a gap and point 1 moved next to it. Point 2 is
  // valid only in frame 0. Point 1 is never valid: no neighbour, and never one of others.
  const size_t F = 2, N = 4;
  std::vector<int32_t> q = {
      0, 0, 0, 100, 0, 0, 49, 0, 0, 51, 0, 0,  // frame 0
      0, 0, 0, 52,  0, 0, 49, 0, 0, 51, 0, 0,  // frame 1
  };
  std::vector<uint8_t> valid = {1, 1, 1, 0, 1, 1, 0, 1};
  EXPECT_EQ(nearest(q, valid, F, N), (std::vector<uint32_t>{kNoPoint, 0, 0, 1}));
  valid = {1, 0, 1, 0, 1, 0, 0, 1};
  EXPECT_EQ(nearest(q, valid, F, N), (std::vector<uint32_t>{kNoPoint, kNoPoint, 0, 0}));
  valid = {0, 0, 0, 0, 0, 0, 0, 1};  // point 3 alone: no candidate
  EXPECT_EQ(nearest(q, valid, F, N), (std::vector<uint32_t>(4, kNoPoint)));
}

TEST(NearestEarlier, ExactWhereDoublesRound) {
  // Point 2 at the origin; point 0 at (2^31 - 1, 0, 2^16), squared distance 2^62 + 1; point 1
  // at (2^31 - 1, 1, 2^16), 2^62 + 2. In doubles both are 2^62 and the tie would go to the
  // later point, 1; exactly, point 0 is nearer.
  const std::vector<int32_t> q = {INT32_MAX, 0, 65536, INT32_MAX, 1, 65536, 0, 0, 0};
  const double x = 2147483647.0, z = 65536.0;
  ASSERT_EQ((x * x + 0.0) + z * z, (x * x + 1.0) + z * z) << "the doubles must tie here";
  const std::vector<uint8_t> valid(3, 1);
  EXPECT_EQ(nearest(q, valid, 1, 3)[2], 0u);
  // The largest differences (2^32 - 1 on every axis: squares summing past 2^64) compare
  // exactly: point 1 is one unit nearer than point 0 on one axis.
  const std::vector<int32_t> far = {INT32_MIN, INT32_MIN, INT32_MIN, INT32_MIN + 1, INT32_MIN,
                                    INT32_MIN, INT32_MAX, INT32_MAX, INT32_MAX};
  EXPECT_EQ(nearest(far, valid, 1, 3)[2], 1u);
  const capz::ExactDistance d0 = capz::exact_distance(&far[6], &far[0]);
  const capz::ExactDistance d1 = capz::exact_distance(&far[6], &far[3]);
  EXPECT_EQ(d0.hi, 2u);  // 3 (2^32 - 1)^2 lies between 2 * 2^64 and 3 * 2^64
  EXPECT_TRUE(d1 < d0);
  EXPECT_FALSE(d0 < d1);
}

TEST(NearestEarlier, NarrowSumsFindTheSamePointsAsExactDistances) {
  // Random windows with gaps and many ties (coordinates from a few values), below and above
  // kNearBruteForce, and one whose coordinates span just under 2^31.
  std::mt19937 rng(37);
  for (size_t points : {size_t{300}, size_t{5000}})
    for (int32_t range : {3, 1000, INT32_MAX / 2}) {
      const size_t frames = 2;
      std::uniform_int_distribution<int32_t> c(-range / 2, range - range / 2 - 1);
      std::vector<int32_t> q(frames * points * 3);
      for (int32_t& x : q) x = c(rng);
      std::vector<uint8_t> valid(frames * points);
      for (uint8_t& v : valid) v = rng() % 5 != 0;
      EXPECT_EQ(capz::nearest_earlier_narrow(q.data(), valid.data(), frames, points),
                nearest(q, valid, frames, points))
          << points << " points, range " << range;
    }
}

TEST(NearestEarlier, AboveBruteForceOnlyThe512PointsBefore) {
  // 5000 points (above 4096): point 4999 sits on point 0 but only points 4487..4998 are
  // candidates; with 4096 points, brute force finds point 0.
  for (const size_t N : {size_t{5000}, size_t{4096}}) {
    std::vector<int32_t> q(N * 3);
    for (size_t p = 0; p < N; ++p) q[p * 3] = static_cast<int32_t>(1000 + 10 * p);
    q[(N - 1) * 3] = 1000 - 3;  // next to point 0, far from the points before it
    const std::vector<uint8_t> valid(N, 1);
    const std::vector<uint32_t> n = nearest(q, valid, 1, N);
    const size_t expected = N > capz::kNearBruteForce ? N - 1 - capz::kNearWindow : 0;
    EXPECT_EQ(n[N - 1], expected) << N;
    EXPECT_EQ(n[1], 0u);
    EXPECT_EQ(n[N - 2], N - 3);
  }
}

// An unorganized cloud of N points in random order (static positions, integers of a 1000 x 1000
// x 20 slab) and a field pattern on it: stripes 200 units wide across x that slide by 37 units a
// frame (the neighbour knows a point's stripe, the previous frame often does not).
struct Cloud {
  size_t F = 8, N = 1500;
  std::vector<int32_t> q;
  std::vector<uint8_t> valid;
  explicit Cloud(uint32_t seed, bool gaps = false) {
    std::mt19937 rng(seed);
    std::vector<int32_t> one(N * 3);
    for (size_t i = 0; i < one.size(); ++i)
      one[i] = static_cast<int32_t>(rng() % (i % 3 == 2 ? 20 : 1000));
    for (size_t f = 0; f < F; ++f) q.insert(q.end(), one.begin(), one.end());
    valid.assign(F * N, 1);
    if (gaps)
      for (size_t i = 0; i < F * N; ++i) valid[i] = rng() % 5 != 0;
  }
  int stripe(size_t f, size_t p) const { return ((q[p * 3] + 37 * static_cast<int>(f)) / 200); }
};

// The field's values at the valid points, 0 at the gaps (a sensor's missing return).
template <typename T>
std::vector<uint8_t> field_of(const Cloud& c, T (*value)(const Cloud&, size_t, size_t)) {
  std::vector<uint8_t> b(c.F * c.N * sizeof(T));
  for (size_t f = 0; f < c.F; ++f)
    for (size_t p = 0; p < c.N; ++p) {
      const T v = c.valid[f * c.N + p] ? value(c, f, p) : T{};  // nothing at gaps
      std::memcpy(&b[(f * c.N + p) * sizeof(T)], &v, sizeof(T));
    }
  return b;
}

uint8_t reflectivity(const Cloud& c, size_t f, size_t p) {
  return static_cast<uint8_t>(20 + 23 * (c.stripe(f, p) % 9));
}
int32_t signed_label(const Cloud& c, size_t f, size_t p) {
  return -70000 + 1001 * c.stripe(f, p);
}
// Smooth over the cloud, scaled by a gain that changes every frame: the previous frame (and the
// previous point, a random one) mispredict by the change, a near point's value (and its change)
// hardly.
float intensity(const Cloud& c, size_t f, size_t p) {
  const float x = static_cast<float>(c.q[p * 3]), y = static_cast<float>(c.q[p * 3 + 1]);
  return (0.5f + 0.001f * x + 0.0007f * y) * (1.0f + 0.05f * static_cast<float>(f));
}
// A colour gradient across the cloud whose red part slides with the stripes.
uint32_t colour(const Cloud& c, size_t f, size_t p) {
  const uint32_t r = static_cast<uint32_t>((c.q[p * 3] + 37 * static_cast<int>(f)) / 4) & 255;
  const uint32_t g = static_cast<uint32_t>(c.q[p * 3 + 1] / 4) & 255;
  const uint32_t b = static_cast<uint32_t>(40 + 5 * c.q[p * 3 + 2]);
  return 0xFF000000u | (r << 16) | (g << 8) | b;
}

// The predictor of the first lane of the first field of the first window's ATTR chunk of stream
// z (-1 when that field is not coded predictively).
int attr_predictor(const std::vector<uint8_t>& z) {
  for (const capz_test::Piece& p : capz_test::pieces(z)) {
    if (p.type != "ATTR") continue;
    capz::ByteReader r(p.payload.data(), p.payload.size(), "ATTR");
    r.varint();  // window index
    const uint8_t t = r.u8();
    return t < 2 ? r.u8() : -1;
  }
  return -2;
}

struct Coded {
  std::vector<uint8_t> bytes;
  std::vector<std::vector<uint8_t>> back;
};
Coded code(const std::vector<AttrSpec>& specs, const std::vector<std::vector<uint8_t>>& data,
           const Cloud& c, bool near) {
  const uint8_t* valid = std::count(c.valid.begin(), c.valid.end(), 0) ? c.valid.data() : nullptr;
  Coded out;
  // With the positions' integers predictors 10 and 11 are candidates; without, they are not.
  out.bytes =
      capz::encode_attributes(specs, data, valid, c.F, c.N, c.N, near ? c.q.data() : nullptr);
  capz::decode_attributes(out.bytes.data(), out.bytes.size(), specs, valid, c.F, c.N, c.N,
                          &out.back, "test", near ? c.q.data() : nullptr);
  return out;
}

TEST(AttrNear, SpatialFieldsOfAnUnorganizedCloudCostLessAndComeBack) {
  // Every lane kind: U1, I4, F4 and a packed colour (four lanes), with and without gaps.
  const std::vector<AttrSpec> specs = {
      AttrSpec{"reflectivity", 'U', 1, 1}, AttrSpec{"label", 'I', 4, 1},
      AttrSpec{"intensity", 'F', 4, 1}, AttrSpec{"rgb", 'U', 4, 1}};
  for (const bool gaps : {false, true}) {
    const Cloud c(5, gaps);
    const std::vector<std::vector<uint8_t>> data = {field_of(c, reflectivity),
                                                    field_of(c, signed_label),
                                                    field_of(c, intensity), field_of(c, colour)};
    const Coded v6 = code(specs, data, c, false), v7 = code(specs, data, c, true);
    EXPECT_EQ(v6.back, data);
    EXPECT_EQ(v7.back, data);
    // At least a tenth smaller (measured: 19 % without gaps, 13 % with a fifth of the points
    // gaps, where neighbours are often missing and LZMA keeps the colour).
    EXPECT_LT(v7.bytes.size() * 10, v6.bytes.size() * 9)
        << v7.bytes.size() << " " << v6.bytes.size();
    if (gaps) continue;
    // Field by field too: each attribute alone shrinks, and its lanes use predictor 10 or 11.
    for (size_t a = 0; a < specs.size(); ++a) {
      const Coded one6 = code({specs[a]}, {data[a]}, c, false);
      const Coded one7 = code({specs[a]}, {data[a]}, c, true);
      EXPECT_EQ(one7.back, std::vector<std::vector<uint8_t>>{data[a]});
      EXPECT_LT(one7.bytes.size(), one6.bytes.size()) << specs[a].name << " gaps " << gaps;
      ASSERT_LT(one7.bytes[0], 2) << specs[a].name;  // plain or colour
      const size_t lanes = one7.bytes[0] == 1 ? 4 : 1;
      for (size_t j = 0; j < std::min<size_t>(lanes, 3); ++j)  // (colour lane A is constant)
        EXPECT_GE(one7.bytes[1 + j], 10) << specs[a].name << " lane " << j;
    }
  }
}

TEST(AttrNear, ChangeCarriedOverWinsWhereEachPointChangesLikeItsNeighbour) {
  // A random value per point plus a change over time that depends on where the point is: the
  // neighbour's change since the previous frame predicts the point's (predictor 11); neither
  // the neighbour's value (10) nor the previous point's change (4) does.
  const Cloud c(9);
  std::vector<uint8_t> b(c.F * c.N * 2);
  std::mt19937 rng(3);
  std::vector<uint16_t> base(c.N);
  for (auto& v : base) v = static_cast<uint16_t>(rng() % 60000);
  for (size_t f = 0; f < c.F; ++f)
    for (size_t p = 0; p < c.N; ++p) {
      const uint16_t v = static_cast<uint16_t>(base[p] + f * (c.q[p * 3] / 100) * 3);
      std::memcpy(&b[(f * c.N + p) * 2], &v, 2);
    }
  const std::vector<AttrSpec> specs = {AttrSpec{"count", 'U', 2, 1}};
  const Coded v7 = code(specs, {b}, c, true), v6 = code(specs, {b}, c, false);
  EXPECT_EQ(v7.back, std::vector<std::vector<uint8_t>>{b});
  ASSERT_EQ(v7.bytes[0], 0);
  EXPECT_EQ(v7.bytes[1], 11);
  EXPECT_LT(v7.bytes.size(), v6.bytes.size());
}

TEST(AttrNear, RandomValuesComeBackUnderEveryPredictor) {
  // Whatever the encoder chooses on noise, with gaps and a point never valid, decodes exactly;
  // and a window of one point (no neighbour at all) too.
  Cloud c(11, true);
  for (size_t f = 0; f < c.F; ++f) c.valid[f * c.N + 7] = 0;
  std::mt19937 rng(4);
  const std::vector<AttrSpec> specs = {AttrSpec{"a", 'U', 8, 1}, AttrSpec{"b", 'F', 8, 1},
                                       AttrSpec{"rgba", 'F', 4, 1}, AttrSpec{"c", 'I', 2, 3}};
  std::vector<std::vector<uint8_t>> data;
  for (const AttrSpec& s : specs) {
    std::vector<uint8_t> b(c.F * c.N * static_cast<size_t>(s.size * s.count));
    for (auto& x : b) x = static_cast<uint8_t>(rng() % 4);  // small noise: predictive coding
    data.push_back(b);
  }
  EXPECT_EQ(code(specs, data, c, true).back, data);
  Cloud one(2);
  one.N = 1;
  one.q.assign(one.F * 3, 5);
  one.valid.assign(one.F, 1);
  const std::vector<std::vector<uint8_t>> d1 = {std::vector<uint8_t>(one.F, 9)};
  EXPECT_EQ(code({AttrSpec{"r", 'U', 1, 1}}, d1, one, true).back, d1);
}

TEST(AttrNear, PredictorsTenAndElevenAreCorruptWithoutPositions) {
  const Cloud c(5);
  const std::vector<AttrSpec> specs = {AttrSpec{"reflectivity", 'U', 1, 1}};
  const std::vector<std::vector<uint8_t>> data = {field_of(c, reflectivity)};
  const std::vector<uint8_t> enc =
      capz::encode_attributes(specs, data, nullptr, c.F, c.N, c.N, c.q.data());
  ASSERT_EQ(enc[0], 0);
  ASSERT_EQ(enc[1], 10);
  std::vector<std::vector<uint8_t>> back;
  auto decode = [&](const std::vector<uint8_t>& e, const int32_t* q) {
    std::string msg;
    const ErrorCode code = capz_test::error_of(
        [&] {
          capz::decode_attributes(e.data(), e.size(), specs, nullptr, c.F, c.N, c.N, &back, "test",
                                  q);
        },
        &msg);
    return std::make_pair(code, msg);
  };
  ASSERT_NO_THROW(decode(enc, c.q.data()));
  for (const uint8_t id : {uint8_t{10}, uint8_t{11}}) {
    std::vector<uint8_t> e = enc;
    e[1] = id;
    const auto none = decode(e, nullptr);  // positions as transform output
    EXPECT_EQ(none.first, ErrorCode::kCorrupt);
    EXPECT_NE(none.second.find("position integers"), std::string::npos) << none.second;
  }
  std::vector<uint8_t> e = enc;
  e[1] = 12;  // the next id is unknown
  EXPECT_EQ(decode(e, c.q.data()).first, ErrorCode::kCorrupt);
  // Other positions decode to other values (the prediction reads them), never out of bounds.
  std::vector<int32_t> moved = c.q;
  std::reverse(moved.begin(), moved.end());
  ASSERT_NO_THROW(decode(enc, moved.data()));
  EXPECT_NE(back, data);
}

// A take of an unorganized cloud with a field: its field coded with predictor 10 (FORMAT.md 7.3),
// exact lossless and at a bound (the encoder's self-check decodes every window, so the decoder
// found the same neighbours from the POSW integers it decoded); organized, the same take keeps
// its pixel neighbours (predictors 10 and 11 are not tried).
TEST(AttrNear, UnorganizedTakesWithFieldsUseTheNearestPoint) {
  const Cloud c(13);
  capz::Take t;
  t.resize(c.F, c.N);
  for (size_t i = 0; i < c.F * c.N; ++i) {
    t.valid[i] = 1;
    for (int a = 0; a < 3; ++a) t.xyz[i * 3 + a] = 0.001 * c.q[i * 3 + a] + 0.0003 * (i % 7);
  }
  t.units = "m";
  capz::PointAttribute refl;
  refl.name = "reflectivity";
  refl.type = 'U';
  refl.size = 1;
  refl.data = field_of(c, reflectivity);
  t.attributes.push_back(refl);
  for (const bool organized : {false, true}) {
    int near = 0;  // targets whose field is coded with predictor 10 or 11 (the bound's, here)
    if (organized) {
      t.pcd = std::make_shared<capz::PCDExtra>();
      t.pcd->width = c.N / 2;
      t.pcd->height = 2;
    }
    for (int target = 0; target < 2; ++target) {
      capz::CompressOptions o;
      o.lossless = target == 0;
      o.max_error = target == 1 ? 1e-3 : 0;
      o.check = true;
      const std::vector<uint8_t> z = capz::compress(t, o);
      ASSERT_GT(z.size(), 10u);
      const int pred = attr_predictor(z);
      near += pred == 10 || pred == 11;
      const capz::Take back = capz::decompress(z.data(), z.size(), "test");
      ASSERT_EQ(back.attributes.size(), 1u);
      EXPECT_EQ(back.attributes[0].data, refl.data);
    }
    EXPECT_EQ(near > 0, !organized) << "organized " << organized;
  }
}

}  // namespace
