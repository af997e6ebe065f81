// The byte-exact residue wired into .capz (docs/FORMAT.md 7, 14): HASH, C3DR/C3DP written for a
// C3D read from a path, the original rebuilt byte for byte, a damaged checksum caught.
#include <gtest/gtest.h>

#include <cstdio>
#include <filesystem>
#include <string>
#include <vector>

#include "capz/codec.h"
#include "capz/error.h"
#include "capz/io.h"
#include "capz/stream.h"
#include "capz/tool/file.h"
#include "capz/tool/original.h"
#include "coding/crc32c.h"
#include "test_util.h"

namespace fs = std::filesystem;

namespace {

// In a folder of this process's own, removed when it exits.
std::string tmp(const std::string& name) {
  static const capz_test::TempDir dir("capz_wire");
  return dir.file(name);
}

std::string compress_file(const std::string& in, bool lossless, const std::string& out) {
  std::unique_ptr<capz::FrameSource> src = capz::open_frames(in);
  capz::CompressOptions o;
  if (lossless)
    o.lossless = true;
  else
    o.max_error = 0.1;
  capz::compress_stream(*src, o, out, true);
  return out;
}

// Offset of the first chunk of `type` in a .capz (walking from the first chunk after the header).
size_t find_chunk(const std::vector<uint8_t>& b, const char* type) {
  for (size_t i = 0; i + 4 <= b.size(); ++i)
    if (std::equal(type, type + 4, b.begin() + static_cast<long>(i))) return i;
  return std::string::npos;
}

// Recomputes the CRC of the chunk at `at` (type, u32 length, payload, u32 CRC of type + payload).
void fix_crc(std::vector<uint8_t>* b, size_t at) {
  const uint8_t* p = b->data() + at;
  const uint32_t len = p[4] | p[5] << 8 | p[6] << 16 | static_cast<uint32_t>(p[7]) << 24;
  const uint32_t crc = capz::crc32c_update(capz::crc32c(p, 4), p + 8, len);
  for (int k = 0; k < 4; ++k) (*b)[at + 8 + len + k] = static_cast<uint8_t>(crc >> (8 * k));
}

const char* kData[] = {"Capture0004.c3d", "EB015PI.c3d", "admarche2.c3d"};

}  // namespace

TEST(ResidueWiring, LosslessC3DComesBackByteForByte) {
  for (const char* name : kData) {
    const std::string in = std::string(CAPZ_REPO_DATA) + "/" + name;
    const std::string z = compress_file(in, true, tmp("l.capz"));
    const capz::OriginalInfo info = capz::original_info(z);
    EXPECT_TRUE(info.hashed && info.residue && info.exact) << name;
    EXPECT_EQ(info.size, fs::file_size(in)) << name;
    const std::string out = tmp("l.c3d");
    capz::rebuild_original(z, out, true);
    EXPECT_EQ(capz::read_file(out), capz::read_file(in)) << name;
    EXPECT_EQ(capz::rebuilds_file(z, in), "") << name;
    fs::remove(out);
  }
}

TEST(ResidueWiring, BoundC3DKeepsHeadAndSize) {
  const std::string in = std::string(CAPZ_REPO_DATA) + "/EB015PI.c3d";
  const std::string z = compress_file(in, false, tmp("b.capz"));
  const capz::OriginalInfo info = capz::original_info(z);
  EXPECT_TRUE(info.hashed && info.residue);
  EXPECT_FALSE(info.exact);
  const std::string out = tmp("b.c3d");
  capz::rebuild_original(z, out, true);
  const std::vector<uint8_t> a = capz::read_file(in), b = capz::read_file(out);
  ASSERT_EQ(a.size(), b.size());
  EXPECT_TRUE(std::equal(a.begin(), a.begin() + 512, b.begin()));  // the header block verbatim
  EXPECT_NE(capz::rebuilds_file(z, in), "");                       // not exact: --rm must not
  fs::remove(out);
}

TEST(ResidueWiring, CompressOfATakeWritesNoResidue) {
  const capz::Take t = capz::read_take(std::string(CAPZ_REPO_DATA) + "/admarche2.c3d");
  capz::CompressOptions o;
  o.lossless = true;
  const std::vector<uint8_t> z = capz::compress(t, o);
  EXPECT_EQ(find_chunk(z, "HASH"), std::string::npos);
  EXPECT_EQ(find_chunk(z, "C3DR"), std::string::npos);
  EXPECT_EQ(capz::describe(z.data(), z.size()).chunk_bytes.count("HASH"), 0u);
}

// A damaged stored hash (its chunk CRC fixed, so only the checksum can tell) fails the rebuild
// as corrupt, naming the archive, and leaves no output.
TEST(ResidueWiring, ChecksumMismatchIsCaught) {
  const std::string z =
      compress_file(std::string(CAPZ_REPO_DATA) + "/admarche2.c3d", true, tmp("h.capz"));
  std::vector<uint8_t> b = capz::read_file(z);
  const size_t at = find_chunk(b, "HASH");
  ASSERT_NE(at, std::string::npos);
  b[at + 8 + 8 + 5] ^= 0x10;  // a byte of the XXH3-128
  fix_crc(&b, at);
  capz::write_file(z, b, true);
  const std::string out = tmp("h.c3d");
  fs::remove(out);
  try {
    capz::rebuild_original(z, out, true);
    FAIL() << "a damaged hash was not caught";
  } catch (const capz::Error& e) {
    EXPECT_EQ(e.code(), capz::ErrorCode::kCorrupt);
    EXPECT_NE(std::string(e.what()).find(z), std::string::npos) << e.what();
  }
  EXPECT_FALSE(fs::exists(out));
  EXPECT_THROW(capz::test_original(z), capz::Error);
}

// A damaged C3DP byte (CRC fixed) is caught by the hash or by the patch's own checks.
TEST(ResidueWiring, DamagedWindowResidueIsCaught) {
  const std::string z =
      compress_file(std::string(CAPZ_REPO_DATA) + "/Capture0004.c3d", true, tmp("p.capz"));
  std::vector<uint8_t> b = capz::read_file(z);
  const size_t at = find_chunk(b, "C3DP");
  if (at == std::string::npos) GTEST_SKIP() << "no C3DP in this archive (regeneration exact)";
  const uint32_t len = b[at + 4] | b[at + 5] << 8;
  b[at + 8 + len - 1] ^= 0x01;
  fix_crc(&b, at);
  capz::write_file(z, b, true);
  try {
    capz::test_original(z);
    FAIL() << "a damaged C3DP was not caught";
  } catch (const capz::Error& e) {
    EXPECT_EQ(e.code(), capz::ErrorCode::kCorrupt) << e.what();
  }
}
