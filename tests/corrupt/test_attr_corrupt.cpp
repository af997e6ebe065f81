// Damaged ATTR chunks (docs/FORMAT.md 13, 13.4): every byte of a window's ATTR payload changed, its
// chunk CRC recomputed so only the payload's own checks can tell: decoding throws a capz::Error
// or gives a take (the change hit a value, which only a checksum could catch); never a crash,
// never unbounded memory. A missing ATTR chunk and one of another window are corrupt.
#include <gtest/gtest.h>

#include <string>
#include <vector>

#include "capz/codec.h"
#include "capz/error.h"
#include "capz/file.h"
#include "chunk_util.h"
#include "coding/crc32c.h"
#include "test_util.h"

using capz::ErrorCode;
using capz_test::chunk_len;
using capz_test::find_chunk;
using capz_test::fix_crc;

namespace {

const std::string kStreams = std::string(CAPZ_TEST_DIR) + "/golden/streams/";

void damage_every_byte(const std::string& stream, uint8_t flip) {
  const std::vector<uint8_t> good = capz::read_file(kStreams + stream);
  const capz::Take ref = capz::decompress(good.data(), good.size(), stream);
  ASSERT_FALSE(ref.attributes.empty());
  const size_t at = find_chunk(good, "ATTR");
  ASSERT_NE(at, std::string::npos);
  const uint32_t len = chunk_len(good, at);
  size_t thrown = 0;
  for (uint32_t i = 0; i < len; ++i) {
    std::vector<uint8_t> b = good;
    b[at + 8 + i] ^= flip;
    fix_crc(&b, at);
    try {
      const capz::Take t = capz::decompress(b.data(), b.size(), "damaged");
      ASSERT_EQ(t.attributes.size(), ref.attributes.size());
      for (size_t k = 0; k < t.attributes.size(); ++k)
        EXPECT_EQ(t.attributes[k].data.size(), ref.attributes[k].data.size()) << "byte " << i;
    } catch (const capz::Error& e) {
      EXPECT_EQ(e.code(), ErrorCode::kCorrupt) << "byte " << i << ": " << e.what();
      ++thrown;
    }
  }
  // The payload's own structure (transforms, predictors, sizes, block ends, LZMA2's checks)
  // catches a part of the changes (about a quarter here); a change inside coded values decodes to
  // other values of the same shape, as for every chunk: the chunk CRC is what catches those.
  EXPECT_GT(thrown, 0u) << thrown << " of " << len;
}

}  // namespace

TEST(AttrCorrupt, DamagedAttrPayloadIsCaughtOrHarmless) {
  damage_every_byte("lidar_small.lossless.v5.0.capz", 0x01);
  damage_every_byte("lidar_small.grid0.01.v5.0.capz", 0x80);
  // 6.0: normal_z completed from normal_x and normal_y (predictor 9, its references, signs).
  damage_every_byte("depth_small.lossless.v6.0.capz", 0x01);
  damage_every_byte("depth_small.grid0.01.v6.0.capz", 0x80);
}

TEST(AttrCorrupt, A6StreamRelabelledAs5IsCorruptNotMisread) {
  // The version bytes of a 6.0 stream set to 5.0 (header CRC recomputed): a 5.x stream has no
  // predictor 9 nor transforms 4 and 5, so its ATTR is refused, naming the chunk and the field.
  std::vector<uint8_t> b = capz::read_file(kStreams + "depth_small.lossless.v6.0.capz");
  ASSERT_EQ(b[9], 6);
  b[9] = 5;
  const uint32_t crc = capz::crc32c(b.data(), 11);
  for (int k = 0; k < 4; ++k) b[11 + k] = static_cast<uint8_t>(crc >> (8 * k));
  std::string msg;
  EXPECT_EQ(capz_test::error_of([&] { capz::decompress(b.data(), b.size(), "x"); }, &msg),
            ErrorCode::kCorrupt);
  EXPECT_NE(msg.find("ATTR"), std::string::npos) << msg;
  // The first field coded with what 5.x lacks: rgb by transform 4 or 5, normal_z by predictor 9.
  EXPECT_TRUE(msg.find("bad transform") != std::string::npos ||
              msg.find("predictor 9") != std::string::npos)
      << msg;
}

TEST(AttrCorrupt, MissingOrMisplacedAttrIsCorrupt) {
  const std::vector<uint8_t> good = capz::read_file(kStreams + "lidar_small.lossless.v5.0.capz");
  const size_t at = find_chunk(good, "ATTR");
  ASSERT_NE(at, std::string::npos);
  // Renamed to a type no decoder knows (skipped as unknown): the window then lacks ATTR.
  std::vector<uint8_t> b = good;
  b[at] = 'Q';
  fix_crc(&b, at);
  std::string msg;
  EXPECT_EQ(capz_test::error_of([&] { capz::decompress(b.data(), b.size(), "x"); }, &msg),
            ErrorCode::kCorrupt);
  EXPECT_NE(msg.find("ATTR"), std::string::npos) << msg;
  // Its window index changed.
  b = good;
  b[at + 8] ^= 1;
  fix_crc(&b, at);
  EXPECT_EQ(capz_test::error_of([&] { capz::decompress(b.data(), b.size(), "x"); }),
            ErrorCode::kCorrupt);
}
