// ATTR's predictor 12, quantum, and the key-first order of a ragged window's attributes
// (docs/FORMAT.md "Scans (format 1.1)": point fields of a ragged window): the value of k D and the
// range prediction by the rules; each base chosen where it fits and exact on the way back (gaps,
// NaN, -0.0 and off-grid values included); damaged parameters refused.
#include <gtest/gtest.h>

#include <cmath>
#include <cstring>
#include <limits>
#include <random>
#include <string>
#include <vector>

#include "capz/error.h"
#include "coding/attributes.h"
#include "coding/attributes_quantum.h"
#include "test_util.h"

using capz::AttrSpec;
using capz::ErrorCode;

namespace {

AttrSpec spec(const std::string& name, char type, int size, int count = 1) {
  return capz_test::field_spec(name, type, size, count);
}

void put_le(std::vector<uint8_t>* b, uint64_t v, int size) {
  for (int k = 0; k < size; ++k) b->push_back(static_cast<uint8_t>(v >> (8 * k)));
}
void put_f32(std::vector<uint8_t>* b, float v) {
  uint32_t u;
  std::memcpy(&u, &v, 4);
  put_le(b, u, 4);
}
void put_f64(std::vector<uint8_t>* b, double v) {
  uint64_t u;
  std::memcpy(&u, &v, 8);
  put_le(b, u, 8);
}

// A ragged window's fields as a 16-ring sensor writes them: intensity F4 (integers, per ring),
// ring U2 (after intensity in the layout), distance F4 (float32 steps of 2.5 mm, 3.4 cm short of
// the decoded range) and a timestamp F8 (microseconds since a start, as multiples of 1e-6). Gaps
// every 23rd point, odd values
// (-0.0, NaN, an off-step distance) at a few valid ones.
struct Window {
  std::vector<AttrSpec> specs = {spec("intensity", 'F', 4), spec("ring", 'U', 2),
                                 spec("distance", 'F', 4), spec("timestamp", 'F', 8)};
  std::vector<std::vector<uint8_t>> data = std::vector<std::vector<uint8_t>>(4);
  std::vector<uint8_t> valid;
  std::vector<double> xyz;
};

Window sensor_window(size_t n) {
  Window w;
  std::mt19937 rng(5);
  std::uniform_int_distribution<int> noise(-2, 2);
  int level[16];
  for (int k = 0; k < 16; ++k) level[k] = 20 + 13 * k;
  for (size_t i = 0; i < n; ++i) {
    const int ring = static_cast<int>(i % 16);
    const double az = 0.01 * static_cast<double>(i / 16), el = 0.03 * (ring - 8);
    const double r = 5 + 2 * std::sin(3 * az) + 0.1 * ring;
    const bool valid = i % 23 != 7;
    w.valid.push_back(valid ? 1 : 0);
    // Decoded positions on a 1 mm grid (0 at gaps, as the decoder has them).
    const double p[3] = {r * std::cos(el) * std::cos(az), r * std::cos(el) * std::sin(az),
                         r * std::sin(el)};
    for (double c : p) w.xyz.push_back(valid ? std::round(c * 1000) * 0.001 : 0.0);
    level[ring] += noise(rng);
    float in = static_cast<float>(level[ring]);
    if (i == 40) in = -0.0f;
    if (i == 41) in = std::numeric_limits<float>::quiet_NaN();
    put_f32(&w.data[0], in);
    put_le(&w.data[1], static_cast<uint64_t>(ring), 2);
    const int32_t k = static_cast<int32_t>(std::lround((r - 0.034) / 0.0025));
    float d = static_cast<float>(k) * 0.0025f;
    if (i == 50) d = 1.2345678f;
    put_f32(&w.data[2], valid ? d : 0.0f);
    put_f64(&w.data[3], static_cast<double>(1000000000 + 55 * i + (i % 16) * 3) * 1e-6);
  }
  return w;
}

std::vector<uint8_t> encode(const Window& w, bool ragged = true) {
  capz::RaggedFields rf;
  rf.xyz = w.xyz.data();
  const size_t n = w.valid.size();
  return capz::encode_attributes(w.specs, w.data, w.valid.data(), 1, n, n, nullptr, true,
                                 ragged ? &rf : nullptr);
}

// The decoder's error code (kInternal: no error, which error_of returns when nothing throws).
capz::ErrorCode decode(const Window& w, const std::vector<uint8_t>& e,
                       std::vector<std::vector<uint8_t>>* back, bool ragged = true,
                       bool with_xyz = true, std::string* msg = nullptr) {
  capz::RaggedFields rf;
  rf.xyz = with_xyz ? w.xyz.data() : nullptr;
  const size_t n = w.valid.size();
  return capz_test::error_of(
      [&] {
        capz::decode_attributes(e.data(), e.size(), w.specs, w.valid.data(), 1, n, n, back, "test",
                                nullptr, ragged ? &rf : nullptr);
      },
      msg);
}

size_t varint_at(const std::vector<uint8_t>& e, size_t* at) {
  size_t v = 0;
  for (int sh = 0;; sh += 7) {
    v |= static_cast<size_t>(e[*at] & 0x7F) << sh;
    if (!(e[(*at)++] & 0x80)) break;
  }
  return v;
}

double f64_at(const std::vector<uint8_t>& e, size_t at) {
  double d;
  std::memcpy(&d, e.data() + at, 8);
  return d;
}

// Offsets of each attribute's header in a payload of one-lane attributes: ring first (key-first).
struct Header {
  size_t at;  // the transform byte
  uint8_t transform, predictor;
};
std::vector<Header> headers(const std::vector<uint8_t>& e, size_t count) {
  std::vector<Header> out;
  size_t at = 0;
  for (size_t a = 0; a < count; ++a) {
    Header h{at, e[at], 0};
    ++at;
    if (h.transform < 2) {
      h.predictor = e[at++];
      if (h.predictor == 12) {
        at += 8;
        const uint8_t base = e[at++] & 3;
        if (base == 1) {
          varint_at(e, &at);
          varint_at(e, &at);
        }
        if (base == 2) at += 8;
      }
    }
    at += varint_at(e, &at);
    out.push_back(h);
  }
  return out;
}

}  // namespace

TEST(AttrQuantum, ValueIsTheFloat32ProductOrTheBinary64One) {
  using capz::attr::quantum_value;
  using capz::attr::to_ordered;
  const float d = 87.0f * 0.0025f;  // float32 arithmetic, as a driver computes it
  uint32_t b;
  std::memcpy(&b, &d, 4);
  EXPECT_EQ(quantum_value(87, 0.0025, 4), to_ordered(b, 'F', 32));
  const double e = -123456.0 * 1e-6;
  uint64_t b8;
  std::memcpy(&b8, &e, 8);
  EXPECT_EQ(quantum_value(-123456, 1e-6, 8), to_ordered(b8, 'F', 64));
  EXPECT_EQ(quantum_value(0, 5.0, 4), to_ordered(0, 'F', 32));  // +0.0
}

TEST(AttrQuantum, RangeRoundsHalfUpAndClamps) {
  using capz::attr::quantum_range_k;
  const double p[3] = {3, 4, 0};  // r = 5
  EXPECT_EQ(quantum_range_k(p, 0.5, 0), 10);
  EXPECT_EQ(quantum_range_k(p, 2, 0), 3);    // 2.5 rounds up
  EXPECT_EQ(quantum_range_k(p, 2, 10), -2);  // -2.5 rounds up too
  EXPECT_EQ(quantum_range_k(p, 1e-12, 0), INT32_MAX);
  EXPECT_EQ(quantum_range_k(p, 1e-12, 10), INT32_MIN);
  const double nan[3] = {std::nan(""), 0, 0};
  EXPECT_EQ(quantum_range_k(nan, 1, 0), 0);
}

TEST(AttrQuantum, KeyFirstOrderOnlyInRaggedWindows) {
  const std::vector<AttrSpec> specs = {spec("a", 'F', 4), spec("b", 'U', 2), spec("c", 'I', 1),
                                       spec("d", 'U', 4), spec("e", 'F', 8)};
  EXPECT_EQ(capz::attr::coding_order(specs, false), (std::vector<size_t>{0, 1, 2, 3, 4}));
  EXPECT_EQ(capz::attr::coding_order(specs, true), (std::vector<size_t>{1, 2, 0, 3, 4}));
}

TEST(AttrQuantum, EachBaseWhereItFitsAndExactBack) {
  const Window w = sensor_window(4000);
  const std::vector<uint8_t> e = encode(w);
  std::vector<std::vector<uint8_t>> back;
  ASSERT_EQ(decode(w, e, &back), ErrorCode::kInternal);
  EXPECT_EQ(back, w.data);
  const std::vector<Header> h = headers(e, 4);  // ring, intensity, distance, timestamp
  EXPECT_EQ(h[1].predictor, 12);                // intensity: quantum 1, keyed by the ring
  EXPECT_EQ(f64_at(e, h[1].at + 2), 1.0);
  EXPECT_EQ(e[h[1].at + 10], 1);
  EXPECT_EQ(e[h[1].at + 11], 1);  // attribute 1 (ring), element 0
  EXPECT_EQ(e[h[1].at + 12], 0);
  EXPECT_EQ(h[2].predictor, 12);  // distance: 2.5 mm from the range
  EXPECT_EQ(f64_at(e, h[2].at + 2), 0.0025);
  EXPECT_EQ(e[h[2].at + 10], 2);
  EXPECT_NEAR(f64_at(e, h[2].at + 11), 0.034, 0.002);
  // Not a ragged window: the layout's order, no predictor 12, the same fields back.
  const std::vector<uint8_t> plain = encode(w, false);
  ASSERT_EQ(decode(w, plain, &back, false), ErrorCode::kInternal);
  EXPECT_EQ(back, w.data);
  for (const Header& x : headers(plain, 4)) EXPECT_NE(x.predictor, 12);
  EXPECT_LT(e.size() * 10, plain.size() * 8) << e.size() << " " << plain.size();
}

TEST(AttrQuantum, MicrosecondTimestampsAsIntegers) {
  // A float64 field on a 1e-6 grid whose integers fit int32 (times within a half hour).
  Window w = sensor_window(3000);
  w.specs = {spec("t", 'F', 8)};
  w.data = {std::vector<uint8_t>()};
  for (size_t i = 0; i < 3000; ++i) put_f64(&w.data[0], 1e-6 * static_cast<double>(300 + 55 * i));
  const std::vector<uint8_t> e = encode(w);
  std::vector<std::vector<uint8_t>> back;
  ASSERT_EQ(decode(w, e, &back), ErrorCode::kInternal);
  EXPECT_EQ(back, w.data);
  EXPECT_EQ(e[1], 12);
  EXPECT_EQ(f64_at(e, 2), 1e-6);
  EXPECT_EQ(e[10], 0);  // base 0: the previous integer
  // The wide bit is for float32 fields only.
  std::vector<uint8_t> d = e;
  d[10] = 4;
  std::string msg;
  EXPECT_EQ(decode(w, d, &back, true, true, &msg), ErrorCode::kCorrupt);
  EXPECT_NE(msg.find("float64"), std::string::npos) << msg;
}

TEST(AttrQuantum, BoundedFloat32FieldsTakeTheWideRounding) {
  // A float32 field as --attr-error 0.001 leaves it: float(round(v / 0.002) 0.002), the product
  // in binary64 (FORMAT.md 16.4), which the float32 product misses on about a quarter of values.
  Window w = sensor_window(3000);
  w.specs = {spec("v", 'F', 4)};
  w.data = {std::vector<uint8_t>()};
  size_t differ = 0;
  for (size_t i = 0; i < 3000; ++i) {
    const int32_t k = 5000 + static_cast<int32_t>(std::lround(3000 * std::sin(0.003 * i)));
    const float v = static_cast<float>(static_cast<double>(k) * 0.002);
    differ += v != static_cast<float>(k) * 0.002f;
    put_f32(&w.data[0], v);
  }
  ASSERT_GT(differ, 300u);
  const std::vector<uint8_t> e = encode(w);
  std::vector<std::vector<uint8_t>> back;
  ASSERT_EQ(decode(w, e, &back), ErrorCode::kInternal);
  EXPECT_EQ(back, w.data);
  ASSERT_EQ(e[1], 12);
  EXPECT_EQ(f64_at(e, 2), 0.002);
  EXPECT_EQ(e[10] & 4, 4);
}

TEST(AttrQuantum, DamagedParametersAreCorrupt) {
  const Window w = sensor_window(2000);
  const std::vector<uint8_t> e = encode(w);
  const std::vector<Header> h = headers(e, 4);
  ASSERT_EQ(h[1].predictor, 12);
  ASSERT_EQ(h[2].predictor, 12);
  std::vector<std::vector<uint8_t>> back;
  auto with = [&](size_t at, const std::vector<uint8_t>& bytes) {
    std::vector<uint8_t> d = e;
    std::copy(bytes.begin(), bytes.end(), d.begin() + static_cast<std::ptrdiff_t>(at));
    return d;
  };
  auto f64_bytes = [](double v) {
    std::vector<uint8_t> b;
    put_f64(&b, v);
    return b;
  };
  const size_t q1 = h[1].at + 2, q2 = h[2].at + 2;
  const std::vector<std::vector<uint8_t>> bad = {
      with(q1, f64_bytes(0)),             // quantum 0
      with(q1, f64_bytes(-1)),            // negative
      with(q1, f64_bytes(std::nan(""))),  // NaN
      with(q1 + 8, {3}),                  // base 3 (near) without position integers
      with(q1 + 8, {8}),                  // unknown base
      with(q1 + 9, {0}),                  // key: intensity, a float
      with(q1 + 9, {9}),                  // key past the last attribute
      with(q1 + 10, {1}),                 // element 1 of a count-1 key
      with(q2 + 9, f64_bytes(INFINITY)),  // offset not finite
  };
  for (size_t i = 0; i < bad.size(); ++i) {
    std::string msg;
    EXPECT_EQ(decode(w, bad[i], &back, true, true, &msg), ErrorCode::kCorrupt) << i;
    EXPECT_NE(msg.find("predictor 12"), std::string::npos) << i << " " << msg;
  }
  // 12 on a lane of another type (the timestamp's predictor byte, F8, is kept: its attribute
  // relabelled as U8).
  Window other = w;
  other.specs[3] = spec("timestamp", 'U', 8);
  ASSERT_EQ(h[3].predictor, 12);
  {
    std::string msg;
    EXPECT_EQ(decode(other, e, &back, true, true, &msg), ErrorCode::kCorrupt);
    EXPECT_NE(msg.find("not a float"), std::string::npos) << msg;
  }
  // 12 outside a ragged window is an unknown predictor; the range base needs positions.
  EXPECT_EQ(decode(w, e, &back, false), ErrorCode::kCorrupt);
  std::string msg;
  EXPECT_EQ(decode(w, e, &back, true, false, &msg), ErrorCode::kCorrupt);
  EXPECT_NE(msg.find("without them"), std::string::npos) << msg;
  // Every truncation is refused, never a crash.
  for (size_t cut = 0; cut < e.size(); cut += 97) {
    const std::vector<uint8_t> t(e.begin(), e.begin() + static_cast<std::ptrdiff_t>(cut));
    EXPECT_EQ(decode(w, t, &back), ErrorCode::kCorrupt) << cut;
  }
}

// Base 3: an intensity stored as a float of whole numbers (a KITTI .bin's, a script's PLY) with no
// ring field, in the sensor's firing order (ring after ring at each azimuth): the previous point
// is another laser's, the nearest earlier point the same laser's at the azimuth before.
TEST(AttrQuantum, NearBaseFromTheNearestEarlierPoint) {
  Window w = sensor_window(3000);
  const size_t n = w.valid.size();
  Window one;
  one.specs = {w.specs[0]};
  one.data = {w.data[0]};
  one.valid = w.valid;
  one.xyz = w.xyz;
  std::vector<int32_t> q;
  for (double c : w.xyz) q.push_back(static_cast<int32_t>(std::lround(c * 1000)));
  capz::RaggedFields rf;
  rf.xyz = one.xyz.data();
  const std::vector<uint8_t> e =
      capz::encode_attributes(one.specs, one.data, one.valid.data(), 1, n, n, q.data(), true, &rf);
  std::vector<std::vector<uint8_t>> back;
  capz::decode_attributes(e.data(), e.size(), one.specs, one.valid.data(), 1, n, n, &back, "test",
                          q.data(), &rf);
  EXPECT_EQ(back, one.data);
  ASSERT_EQ(e[1], 12);           // transform 0, predictor 12
  EXPECT_EQ(f64_at(e, 2), 1.0);  // quantum 1
  EXPECT_EQ(e[10], 3);           // base 3: near
  const std::vector<uint8_t> without =
      capz::encode_attributes(one.specs, one.data, one.valid.data(), 1, n, n, nullptr, true, &rf);
  EXPECT_LT(e.size() * 10, without.size() * 8) << e.size() << " " << without.size();
  // Without the positions' integers the decoder has no nearest points: corrupt.
  std::string msg;
  EXPECT_EQ(capz_test::error_of(
                [&] {
                  capz::decode_attributes(e.data(), e.size(), one.specs, one.valid.data(), 1, n, n,
                                          &back, "test", nullptr, &rf);
                },
                &msg),
            ErrorCode::kCorrupt);
  EXPECT_NE(msg.find("nearest points"), std::string::npos) << msg;
}
