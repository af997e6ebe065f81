// Damaged ATTR chunks (docs/FORMAT.md 13, 13.4): bytes of a window's ATTR payload changed (every
// one of a short payload; of a long one its head, its tail and a spread between:
// payload_positions), its chunk CRC recomputed so only the payload's own checks can tell: decoding
// throws a capz::Error or gives a take (the change hit a value, which only a checksum could catch);
// never a crash, never unbounded memory. A missing ATTR chunk and one of another window are
// corrupt.
#include <gtest/gtest.h>

#include <string>
#include <vector>

#include "capz/codec.h"
#include "capz/error.h"
#include "capz/tool/file.h"
#include "chunk_util.h"
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
  const std::vector<size_t> positions = capz_test::payload_positions(len);
  for (const size_t i : positions) {
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
  EXPECT_GT(thrown, 0u) << thrown << " of " << positions.size();
}

}  // namespace

TEST(AttrCorrupt, DamagedAttrPayloadIsCaughtOrHarmless) {
  damage_every_byte("lidar_small.lossless.v1.0.capz", 0x01);
  damage_every_byte("lidar_small.grid0.01.v1.0.capz", 0x80);
  // normal_z completed from normal_x and normal_y (predictor 9, its references, signs).
  damage_every_byte("depth_small.lossless.v1.0.capz", 0x01);
  damage_every_byte("depth_small.grid0.01.v1.0.capz", 0x80);
}

TEST(AttrCorrupt, MissingOrMisplacedAttrIsCorrupt) {
  const std::vector<uint8_t> good = capz::read_file(kStreams + "lidar_small.lossless.v1.0.capz");
  const size_t at = find_chunk(good, "ATTR");
  ASSERT_NE(at, std::string::npos);
  // Renamed to an ancillary type no decoder knows (skipped): the window then lacks ATTR.
  std::vector<uint8_t> b = good;
  b[at] = 'q';
  fix_crc(&b, at);
  std::string msg;
  EXPECT_EQ(capz_test::error_of([&] { capz::decompress(b.data(), b.size(), "x"); }, &msg),
            ErrorCode::kCorrupt);
  EXPECT_NE(msg.find("ATTR"), std::string::npos) << msg;
  // Renamed to a critical type no decoder knows: refused as a later version's (FORMAT.md 2).
  b[at] = 'Q';
  fix_crc(&b, at);
  EXPECT_EQ(capz_test::error_of([&] { capz::decompress(b.data(), b.size(), "x"); }, &msg),
            ErrorCode::kUnsupportedVersion);
  EXPECT_NE(msg.find("chunk QTTR of format 1.0"), std::string::npos) << msg;
  // Its window index changed.
  b = good;
  b[at + 8] ^= 1;
  fix_crc(&b, at);
  EXPECT_EQ(capz_test::error_of([&] { capz::decompress(b.data(), b.size(), "x"); }),
            ErrorCode::kCorrupt);
}
