// Damaged residue of lossless PLY and .bin streams (docs/FORMAT.md "Lossless frame-file
// streams"): every byte of HASH, PCDR and each window's PCDP changed with its chunk CRC
// recomputed: the rebuild throws a capz::Error and leaves no folder, or gives every frame file
// back exactly; PCDR's kind of another format, PCDP flags a PLY or .bin frame cannot have (LZF
// variant 1, a .bin header or ascii body) and a PCDR in a stream without the lossless bit are
// corrupt, each refused for that reason, not only by the rebuilt bytes' hash.
#include <gtest/gtest.h>

#include <cstdio>
#include <cstring>
#include <string>
#include <vector>

#include "chunk_util.h"
#include "frame_files_residue.h"

using capz_test::fix_crc;

namespace {

// Frame f of 2 + f points, x y z intensity float32: a binary PLY with a comment and a byte after
// its body (frame 1), an ascii PLY in "%.3f" (frame 2); or .bin frames, frame 1 with a NaN
// payload of its own.
std::vector<uint8_t> frame(size_t f, bool ply) {
  const size_t n = 2 + f;
  const bool text = ply && f == 2;
  std::string h;
  if (ply)
    h = std::string("ply\nformat ") + (text ? "ascii" : "binary_little_endian") + " 1.0\n" +
        (f == 1 ? "comment own\n" : "") + "element vertex " + std::to_string(n) +
        "\nproperty float x\nproperty float y\nproperty float z\nproperty float "
        "intensity\nend_header\n";
  std::vector<uint8_t> b(h.begin(), h.end());
  for (size_t i = 0; i < 4 * n; ++i) {
    const float v = 0.5f * static_cast<float>(i) - static_cast<float>(f);
    if (text) {
      char s[32];
      std::snprintf(s, sizeof s, "%.3f%c", static_cast<double>(v), i % 4 == 3 ? '\n' : ' ');
      b.insert(b.end(), s, s + std::strlen(s));
      continue;
    }
    uint8_t x[4];
    std::memcpy(x, &v, 4);
    if (f == 1 && i == 4) x[0] = 9, x[1] = 0, x[2] = 0xc0, x[3] = 0x7f;
    b.insert(b.end(), x, x + 4);
  }
  if (ply && f == 1) b.push_back(0);
  return b;
}

class FrameResidueCorrupt : public ::testing::TestWithParam<bool>,
                            public capz_test::FrameFilesResidue {
 protected:
  void SetUp() override {
    std::vector<std::vector<uint8_t>> files;
    for (size_t f = 0; f < 4; ++f) files.push_back(frame(f, GetParam()));
    make(files, GetParam() ? ".ply" : ".bin");
  }

  // `b` is refused as corrupt for the reason `why` names (not only by the rebuilt bytes' hash).
  void expect_refused(const std::vector<uint8_t>& b, const std::string& why) {
    const std::string z = tmp_.file("refused.capz");
    capz::write_file(z, b, true);
    try {
      capz::test_original(z);
      ADD_FAILURE() << why << ": accepted";
    } catch (const capz::Error& e) {
      EXPECT_EQ(e.code(), capz::ErrorCode::kCorrupt);
      EXPECT_NE(std::string(e.what()).find(why), std::string::npos) << e.what();
    }
  }

  // The first frame record's flags byte in PCDP 0 (after the window index, size and hash).
  size_t first_flags() const {
    const size_t at = nth("PCDP", 0);
    size_t p = at + 8 + 1;        // window 0
    while (good_[p] & 0x80) ++p;  // size varint
    return p + 1 + 16;
  }
};

}  // namespace

INSTANTIATE_TEST_SUITE_P(PlyAndBin, FrameResidueCorrupt, ::testing::Bool());

TEST_P(FrameResidueCorrupt, TheUndamagedStreamRebuilds) {
  EXPECT_TRUE(rebuilds_or_throws(good_, "undamaged"));
}

TEST_P(FrameResidueCorrupt, DamagedResidueIsCaught) {
  damage_every_byte("HASH", 0);
  damage_every_byte("PCDR", 0);
  damage_every_byte("PCDP", 0);
  damage_every_byte("PCDP", 1);
}

// PCDR's kind set to PCD's (3) or the other frame format's: corrupt, nothing written.
TEST_P(FrameResidueCorrupt, ResidueOfAnotherFormatIsCorrupt) {
  for (uint8_t kind : {uint8_t{3}, static_cast<uint8_t>(GetParam() ? 4 : 5)}) {
    std::vector<uint8_t> b = good_;
    const size_t at = nth("PCDR", 0);
    ASSERT_NE(at, std::string::npos);
    ASSERT_EQ(b[at + 8], GetParam() ? 5 : 4);
    b[at + 8] = kind;
    fix_crc(&b, at);
    EXPECT_FALSE(rebuilds_or_throws(b, "PCDR kind " + std::to_string(kind)));
    expect_refused(b, "the residue of another frame format");
  }
}

// Flags a frame-file record cannot have: LZF variant 1 (bit 6) with e 2; for .bin, e 1, a header
// mode and an ascii body.
TEST_P(FrameResidueCorrupt, FlagsOfPCDOnlyAreCorrupt) {
  std::vector<uint8_t> bad = {uint8_t{2 | 1 << 6}};
  if (!GetParam()) bad.insert(bad.end(), {uint8_t{1}, uint8_t{1 << 2}, uint8_t{3 << 4}});
  const size_t p = first_flags(), at = nth("PCDP", 0);
  for (uint8_t flags : bad) {
    std::vector<uint8_t> b = good_;
    b[p] = flags;
    fix_crc(&b, at);
    EXPECT_FALSE(rebuilds_or_throws(b, "flags " + std::to_string(flags)));
    expect_refused(b, "bad flags for frame file f0");
  }
}

// HEAD without its lossless bit (flags byte 19 of its payload): PCDR is valid only in a lossless
// stream.
TEST_P(FrameResidueCorrupt, ResidueInAStreamThatIsNotLosslessIsCorrupt) {
  std::vector<uint8_t> b = good_;
  const size_t at = nth("HEAD", 0);
  ASSERT_EQ(b[at + 8 + 19] & 1, 1);
  b[at + 8 + 19] &= 0xfe;
  fix_crc(&b, at);
  EXPECT_FALSE(rebuilds_or_throws(b, "HEAD not lossless"));
  expect_refused(b, "not lossless");
}

// The PCDP of window 1 claiming window 0: corrupt, nothing written.
TEST_P(FrameResidueCorrupt, WindowResidueOfAnotherWindowIsCorrupt) {
  expect_window_claim_corrupt();
}
