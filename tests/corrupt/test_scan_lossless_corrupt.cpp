// Damaged residue of a lossless ragged stream (docs/FORMAT.md "Lossless ragged streams"): every
// byte of HASH, PCDR and each window's PCDP changed with its chunk CRC recomputed: the rebuild
// throws a capz::Error and leaves no folder, or gives every frame file back exactly; and a
// PCDP's window index naming another window is corrupt.
#include <gtest/gtest.h>

#include <cstring>
#include <string>
#include <vector>

#include "chunk_util.h"
#include "frame_files_residue.h"

using capz_test::fix_crc;

namespace {

// Frame f of 2 + f points, x y z float32: binary frames, one with a header comment and a NaN
// payload of its own, one ascii in other spellings.
std::vector<uint8_t> frame(size_t f) {
  const size_t n = 2 + f;
  const bool text = f == 2;
  const std::string h = std::string(f == 1 ? "# own\n" : "") +
                        "# .PCD v0.7 - Point Cloud Data file format\nVERSION 0.7\nFIELDS x y z\n" +
                        "SIZE 4 4 4\nTYPE F F F\nCOUNT 1 1 1\nWIDTH " + std::to_string(n) +
                        "\nHEIGHT 1\nVIEWPOINT 0 0 0 1 0 0 0\nPOINTS " + std::to_string(n) +
                        "\nDATA " + (text ? "ascii" : "binary") + "\n";
  std::vector<uint8_t> b(h.begin(), h.end());
  for (size_t i = 0; i < 3 * n; ++i) {
    const float v = 0.5f * static_cast<float>(i) - static_cast<float>(f);
    if (text) {
      const std::string s = std::to_string(v) + (i % 3 == 2 ? "\n" : " ");
      b.insert(b.end(), s.begin(), s.end());
      continue;
    }
    uint8_t x[4];
    std::memcpy(x, &v, 4);
    if (f == 1 && i == 3) x[0] = 9, x[1] = 0, x[2] = 0xc0, x[3] = 0x7f;
    b.insert(b.end(), x, x + 4);
  }
  return b;
}

class ScanResidueCorrupt : public ::testing::Test, public capz_test::FrameFilesResidue {
 protected:
  void SetUp() override {
    std::vector<std::vector<uint8_t>> files;
    for (size_t f = 0; f < 4; ++f) files.push_back(frame(f));
    make(files, ".pcd");
  }
};

}  // namespace

TEST_F(ScanResidueCorrupt, TheUndamagedStreamRebuilds) {
  EXPECT_TRUE(rebuilds_or_throws(good_, "undamaged"));
}

TEST_F(ScanResidueCorrupt, DamagedResidueIsCaught) {
  damage_every_byte("HASH", 0);
  damage_every_byte("PCDR", 0);
  damage_every_byte("PCDP", 0);
  damage_every_byte("PCDP", 1);
}

// The PCDP of window 1 claiming window 0: corrupt, nothing written.
TEST_F(ScanResidueCorrupt, WindowResidueOfAnotherWindowIsCorrupt) {
  expect_window_claim_corrupt();
}
