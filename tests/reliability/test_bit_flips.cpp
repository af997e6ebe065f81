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
#include "capz/io.h"
#include "coding/c3d_params.h"
#include "coding/container.h"
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
        ASSERT_EQ(b.analog.values, ref.analog.values) << "byte " << byte << " bit " << bit;
        ASSERT_EQ(b.analog.labels, ref.analog.labels) << "byte " << byte << " bit " << bit;
        ASSERT_EQ(!b.c3d, !ref.c3d) << "byte " << byte << " bit " << bit;
        if (ref.c3d) {
          ASSERT_EQ(b.c3d->residual, ref.c3d->residual) << "byte " << byte << " bit " << bit;
          ASSERT_EQ(b.c3d->camera_mask, ref.c3d->camera_mask) << "byte " << byte << " bit " << bit;
          ASSERT_EQ(capz::encode_c3d_parameters(*b.c3d), capz::encode_c3d_parameters(*ref.c3d))
              << "byte " << byte << " bit " << bit;
        }
        ++harmless;
      } catch (const capz::Error& e) {
        const std::string m = e.what();
        // The file header (magic, version, and from 4.0 its CRC) names what it is; a flipped
        // major byte that lands below 4 drops the header CRC, so the next chunk fails to parse.
        const size_t header = capz::file_header_bytes(stream[9]);
        const bool names_it =
            (byte < header &&
             (m.find("magic") != std::string::npos || m.find("version") != std::string::npos ||
              m.find("header") != std::string::npos ||
              m.find("not a .capz") != std::string::npos)) ||
            ((byte == 9 || byte >= header) && m.find("chunk") != std::string::npos);
        EXPECT_TRUE(names_it) << "byte " << byte << " bit " << bit << ": " << m;
        ++detected;
      }
      s[byte] ^= static_cast<uint8_t>(1u << bit);
    }
  }
  EXPECT_EQ(detected + harmless, stream.size() * 8);
  // Only the minor version byte can be harmless in so small a stream (of a 3.x stream; from 4.0
  // the file header has a CRC too); everything else is CRC'd.
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

// A real C3D cut to 8 frames (24 points with gaps, int16 storage, 16 analog channels, a full
// parameter section), lossy in windows of 3 frames with the ts codec: every chunk type a C3D
// stream has (META with the parameter section, C3DW, ANLG, MASK, POSW with a codec payload).
TEST(BitFlips, EveryFlipInAC3DStreamWithAnalogAndParametersIsDetectedOrHarmless) {
  capz::Take t = capz::read_take(std::string(CAPZ_TEST_DIR) +
                                 "/fuzz/corpus/read_c3d/"
                                 "seed-btkdata-others-ADemo1_rewrite_c3d_pc_integer.c3d");
  ASSERT_GT(t.analog.channels, 0);
  ASSERT_GT(t.gap_samples(), 0u);
  capz::CompressOptions o;
  o.max_error = 0.5;  // mm
  o.window_frames = 3;
  o.codec = "ts";
  std::vector<uint8_t> s = capz::compress(t, o);
  capz::Take ref = capz::decompress(s.data(), s.size(), "ref");
  ASSERT_EQ(ref.analog.values, t.analog.values);
  check_every_flip(s, ref);
}
