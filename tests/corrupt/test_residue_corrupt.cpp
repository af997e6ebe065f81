// Damaged byte-exact chunks (docs/FORMAT.md 7, 14): every byte of HASH, C3DR and C3DP, changed with
// its chunk CRC recomputed (so only the payload's own checks and the hash can tell): the rebuild
// throws a capz::Error or gives the original back exactly; never a crash, never a wrong file.
#include <gtest/gtest.h>

#include <filesystem>
#include <string>
#include <vector>

#include "capz/codec.h"
#include "capz/error.h"
#include "capz/stream.h"
#include "capz/tool/file.h"
#include "capz/tool/original.h"
#include "chunk_util.h"
#include "test_util.h"

namespace fs = std::filesystem;

using capz_test::chunk_len;
using capz_test::find_chunk;
using capz_test::fix_crc;

namespace {

// Per test, in a folder of this process's own that is removed when it exits (ctest runs the
// tests of this executable in parallel processes).
std::string tmp(const std::string& name) {
  static const capz_test::TempDir dir("capz_rcorrupt");
  const std::string test = ::testing::UnitTest::GetInstance()->current_test_info()->name();
  return dir.file(test + "_" + name);
}

std::vector<uint8_t> lossless_archive(const char* name) {
  const std::string z = tmp("src.capz");
  std::unique_ptr<capz::FrameSource> src =
      capz::open_frames(std::string(CAPZ_REPO_DATA) + "/" + name);
  capz::CompressOptions o;
  o.lossless = true;
  capz::compress_stream(*src, o, z, true);
  return capz::read_file(z);
}

// Every byte of the chunk `type` changed (xor `flip`, CRC fixed): the rebuild must throw and
// leave no output, or (a field the rebuild does not use for this file, e.g. the int16 scale of a
// float file) give back the original exactly, as the hash then proves.
void damage_every_byte(const char* name, const char* type, uint8_t flip) {
  const std::vector<uint8_t> good = lossless_archive(name);
  const std::vector<uint8_t> orig = capz::read_file(std::string(CAPZ_REPO_DATA) + "/" + name);
  const size_t at = find_chunk(good, type);
  ASSERT_NE(at, std::string::npos) << type;
  const uint32_t len = chunk_len(good, at);
  const std::string z = tmp("bad.capz"), out = tmp("bad.c3d");
  for (uint32_t i = 0; i < len; ++i) {
    std::vector<uint8_t> b = good;
    b[at + 8 + i] ^= flip;
    fix_crc(&b, at);
    capz::write_file(z, b, true);
    fs::remove(out);
    bool thrown = false;
    try {
      capz::rebuild_original(z, out, true);
    } catch (const capz::Error&) {
      thrown = true;
    }
    if (thrown)
      EXPECT_FALSE(fs::exists(out)) << type << " byte " << i;
    else
      EXPECT_EQ(capz::read_file(out), orig)
          << type << " byte " << i << " xor " << int(flip) << ": a wrong file was written";
  }
}

}  // namespace

TEST(ResidueCorrupt, DamagedHashIsCaught) {
  damage_every_byte("admarche2.c3d", "HASH", 0x01);
}

TEST(ResidueCorrupt, DamagedFileResidueIsCaught) {
  damage_every_byte("admarche2.c3d", "C3DR", 0x01);
  damage_every_byte("admarche2.c3d", "C3DR", 0x80);
}

TEST(ResidueCorrupt, DamagedWindowResidueIsCaught) {
  const std::vector<uint8_t> good = lossless_archive("Capture0004.c3d");
  if (find_chunk(good, "C3DP") == std::string::npos)
    GTEST_SKIP() << "Capture0004.c3d's archive has no C3DP";
  damage_every_byte("Capture0004.c3d", "C3DP", 0x01);
  damage_every_byte("Capture0004.c3d", "C3DP", 0x80);
}

// A bad chunk CRC in HASH is reported as corrupt when the archive is opened at all.
TEST(ResidueCorrupt, HashBadCrcIsCorrupt) {
  std::vector<uint8_t> b = lossless_archive("admarche2.c3d");
  const size_t at = find_chunk(b, "HASH");
  ASSERT_NE(at, std::string::npos);
  b[at + 9] ^= 1;
  const std::string z = tmp("crc.capz");
  capz::write_file(z, b, true);
  try {
    capz::original_info(z);
    FAIL() << "bad HASH CRC accepted";
  } catch (const capz::Error& e) {
    EXPECT_EQ(e.code(), capz::ErrorCode::kCorrupt) << e.what();
  }
  EXPECT_THROW(capz::decompress(b.data(), b.size(), z), capz::Error);
}
