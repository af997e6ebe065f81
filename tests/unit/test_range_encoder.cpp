// The range encoder's and bit writer's branch-free output paths against the classic loops they
// replaced (same bytes), and IntEncoder::Cursor::bytes_out as the finished size.
#include <gtest/gtest.h>

#include <random>

#include "coding/bytes.h"
#include "coding/entropy.h"

namespace capz {
namespace {

// The cache-and-pending range encoder (LZMA's) that RangeEncoder::Core was before it wrote its
// bytes directly; counts the carries it passed through held-back 0xFF bytes.
struct ClassicRangeEncoder {
  uint64_t low = 0;
  uint32_t range = 0xFFFFFFFFu;
  uint8_t cache = 0;
  uint64_t pending = 1;
  std::vector<uint8_t> out;
  int carries_through_ff = 0;

  void encode(uint32_t start, uint32_t freq) {
    const uint32_t r = range >> kTotalBits;
    low += static_cast<uint64_t>(r) * start;
    range = r * freq;
    while (range < kTopValue) {
      range <<= 8;
      shift_low();
    }
  }
  void shift_low() {
    if (static_cast<uint32_t>(low) < 0xFF000000u || (low >> 32) != 0) {
      const uint8_t carry = static_cast<uint8_t>(low >> 32);
      if (carry && pending > 1) ++carries_through_ff;
      uint8_t temp = cache;
      do {
        out.push_back(static_cast<uint8_t>(temp + carry));
        temp = 0xFF;
      } while (--pending != 0);
      cache = static_cast<uint8_t>(static_cast<uint32_t>(low) >> 24);
    }
    ++pending;
    low = static_cast<uint32_t>(static_cast<uint32_t>(low) << 8);
  }
  std::vector<uint8_t> finish() {
    for (int i = 0; i < 5; ++i) shift_low();
    return out;
  }
};

// Intervals of every width: wide ones (no byte out), narrow ones (two bytes out at once), and
// stretches at the top of the range, which make runs of 0xFF bytes and carries through them.
struct Interval {
  uint32_t start, freq;
};
std::vector<Interval> random_intervals(uint32_t seed, size_t n) {
  std::mt19937 rng(seed);
  std::vector<Interval> v(n);
  for (Interval& iv : v) {
    const int kind = static_cast<int>(rng() % 8);
    uint32_t freq;
    if (kind < 3)
      freq = 1 + rng() % 16;  // narrow
    else if (kind < 6)
      freq = 1 + rng() % kTotal;
    else
      freq = kTotal - rng() % 64;  // nearly the whole range
    freq = std::min(freq, kTotal);
    const uint32_t start = kind == 7 ? kTotal - freq : rng() % (kTotal - freq + 1);
    iv = {start, freq};
  }
  return v;
}

TEST(RangeEncoder, GivenRandomIntervalsWhenCodedThenClassicCodersBytes) {
  int carries = 0;
  for (uint32_t seed = 1; seed <= 40; ++seed) {
    const std::vector<Interval> iv = random_intervals(seed, 1 + 5000 * (seed % 7));
    ClassicRangeEncoder ref;
    RangeEncoder enc;
    for (size_t i = 0; i < iv.size(); ++i) {
      ref.encode(iv[i].start, iv[i].freq);
      enc.encode(iv[i].start, iv[i].freq);
      // Whenever it is asked, the finished size: what the classic coder's flush would give.
      if (i % 997 == 0) {
        ClassicRangeEncoder copy = ref;
        ASSERT_EQ(enc.bytes_so_far(), copy.finish().size()) << "seed " << seed << " at " << i;
      }
    }
    const std::vector<uint8_t> want = ref.finish();
    ASSERT_EQ(enc.finish(), want) << "seed " << seed;
    carries += ref.carries_through_ff;
    // The encoder is reset by finish: the same intervals again give the same bytes.
    for (const Interval& x : iv) enc.encode(x.start, x.freq);
    ASSERT_EQ(enc.finish(), want) << "seed " << seed << ", second block";
  }
  EXPECT_GT(carries, 0) << "no carry passed a 0xFF byte: the test misses that path";
}

TEST(RangeEncoder, GivenNothingCodedWhenFinishedThenFiveZeros) {
  RangeEncoder enc;
  EXPECT_EQ(enc.finish(), std::vector<uint8_t>(5, 0));
  EXPECT_EQ(ClassicRangeEncoder().finish(), std::vector<uint8_t>(5, 0));
}

TEST(RangeEncoder, GivenRandomFieldsWhenWrittenThenBitLoopsBytes) {
  std::mt19937 rng(7);
  for (int round = 0; round < 20; ++round) {
    BitWriter w;
    std::vector<uint8_t> want;
    uint64_t acc = 0;
    int bits = 0;
    const int n = 1 + static_cast<int>(rng() % 20000);
    for (int i = 0; i < n; ++i) {
      const int nb = static_cast<int>(rng() % 33);
      const uint32_t v = nb == 32 ? rng() : rng() & ((1u << nb) - 1);
      w.put(v, nb);
      acc |= static_cast<uint64_t>(v) << bits;
      bits += nb;
      while (bits >= 8) {
        want.push_back(static_cast<uint8_t>(acc));
        acc >>= 8;
        bits -= 8;
      }
    }
    if (bits > 0) want.push_back(static_cast<uint8_t>(acc));
    ASSERT_EQ(w.finish(), want) << "round " << round;
  }
}

// bytes_out() is what finish() would give after the varint, at every point: the trials of the
// analog encoder stop on it, so it must never exceed the finished size (and should not lag).
TEST(RangeEncoder, GivenIntEncoderWhenAskedMidwayThenBytesOutIsTheFinishedSize) {
  std::mt19937 rng(9);
  std::vector<uint32_t> u(30000);
  for (size_t i = 0; i < u.size(); ++i)
    u[i] = i % 5 == 0 ? rng() >> (rng() % 32) : rng() % (1 + i % 40);
  std::vector<size_t> at;
  {
    IntEncoder enc(4);
    IntEncoder::Cursor c = enc.cursor();
    for (size_t i = 0; i < u.size(); ++i) {
      c.put(u[i], static_cast<int>(i % 4));
      if (i % 3 == 0) c.raw_bits(static_cast<uint32_t>(i) & 0x1F, 5);
      if (i % 1000 == 999) at.push_back(c.bytes_out());
    }
  }
  for (size_t k = 0; k < at.size(); ++k) {
    const size_t stop = 1000 * (k + 1);
    IntEncoder enc(4);
    IntEncoder::Cursor c = enc.cursor();
    for (size_t i = 0; i < stop; ++i) {
      c.put(u[i], static_cast<int>(i % 4));
      if (i % 3 == 0) c.raw_bits(static_cast<uint32_t>(i) & 0x1F, 5);
    }
    enc.commit(c);
    const std::vector<uint8_t> block = enc.finish();
    ByteReader r(block.data(), block.size(), "test");
    const uint64_t rc_bytes = r.varint();
    ASSERT_EQ(block.size() - r.offset(), at[k]) << "after " << stop << " values";
    ASSERT_LT(rc_bytes, at[k]);
  }
}

}  // namespace
}  // namespace capz
