// Checksums: flipping any single bit of a small .capz stream is either detected (capz::Error
// whose message names the damaged chunk, or the magic/version for the 11-byte file header) or
// harmless (the stream decodes to the identical take).
#include <gtest/gtest.h>

#include <cmath>
#include <cstdio>
#include <string>
#include <vector>

#include "capz/codec.h"
#include "capz/error.h"
#include "test_util.h"

namespace {

capz::Take small_take() {
  capz::Take t;
  t.source = "flip";
  t.format = capz::Format::kTRC;
  t.resize(12, 3);
  t.rate = 60;
  t.units = "mm";
  t.labels = {"A", "B", "C"};
  for (size_t f = 0; f < t.frames; ++f)
    for (size_t p = 0; p < t.points; ++p) {
      if ((f + p) % 7 == 3) continue;  // a few gaps, so the stream has MASK chunks
      double* x = t.at(f, p);
      x[0] = 100.0 * p + 3.25 * std::sin(0.3 * static_cast<double>(f));
      x[1] = -20.0 + 0.5 * static_cast<double>(f);
      x[2] = 900.0 + 10.0 * p;
      t.valid[f * t.points + p] = 1;
    }
  return t;
}

void check_every_flip(const std::vector<uint8_t>& stream, const capz::Take& ref) {
  size_t detected = 0, harmless = 0;
  std::vector<uint8_t> s = stream;
  for (size_t byte = 0; byte < s.size(); ++byte) {
    for (int bit = 0; bit < 8; ++bit) {
      s[byte] ^= static_cast<uint8_t>(1u << bit);
      try {
        capz::Take b = capz::decompress(s.data(), s.size(), "flipped.capz");
        // Not detected: it must be harmless.
        ASSERT_EQ(b.frames, ref.frames) << "byte " << byte << " bit " << bit;
        ASSERT_EQ(b.points, ref.points) << "byte " << byte << " bit " << bit;
        ASSERT_EQ(b.valid, ref.valid) << "byte " << byte << " bit " << bit;
        ASSERT_EQ(b.xyz, ref.xyz) << "byte " << byte << " bit " << bit;
        ASSERT_EQ(b.labels, ref.labels) << "byte " << byte << " bit " << bit;
        ASSERT_EQ(b.units, ref.units) << "byte " << byte << " bit " << bit;
        ASSERT_EQ(b.rate, ref.rate) << "byte " << byte << " bit " << bit;
        ++harmless;
      } catch (const capz::Error& e) {
        const std::string m = e.what();
        const bool names_it = byte < 11 ? (m.find("magic") != std::string::npos ||
                                           m.find("version") != std::string::npos ||
                                           m.find("not a .capz") != std::string::npos)
                                        : m.find("chunk") != std::string::npos;
        EXPECT_TRUE(names_it) << "byte " << byte << " bit " << bit << ": " << m;
        ++detected;
      }
      s[byte] ^= static_cast<uint8_t>(1u << bit);
    }
  }
  EXPECT_EQ(detected + harmless, stream.size() * 8);
  // Only the minor version byte can be harmless in so small a stream; everything else is CRC'd.
  EXPECT_LE(harmless, 8u);
  std::printf("%zu bytes: %zu flips detected, %zu harmless\n", stream.size(), detected, harmless);
}

}  // namespace

TEST(BitFlips, EveryFlipInALossyStreamIsDetectedOrHarmless) {
  capz::Take t = small_take();
  capz::CompressOptions o;
  o.max_error = 0.01;
  o.window_frames = 5;  // several windows: several POSW/MASK chunks and a real INDX
  std::vector<uint8_t> s = capz::compress(t, o);
  capz::Take ref = capz::decompress(s.data(), s.size(), "ref");
  check_every_flip(s, ref);
}

TEST(BitFlips, EveryFlipInALosslessStreamIsDetectedOrHarmless) {
  capz::Take t = small_take();
  capz::CompressOptions o;
  o.lossless = true;
  std::vector<uint8_t> s = capz::compress(t, o);
  capz::Take ref = capz::decompress(s.data(), s.size(), "ref");
  capz_test::expect_same_samples(t, ref);
  check_every_flip(s, ref);
}
