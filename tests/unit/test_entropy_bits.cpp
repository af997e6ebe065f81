// Binary models and zero-first values (docs/FORMAT.md 2.8): the rule as written, round trips
// beside plain tokens, the cost floor behind the 2900-values-a-byte bound, and corrupt blocks.
#include <gtest/gtest.h>

#include <random>
#include <vector>

#include "coding/entropy.h"

namespace capz {
namespace {

// FORMAT.md 2.8 read literally: q of a 0 in 2^-22 from 2^21, coded as q >> 7 within [64,
// 2^15 - 64], the rate by the bits coded so far (4 for 16, 5 for the next 48, 6 for the next
// 192, then 7).
struct SpecBit {
  uint32_t q = 1u << 21;
  int n = 0;
  void code(RangeEncoder* rc, bool bit) {
    uint32_t p = q >> 7;
    if (p < 64) p = 64;
    if (p > (1u << 15) - 64) p = (1u << 15) - 64;
    if (bit)
      rc->encode(p, (1u << 15) - p);
    else
      rc->encode(0, p);
    const int rate = n < 16 ? 4 : n < 64 ? 5 : n < 256 ? 6 : 7;
    ++n;
    if (bit)
      q -= q >> rate;
    else
      q += ((1u << 22) - q) >> rate;
  }
};

// A block of bits only (no raw part): IntEncoder's finish() is varint(n), the range part.
std::vector<uint8_t> range_part(std::vector<uint8_t> block) {
  size_t at = 0;
  while (block[at] & 0x80) ++at;
  return std::vector<uint8_t>(block.begin() + static_cast<std::ptrdiff_t>(at) + 1, block.end());
}

TEST(EntropyBits, GivenBitsWhenCodedThenTheBytesOfFormatsRule) {
  std::mt19937 rng(11);
  for (double zeros : {0.5, 0.9, 0.999, 0.02}) {
    std::bernoulli_distribution one(1.0 - zeros);
    IntEncoder enc(2);
    enc.add_bit_models();
    RangeEncoder ref;
    SpecBit m[2];
    for (int i = 0; i < 4000; ++i) {
      const bool b = one(rng);
      const int ctx = i % 3 == 0;
      enc.put_bit(b, ctx);
      m[ctx].code(&ref, b);
    }
    EXPECT_EQ(range_part(enc.finish()), ref.finish()) << zeros;
  }
}

TEST(EntropyBits, GivenZeroFirstAndPlainValuesWhenRoundTrippedThenExact) {
  std::mt19937 rng(12);
  std::geometric_distribution<uint32_t> small(0.6);
  std::bernoulli_distribution zero(0.85);
  struct V {
    int kind, ctx;
    uint32_t u;
  };
  std::vector<V> vs;
  for (int i = 0; i < 30000; ++i) {
    const int kind = static_cast<int>(rng() % 3), ctx = static_cast<int>(rng() % 5);
    uint32_t u = kind == 0 ? rng() % 2 : zero(rng) ? 0 : small(rng);
    if (i % 1000 == 7) u = kind == 0 ? 1 : 0xFFFFFFFFu;  // the largest value either codes
    vs.push_back({kind, ctx, u});
  }
  IntEncoder enc(5);
  enc.add_bit_models();
  for (const V& v : vs) {
    if (v.kind == 0) enc.put_bit(v.u != 0, v.ctx);
    if (v.kind == 1) enc.put_zero_first(v.u, v.ctx);
    if (v.kind == 2) enc.put(v.u, v.ctx);
  }
  const std::vector<uint8_t> block = enc.finish();
  IntDecoder dec(block.data(), block.size(), 5, "test");
  dec.add_bit_models();
  IntDecoder::Cursor c = dec.cursor();
  for (const V& v : vs) {
    int tok;
    const uint32_t u = v.kind == 0   ? c.get_bit(v.ctx)
                       : v.kind == 1 ? c.get_zero_first(v.ctx)
                                     : c.get(v.ctx, &tok);
    ASSERT_EQ(u, v.u);
  }
  dec.commit(c);
  EXPECT_TRUE(dec.at_end());
}

// A bit costs more than 1/360 bit, whatever came before: a million zeros need at least
// 10^6 / 2900 bytes.
TEST(EntropyBits, GivenOnlyZerosWhenCodedThenAboveTheBoundsFloor) {
  IntEncoder enc(1);
  enc.add_bit_models();
  const size_t n = 1000000;
  for (size_t i = 0; i < n; ++i) enc.put_zero_first(0, 0);
  const std::vector<uint8_t> block = enc.finish();
  EXPECT_GE(block.size() * kMaxSymbolsPerByte, n);
  EXPECT_LT(block.size(), n / 2000);  // and still about the floor's cost, 0.0028 bit
  IntDecoder dec(block.data(), block.size(), 1, "zeros");
  dec.add_bit_models();
  IntDecoder::Cursor c = dec.cursor();
  for (size_t i = 0; i < n; ++i) ASSERT_EQ(c.get_zero_first(0), 0u);
}

TEST(EntropyBits, GivenZeroFirstOfTwoToThe32WhenDecodedThenCorrupt) {
  IntEncoder enc(1);
  enc.add_bit_models();
  enc.put_bit(true, 0);
  enc.put(0xFFFFFFFFu, 0);  // u - 1 = 2^32 - 1: u would not fit
  const std::vector<uint8_t> block = enc.finish();
  IntDecoder dec(block.data(), block.size(), 1, "big");
  dec.add_bit_models();
  IntDecoder::Cursor c = dec.cursor();
  try {
    c.get_zero_first(0);
    FAIL() << "no error";
  } catch (const Error& e) {
    EXPECT_EQ(e.code(), ErrorCode::kCorrupt);
    EXPECT_NE(std::string(e.what()).find("big"), std::string::npos);
  }
}

TEST(EntropyBits, GivenBitFlipsWhenDecodedThenCleanErrorOrValues) {
  std::mt19937 rng(13);
  IntEncoder enc(3);
  enc.add_bit_models();
  std::vector<uint32_t> v(3000);
  for (auto& x : v) x = rng() % 4 == 0 ? rng() % 40 : 0;
  for (size_t i = 0; i < v.size(); ++i) enc.put_zero_first(v[i], static_cast<int>(i % 3));
  const std::vector<uint8_t> block = enc.finish();
  int errors = 0;
  for (int trial = 0; trial < 300; ++trial) {
    std::vector<uint8_t> bad = block;
    bad[1 + rng() % (bad.size() - 1)] ^= static_cast<uint8_t>(1u << (rng() % 8));
    try {
      IntDecoder dec(bad.data(), bad.size(), 3, "flip");
      dec.add_bit_models();
      IntDecoder::Cursor c = dec.cursor();
      for (size_t i = 0; i < v.size(); ++i) c.get_zero_first(static_cast<int>(i % 3));
      dec.commit(c);
      if (!dec.at_end()) ++errors;
    } catch (const Error& e) {
      EXPECT_EQ(e.code(), ErrorCode::kCorrupt);
      ++errors;
    }
  }
  EXPECT_GT(errors, 0);
}

}  // namespace
}  // namespace capz
