// LZF decompression (coding/lzf.h) against the format's rule read byte by byte: every kind of
// run (literals of 1 to 32 bytes, copies of 3 to 264 bytes from 1 to 8192 back, overlapping or
// not) at every distance from the output's end, where the decoder's wide copies must not be
// used; malformed streams refused as the rule refuses them; and lzf_decompress_prefix, which the
// PCD reader uses to decompress a body's coordinate planes alone.
#include <gtest/gtest.h>

#include <cstdint>
#include <random>
#include <vector>

#include "coding/lzf.h"

namespace {

// The rule, one byte at a time (the decoder as it was before its wide copies): the bytes the
// stream gives, or false when a run is malformed, reaches before the start or past `size`, or
// the stream gives other than `size` bytes.
bool reference(const std::vector<uint8_t>& in, size_t size, std::vector<uint8_t>* out) {
  out->clear();
  size_t p = 0;
  while (p < in.size()) {
    const size_t c = in[p++];
    if (c < 32) {
      if (c + 1 > in.size() - p || c + 1 > size - out->size()) return false;
      for (size_t k = 0; k <= c; ++k) out->push_back(in[p++]);
      continue;
    }
    size_t len = (c >> 5) + 2;
    if ((c >> 5) == 7) {
      if (p >= in.size()) return false;
      len += in[p++];
    }
    if (p >= in.size()) return false;
    const size_t dist = ((c & 31) << 8) + in[p++] + 1;
    if (dist > out->size() || len > size - out->size()) return false;
    for (size_t k = 0; k < len; ++k) out->push_back((*out)[out->size() - dist]);
  }
  return out->size() == size;
}

// A stream of random runs giving about `target` bytes (its exact size in *size): literals of
// 1 to 32 bytes, copies of 3 to 264 bytes from up to 8192 back (short distances often, so copies
// overlap what they write).
std::vector<uint8_t> random_stream(std::mt19937& rng, size_t target, size_t* size) {
  std::vector<uint8_t> s;
  size_t o = 0;
  while (o < target) {
    if (o == 0 || rng() % 3 == 0) {
      const size_t n = 1 + rng() % 32;
      s.push_back(static_cast<uint8_t>(n - 1));
      for (size_t k = 0; k < n; ++k) s.push_back(static_cast<uint8_t>(rng()));
      o += n;
      continue;
    }
    const size_t len = rng() % 4 == 0 ? 3 + rng() % 262 : 3 + rng() % 20;
    const size_t most = std::min<size_t>(o, 8192);
    const size_t dist = rng() % 2 ? 1 + rng() % std::min<size_t>(most, 20) : 1 + rng() % most;
    const size_t l = len - 2, off = dist - 1;
    if (l < 7) {
      s.push_back(static_cast<uint8_t>(l << 5 | off >> 8));
    } else {
      s.push_back(static_cast<uint8_t>(7 << 5 | off >> 8));
      s.push_back(static_cast<uint8_t>(l - 7));
    }
    s.push_back(static_cast<uint8_t>(off & 255));
    o += len;
  }
  *size = o;
  return s;
}

TEST(LzfDecompress, EveryRunKindGivesTheRulesBytes) {
  std::mt19937 rng(7);
  for (int trial = 0; trial < 300; ++trial) {
    size_t size = 0;
    const std::vector<uint8_t> s = random_stream(rng, 1 + rng() % 20000, &size);
    std::vector<uint8_t> want;
    ASSERT_TRUE(reference(s, size, &want));
    // The output exactly sized: the wide copies are refused near its end.
    std::vector<uint8_t> got(size);
    ASSERT_TRUE(capz::lzf_decompress_into(s.data(), s.size(), got.data(), got.size()));
    EXPECT_EQ(got, want) << "trial " << trial;
    // Too small or too large an output, or a stream cut short: refused.
    std::vector<uint8_t> wrong(size + 1);
    EXPECT_FALSE(capz::lzf_decompress_into(s.data(), s.size(), wrong.data(), size - 1));
    EXPECT_FALSE(capz::lzf_decompress_into(s.data(), s.size(), wrong.data(), size + 1));
    EXPECT_FALSE(capz::lzf_decompress_into(s.data(), s.size() - 1, wrong.data(), size));
  }
}

TEST(LzfDecompress, MalformedStreamsAreRefusedAsTheRuleRefusesThem) {
  std::mt19937 rng(11);
  for (int trial = 0; trial < 3000; ++trial) {
    std::vector<uint8_t> s(1 + rng() % 200);
    for (uint8_t& b : s) b = static_cast<uint8_t>(rng() % 4 == 0 ? rng() % 32 : rng());
    const size_t size = rng() % 400;
    std::vector<uint8_t> want, got(size + 1);
    const bool ok = reference(s, size, &want);
    ASSERT_EQ(capz::lzf_decompress_into(s.data(), s.size(), got.data(), size), ok) << trial;
    if (ok) {
      EXPECT_EQ(std::vector<uint8_t>(got.begin(), got.begin() + long(size)), want);
    }
  }
}

// Long streams (their runs mostly far from the buffers' ends) with one byte changed: a copy from
// before the start, a run past the output's end, or another output size, refused as the rule
// refuses it; else the rule's bytes.
TEST(LzfDecompress, LongStreamsWithAByteChangedAreReadAsTheRuleReadsThem) {
  std::mt19937 rng(5);
  size_t refused = 0;
  for (int trial = 0; trial < 400; ++trial) {
    size_t size = 0;
    std::vector<uint8_t> s = random_stream(rng, 2000 + rng() % 6000, &size);
    s[rng() % (s.size() / 4)] = static_cast<uint8_t>(rng());
    const size_t out_size = trial % 2 ? size : size + 300;
    std::vector<uint8_t> want, got(out_size);
    const bool ok = reference(s, out_size, &want);
    refused += !ok;
    ASSERT_EQ(capz::lzf_decompress_into(s.data(), s.size(), got.data(), out_size), ok) << trial;
    if (ok) {
      EXPECT_EQ(got, want) << trial;
    }
  }
  EXPECT_GT(refused, 100u);
}

TEST(LzfDecompress, PrefixGivesTheFirstBytesAlone) {
  std::mt19937 rng(3);
  size_t size = 0;
  const std::vector<uint8_t> s = random_stream(rng, 30000, &size);
  std::vector<uint8_t> want;
  ASSERT_TRUE(reference(s, size, &want));
  for (size_t prefix :
       {size_t{0}, size_t{1}, size_t{31}, size_t{4096}, size / 3, size - 1, size, size + 5}) {
    std::vector<uint8_t> got(size);
    ASSERT_TRUE(capz::lzf_decompress_prefix(s.data(), s.size(), got.data(), size, prefix));
    const size_t m = std::min(prefix, size);
    EXPECT_TRUE(std::equal(got.begin(), got.begin() + long(m), want.begin())) << prefix;
  }
  // The runs after the prefix are not read: a stream broken after the run that ends at or past
  // the middle of the stream still gives the bytes before that, and not one more.
  size_t cut = 0, before = 0;  // a run boundary in the stream, and the bytes the runs before give
  while (cut < s.size() / 2) {
    const size_t c = s[cut++];
    if (c < 32) {
      cut += c + 1, before += c + 1;
      continue;
    }
    before += (c >> 5) + 2 + ((c >> 5) == 7 ? s[cut++] : 0);
    ++cut;
  }
  std::vector<uint8_t> broken(s.begin(), s.begin() + long(cut));
  broken.push_back(31);  // a run of 32 literals with one byte left in the stream
  broken.push_back(0);
  std::vector<uint8_t> out, got(size);
  ASSERT_FALSE(reference(broken, size, &out));
  ASSERT_EQ(out.size(), before);
  ASSERT_GT(before, 100u);
  EXPECT_FALSE(capz::lzf_decompress_into(broken.data(), broken.size(), got.data(), size));
  EXPECT_TRUE(capz::lzf_decompress_prefix(broken.data(), broken.size(), got.data(), size, before));
  EXPECT_TRUE(std::equal(got.begin(), got.begin() + long(before), want.begin()));
  EXPECT_FALSE(
      capz::lzf_decompress_prefix(broken.data(), broken.size(), got.data(), size, before + 1));
}

}  // namespace
