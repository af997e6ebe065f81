// Range coder and integer entropy coding: exact round trips and clean failure on bad blocks.
#include <gtest/gtest.h>

#include <cmath>
#include <map>
#include <random>

#include "coding/entropy.h"

namespace capz {
namespace {

TEST(Entropy, GivenEmptyStreamWhenRoundTrippedThenEmpty) {
  auto block = encode_ints({});
  EXPECT_EQ(decode_ints(block.data(), block.size(), 0).size(), 0u);
}

TEST(Entropy, GivenUniformRandomInt32WhenRoundTrippedThenExact) {
  std::mt19937 rng(1);
  std::vector<int32_t> v(20000);
  for (auto& x : v) x = static_cast<int32_t>(rng());
  v.push_back(INT32_MIN);
  v.push_back(INT32_MAX);
  v.push_back(0);
  auto block = encode_ints(v);
  EXPECT_EQ(decode_ints(block.data(), block.size(), v.size()), v);
  // Incompressible: about 4 bytes a value, never much more.
  EXPECT_LT(block.size(), v.size() * 4 + v.size() / 10);
}

TEST(Entropy, GivenSkewedLaplacianStreamWhenRoundTrippedThenExactAndNearEntropy) {
  std::mt19937 rng(2);
  std::exponential_distribution<double> ex(0.5);
  std::bernoulli_distribution sign(0.5);
  std::vector<int32_t> v(100000);
  std::vector<double> hist(200, 0);
  for (auto& x : v) {
    int m = static_cast<int>(ex(rng));
    x = sign(rng) ? m : -m;
  }
  auto block = encode_ints(v);
  EXPECT_EQ(decode_ints(block.data(), block.size(), v.size()), v);
  // Empirical entropy of the values.
  std::map<int32_t, double> h;
  for (auto x : v) h[x] += 1;
  double bits = 0;
  for (auto& kv : h) bits -= kv.second * std::log2(kv.second / v.size());
  EXPECT_LT(block.size() * 8.0, bits * 1.05 + 256);
}

TEST(Entropy, GivenAllZerosWhenCodedThenTiny) {
  std::vector<int32_t> v(1000000, 0);
  auto block = encode_ints(v);
  EXPECT_LT(block.size(), 2000u);
  EXPECT_EQ(decode_ints(block.data(), block.size(), v.size()), v);
}

TEST(Entropy, GivenUnsignedStreamWithContextsWhenRoundTrippedThenExact) {
  std::mt19937 rng(3);
  std::vector<uint32_t> v(30000);
  for (size_t i = 0; i < v.size(); ++i) v[i] = (i % 3 == 0) ? rng() : rng() % 7;
  auto block = encode_uints(v);
  EXPECT_EQ(decode_uints(block.data(), block.size(), v.size()), v);

  // The class API with caller contexts and raw-bit fields interleaved.
  IntEncoder enc(3);
  for (size_t i = 0; i < v.size(); ++i) {
    enc.put(v[i], static_cast<int>(i % 3));
    enc.raw_bits(static_cast<uint32_t>(i) & 0x1FFFFF, 21);
  }
  auto b2 = enc.finish();
  IntDecoder dec(b2.data(), b2.size(), 3, "test");
  for (size_t i = 0; i < v.size(); ++i) {
    ASSERT_EQ(dec.get(static_cast<int>(i % 3)), v[i]);
    ASSERT_EQ(dec.raw_bits(21), static_cast<uint32_t>(i) & 0x1FFFFF);
  }
  EXPECT_TRUE(dec.at_end());
}

TEST(Entropy, GivenSymbolModelWithSmallAlphabetWhenRoundTrippedThenExact) {
  std::mt19937 rng(4);
  std::vector<int> s(50000);
  for (auto& x : s) x = (rng() % 10 == 0) ? static_cast<int>(rng() % 5) : 0;
  RangeEncoder enc;
  SymbolModel m;
  for (int x : s) m.encode(&enc, x);
  auto block = enc.finish();
  RangeDecoder dec(block.data(), block.size(), "test");
  SymbolModel m2;
  for (int x : s) ASSERT_EQ(m2.decode(&dec), x);
  EXPECT_TRUE(dec.at_end());
}

TEST(Entropy, GivenTruncatedBlockWhenDecodedThenThrowsCorrupt) {
  std::mt19937 rng(5);
  std::vector<int32_t> v(5000);
  for (auto& x : v) x = static_cast<int32_t>(rng() % 1000) - 500;
  auto block = encode_ints(v);
  for (size_t cut : {size_t{0}, size_t{1}, size_t{4}, block.size() / 2, block.size() - 1}) {
    try {
      decode_ints(block.data(), cut, v.size(), "cut");
      FAIL() << "no error at cut " << cut;
    } catch (const Error& e) {
      EXPECT_EQ(e.code(), ErrorCode::kCorrupt);
    }
  }
}

TEST(Entropy, GivenBitFlipsWhenDecodedThenCleanErrorOrSomeValues) {
  std::mt19937 rng(6);
  std::vector<int32_t> v(2000);
  for (auto& x : v) x = static_cast<int32_t>(rng() % 100) - 50;
  auto block = encode_ints(v);
  for (int trial = 0; trial < 500; ++trial) {
    auto bad = block;
    bad[rng() % bad.size()] ^= static_cast<uint8_t>(1u << (rng() % 8));
    try {
      auto out = decode_ints(bad.data(), bad.size(), v.size());
      EXPECT_EQ(out.size(), v.size());
    } catch (const Error& e) {
      EXPECT_EQ(e.code(), ErrorCode::kCorrupt);
    }
  }
}

TEST(Entropy, GivenImplausibleCountWhenDecodedThenThrowsBeforeAllocating) {
  auto block = encode_ints({1, 2, 3});
  EXPECT_THROW(decode_ints(block.data(), block.size(), size_t{1} << 40), Error);
}

}  // namespace
}  // namespace capz

namespace capz {
namespace {

TEST(EntropyBytes, GivenTextAndBinaryBytesWhenRoundTrippedThenExactAndTextShrinks) {
  std::string text;
  for (int i = 0; i < 200; ++i)
    text += "POINT:LABELS RightKnee LeftKnee " + std::to_string(i) + "    ";
  std::vector<uint8_t> t(text.begin(), text.end());
  auto block = encode_bytes(t.data(), t.size());
  EXPECT_LT(block.size(), t.size() / 2);
  EXPECT_EQ(decode_bytes(block.data(), block.size(), t.size(), "bytes"), t);
  std::mt19937 rng(12);
  std::vector<uint8_t> r(5000);
  for (auto& b : r) b = static_cast<uint8_t>(rng());
  auto rb = encode_bytes(r.data(), r.size());
  EXPECT_EQ(decode_bytes(rb.data(), rb.size(), r.size(), "bytes"), r);
  EXPECT_THROW(decode_bytes(rb.data(), rb.size() / 2, r.size(), "bytes"), Error);
  EXPECT_THROW(decode_bytes(rb.data(), rb.size(), size_t{1} << 40, "bytes"), Error);
}

}  // namespace
}  // namespace capz
