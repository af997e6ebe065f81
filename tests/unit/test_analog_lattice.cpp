// Rank tables coded against a lattice (FORMAT.md 11.7): round trips of float32 and double tables,
// the window codec choosing them only in 8.x windows, and the decoder refusing a lattice table
// in a stream before 8.0 and every damaged field.
#include <gtest/gtest.h>

#include <cmath>
#include <cstring>
#include <limits>
#include <random>

#include "capz/error.h"
#include "coding/analog/analog_codec.h"
#include "coding/analog/analog_repr.h"
#include "coding/bytes.h"
#include "coding/entropy.h"

namespace capz {
namespace analog {
namespace {

// n samples as a writer converting counts to volts in float32 arithmetic makes them: k a slow
// random walk, x = float(float(k) * float(s) + float(o)). Nearly, but not exactly, on a lattice.
std::vector<double> float32_volts(size_t n, uint32_t seed) {
  std::mt19937 rng(seed);
  std::uniform_int_distribution<int> step(-3, 3);
  const float s = static_cast<float>(20.0 / 65535.0), o = -1.0541695f;
  std::vector<double> x(n);
  int k = 3000;
  for (double& v : x) {
    k += step(rng);
    v = static_cast<double>(static_cast<float>(static_cast<float>(k) * s) + o);
  }
  return x;
}

// The rank representation of x (candidate_representations offers it for few distinct values).
ChannelRepr rank_of(const std::vector<double>& x) {
  for (ChannelRepr& r : candidate_representations(x.data(), 1, x.size(), ChannelHint()))
    if (r.kind == Kind::kRank) return std::move(r);
  ADD_FAILURE() << "no rank candidate";
  return ChannelRepr();
}

std::vector<uint8_t> header(const ChannelRepr& r, bool lattice) {
  ByteWriter w;
  HeaderRules rules;
  rules.lattice = lattice;
  HeaderState state;
  write_repr_header(r, KeptRows(), rules, &state, &w);
  return w.buffer();
}

// The table flag of a rank header: after the kind byte and the varint entry count.
uint8_t flag_of(const std::vector<uint8_t>& h) {
  size_t k = 1;
  while (h.at(k) & 0x80) ++k;
  return h.at(k + 1);
}

ChannelRepr read(const std::vector<uint8_t>& h, size_t n, bool lattice) {
  ByteReader in(h.data(), h.size(), "test header");
  HeaderRules rules;
  rules.lattice = lattice;
  HeaderState state;
  KeptRows kept;
  ChannelRepr r = read_repr_header(&in, n, rules, &state, &kept);
  EXPECT_TRUE(in.at_end());
  return r;
}

void expect_same_table(const ChannelRepr& a, const ChannelRepr& b) {
  ASSERT_EQ(a.table.size(), b.table.size());
  for (size_t i = 0; i < a.table.size(); ++i)
    ASSERT_EQ(bits_of(a.table[i]), bits_of(b.table[i])) << "entry " << i;
}

TEST(AnalogLattice, GivenNearLatticeFloat32TableWhenCodedThenFlagBit1SmallerAndExact) {
  const std::vector<double> x = float32_volts(2000, 1);
  const ChannelRepr r = rank_of(x);
  ASSERT_GT(r.table.size(), 50u);
  const std::vector<uint8_t> plain = header(r, false), lat = header(r, true);
  EXPECT_EQ(flag_of(plain), 1);  // float32
  EXPECT_EQ(flag_of(lat), 3);    // float32, lattice
  EXPECT_LT(lat.size() * 2, plain.size());
  expect_same_table(read(lat, x.size(), true), r);
  expect_same_table(read(plain, x.size(), true), r);  // 8.x reads the gaps too
}

// PiG's float32 EMG tables: one pair of entries a few float32 units apart, off the lattice, makes
// the smallest gap thousands of times smaller than the step. The table is still coded against
// the real step: about as small as without that entry, and exact.
TEST(AnalogLattice, GivenTwoEntriesAFewUnitsApartThenTheLatticeOfTheMedianGapAndExact) {
  const std::vector<double> x = float32_volts(2000, 3);
  std::vector<double> odd = x;
  float near = static_cast<float>(odd[700]);
  for (int u = 0; u < 15; ++u) near = std::nextafter(near, 10.0f);
  odd[1500] = near;  // a new entry 15 units above an existing one
  const ChannelRepr r = rank_of(x), ro = rank_of(odd);
  ASSERT_EQ(ro.table.size(), r.table.size() + 1);
  const std::vector<uint8_t> lat = header(r, true), lat_odd = header(ro, true);
  EXPECT_EQ(flag_of(lat_odd), 3);
  EXPECT_LT(lat_odd.size(), lat.size() + 16);
  expect_same_table(read(lat_odd, odd.size(), true), ro);
}

// An entry next to zero after one a little off the lattice: the nearest number of steps predicts
// it on the other side of zero, over 2^30 float32 patterns away, so the coder takes one step
// more and the table is still coded against the lattice, exactly.
TEST(AnalogLattice, GivenAnEntryNextToZeroPredictedAcrossZeroThenStillTheLatticeAndExact) {
  const double s = 20.0 / 65535.0 / 4000.0;
  std::vector<double> x;
  for (int j = -200; j <= 200; ++j) x.push_back(static_cast<float>(j * s));
  x[199] = static_cast<float>(-s - 1e-9);  // j = -1, 1.3% of a step off
  x[200] = std::ldexp(1.0, -60);           // j = 0, just above zero
  for (int rep = 0; rep < 3; ++rep)
    for (size_t i = 0; i < 401; ++i) x.push_back(x[i]);  // every value a few times
  const ChannelRepr r = rank_of(x);
  ASSERT_EQ(r.table.size(), 401u);
  const std::vector<uint8_t> lat = header(r, true);
  EXPECT_EQ(flag_of(lat), 3);
  EXPECT_LT(lat.size() * 2, header(r, false).size());
  expect_same_table(read(lat, x.size(), true), r);
}

// Tables on no lattice, nearly one, or one with outliers: whichever coding wins (write_value_table
// stops each lattice try once it reaches the smallest size so far), the header is never larger
// than the gaps' and reads back bit for bit.
TEST(AnalogLattice, GivenTablesOfEveryShapeThenNeverLargerThanTheGapsAndExact) {
  std::mt19937 rng(9);
  int tried = 0;
  for (int shape = 0; shape < 6; ++shape) {
    std::vector<double> x = float32_volts(3000, 10 + shape);
    std::uniform_real_distribution<float> u(-3.0f, 3.0f);
    for (size_t i = 0; i < x.size(); ++i) {
      if (shape == 1) x[i] = u(rng);                                     // no lattice
      if (shape == 2 && i % 97 == 0) x[i] = u(rng);                      // outliers
      if (shape == 3) x[i] = static_cast<double>(u(rng)) * 1e-3 + 1e-9;  // doubles
      if (shape >= 4) x[i] = std::ldexp(x[i], shape * 7);
    }
    for (size_t i = 300; i < x.size(); ++i) x[i] = x[i % 300];  // a rank table
    ChannelRepr r;
    for (ChannelRepr& c : candidate_representations(x.data(), 1, x.size(), ChannelHint()))
      if (c.kind == Kind::kRank) r = std::move(c);
    if (r.kind != Kind::kRank) continue;  // a scaled fit alone (an exact lattice)
    ++tried;
    const std::vector<uint8_t> plain = header(r, false), lat = header(r, true);
    EXPECT_LE(lat.size(), plain.size()) << shape;
    expect_same_table(read(lat, x.size(), true), r);
  }
  EXPECT_GE(tried, 4);
}

TEST(AnalogLattice, GivenDoubleTableWhenCodedThenExact) {
  std::vector<double> x(500);
  for (size_t i = 0; i < x.size(); ++i) x[i] = 0.1 * static_cast<double>(i % 97) + 1e-3;
  const ChannelRepr r = rank_of(x);
  const std::vector<uint8_t> lat = header(r, true);
  EXPECT_EQ(flag_of(lat), 2);
  expect_same_table(read(lat, x.size(), true), r);
}

TEST(AnalogLattice, GivenLatticeTableInAStreamBefore8ThenCorrupt) {
  const std::vector<double> x = float32_volts(1000, 2);
  const std::vector<uint8_t> lat = header(rank_of(x), true);
  ASSERT_EQ(flag_of(lat), 3);
  EXPECT_THROW(read(lat, x.size(), false), Error);
}

// The window codec: an 8.x window is smaller on such channels and decodes exactly; decoded as
// a window before 8.0 it is corrupt.
TEST(AnalogLattice, GivenFormat8WindowThenSmallerExactAndRefusedBefore8) {
  const size_t n = 1500;
  std::vector<double> rows(2 * n);
  const std::vector<double> a = float32_volts(n, 3), b = float32_volts(n, 4);
  for (size_t i = 0; i < n; ++i) {
    rows[2 * i] = a[i];
    rows[2 * i + 1] = b[i];
  }
  const std::vector<uint8_t> p7 =
      encode_analog_window(rows.data(), n, 2, AnalogHints(), 0, kAnalogWindowsSince);
  const std::vector<uint8_t> p8 =
      encode_analog_window(rows.data(), n, 2, AnalogHints(), 0, kAnalogLatticeSince);
  EXPECT_LT(p8.size(), p7.size());
  std::vector<double> back(rows.size(), 0.0);
  decode_analog_window(p8.data(), p8.size(), n, 2, back.data(), "w", 0, kAnalogLatticeSince);
  for (size_t i = 0; i < rows.size(); ++i) ASSERT_EQ(bits_of(back[i]), bits_of(rows[i])) << i;
  EXPECT_THROW(
      decode_analog_window(p8.data(), p8.size(), n, 2, back.data(), "w", 0, kAnalogWindowsSince),
      Error);
}

// A lattice table header written field by field (FORMAT.md 11.7), float32 entries 1.0, 2.0, ...
// with the given fields.
struct Fields {
  uint64_t m = 3;
  uint8_t flag = 3;
  double step = 1.0;
  uint64_t first = 0;  // set below to ord32(1.0f)
  std::vector<std::pair<uint32_t, int32_t>> entries = {{1, 0}, {1, 0}};
  size_t extra_block_bytes = 0;
};
std::vector<uint8_t> build(const Fields& f) {
  ByteWriter w;
  w.u8(static_cast<uint8_t>(Kind::kRank));
  w.varint(f.m);
  w.u8(f.flag);
  w.f64(f.step);
  w.u64(f.first ? f.first : ordered_f32(1.0));
  IntEncoder enc(2);
  for (const auto& e : f.entries) {
    enc.put(e.first, 0);
    enc.put_signed(e.second, 1);
  }
  std::vector<uint8_t> block = enc.finish();
  block.resize(block.size() + f.extra_block_bytes, 0);
  w.varint(block.size());
  w.bytes(block);
  return w.buffer();
}

TEST(AnalogLattice, GivenHandWrittenTableThenEntriesFollowTheLattice) {
  const ChannelRepr r = read(build(Fields()), 10, true);
  ASSERT_EQ(r.table.size(), 3u);
  EXPECT_EQ(r.table[0], 1.0);
  EXPECT_EQ(r.table[1], 2.0);
  EXPECT_EQ(r.table[2], 3.0);
  Fields moved;
  moved.entries = {{1, 1}, {2, -1}};  // 2.0 one float32 unit up, then + 2 steps one unit down
  const ChannelRepr q = read(build(moved), 10, true);
  EXPECT_EQ(q.table[1], static_cast<double>(std::nextafter(2.0f, 3.0f)));
  EXPECT_EQ(q.table[2], static_cast<double>(std::nextafter(
                            static_cast<float>(static_cast<double>(q.table[1]) + 2.0), 0.0f)));
}

TEST(AnalogLattice, GivenDamagedFieldsThenCorruptNeverCrash) {
  auto corrupt = [](const Fields& f, size_t n) {
    const std::vector<uint8_t> h = build(f);
    ByteReader in(h.data(), h.size(), "test header");
    HeaderRules rules;
    rules.lattice = true;
    HeaderState state;
    KeptRows kept;
    try {
      read_repr_header(&in, n, rules, &state, &kept);
    } catch (const Error& e) {
      EXPECT_EQ(e.code(), ErrorCode::kCorrupt);
      return true;
    }
    return false;
  };
  EXPECT_FALSE(corrupt(Fields(), 10));
  Fields f;
  f.flag = 7;  // above 3
  EXPECT_TRUE(corrupt(f, 10));
  EXPECT_TRUE(corrupt(Fields(), 2));  // m = 3 entries for 2 samples
  f = Fields();
  f.m = 1;  // a lattice table has at least 2 entries
  f.entries.clear();
  EXPECT_TRUE(corrupt(f, 10));
  for (double s : {0.0, -1.0, std::numeric_limits<double>::quiet_NaN(),
                   std::numeric_limits<double>::infinity()}) {
    f = Fields();
    f.step = s;
    EXPECT_TRUE(corrupt(f, 10)) << s;
  }
  f = Fields();
  f.first = uint64_t{1} << 32;  // float32 pattern out of range
  EXPECT_TRUE(corrupt(f, 10));
  f = Fields();
  f.entries = {{1, 0}, {0, 0}};  // entry 2 equals entry 1: not increasing
  EXPECT_TRUE(corrupt(f, 10));
  f = Fields();
  f.entries = {{1, 0}, {1, -(1 << 30)}};  // far below the previous entry
  EXPECT_TRUE(corrupt(f, 10));
  f = Fields();
  f.flag = 2;  // a double table whose prediction 1 + 4e9 * 1e300 is not finite
  f.step = 1e300;
  f.first = ordered_bits(bits_of(1.0));
  f.entries = {{4000000000u, 0}, {1, 0}};
  EXPECT_TRUE(corrupt(f, 10));
  f = Fields();
  f.entries = {{1, 0}};  // one entry short: the block ends early
  EXPECT_TRUE(corrupt(f, 10));
  f = Fields();
  f.extra_block_bytes = 4;  // bytes left over in the block
  EXPECT_TRUE(corrupt(f, 10));
}

}  // namespace
}  // namespace analog
}  // namespace capz
