// Damaged PCD residue chunks (docs/FORMAT.md 7.3, 14.3): every byte of PCDR and PCDP changed with
// its chunk CRC recomputed (so only the payload's own checks and the checksums can tell): the
// rebuild throws a capz::Error and leaves no folder, or gives every frame file back exactly; never
// a crash, never a wrong file.
#include <gtest/gtest.h>

#include <cstring>
#include <filesystem>
#include <string>
#include <vector>

#include "capz/codec.h"
#include "capz/error.h"
#include "capz/stream.h"
#include "capz/tool/file.h"
#include "capz/tool/original.h"
#include "chunk_util.h"
#include "coding/lzf.h"
#include "test_util.h"

namespace fs = std::filesystem;

using capz_test::chunk_len;
using capz_test::find_chunk;
using capz_test::fix_crc;

namespace {

std::string header(const char* data, const std::string& nl) {
  return "# .PCD v0.7 - Point Cloud Data file format" + nl + "VERSION 0.7" + nl + "FIELDS x y z" +
         nl + "SIZE 4 4 4" + nl + "TYPE F F F" + nl + "COUNT 1 1 1" + nl + "WIDTH 3" + nl +
         "HEIGHT 1" + nl + "VIEWPOINT 0 0 0 1 0 0 0" + nl + "POINTS 3" + nl + "DATA " + data + nl;
}

// Frames that use every mode: the writer's own, a shared header of another form with a NaN
// payload and trailing bytes, an ASCII body with other spellings, one by column styles, a
// binary_compressed body of LZF variant 1.
std::vector<std::vector<uint8_t>> frames() {
  std::vector<std::vector<uint8_t>> out;
  for (int f = 0; f < 3; ++f) {
    const std::string h = f == 0 ? header("binary", "\n") : "# scan\r\n" + header("binary", "\r\n");
    std::vector<uint8_t> b(h.begin(), h.end());
    for (int i = 0; i < 9; ++i) {
      float v = static_cast<float>(f * 9 + i) * 0.5f;
      uint8_t x[4];
      std::memcpy(x, &v, 4);
      if (f == 2 && i == 3) x[0] = 1, x[1] = 0, x[2] = 0xc0, x[3] = 0x7f;  // a NaN payload
      b.insert(b.end(), x, x + 4);
    }
    if (f == 1) b.push_back('\n');
    out.push_back(b);
  }
  const std::string a = header("ascii", "\n") + "1.50 2 3\n4 5e+00 6\n-0 8 9.0\n";
  out.emplace_back(a.begin(), a.end());
  // Python's repr of each value, NaN in capitals: a body by column styles (5.4.3).
  const std::string r = header("ascii", "\n") + "0.5 1.0 1.5\n2.0 2.5 3.0\nNaN NaN NaN\n";
  out.emplace_back(r.begin(), r.end());
  // binary_compressed by PCL's LZF (LZF variant 1, flags bit 6): nine 1.0f values.
  std::vector<uint8_t> raw;
  for (int i = 0; i < 9; ++i) raw.insert(raw.end(), {0, 0, 0x80, 0x3f});
  const std::vector<uint8_t> c =
      capz::lzf_compress(raw.data(), raw.size(), capz::LzfVariant::kLiblzf13);
  const std::string h = header("binary_compressed", "\n");
  std::vector<uint8_t> b(h.begin(), h.end());
  for (uint32_t v : {static_cast<uint32_t>(c.size()), static_cast<uint32_t>(raw.size())})
    for (int k = 0; k < 4; ++k) b.push_back(static_cast<uint8_t>(v >> (8 * k)));
  b.insert(b.end(), c.begin(), c.end());
  out.push_back(b);
  return out;
}

class PcdResidueCorrupt : public ::testing::Test {
 protected:
  void SetUp() override {
    in_ = tmp_.file("in");
    fs::create_directories(in_);
    orig_ = frames();
    for (size_t f = 0; f < orig_.size(); ++f)
      capz::write_file(in_ + "/f" + std::to_string(f) + ".pcd", orig_[f], true);
    std::unique_ptr<capz::FrameSource> src = capz::open_frames(in_);
    capz::CompressOptions o;
    o.lossless = true;
    const std::string z = tmp_.file("good.capz");
    capz::compress_stream(*src, o, z, true);
    good_ = capz::read_file(z);
  }

  // Every byte of the chunk `type` xor `flip`, CRC fixed: throws and leaves nothing, or gives
  // every frame file back exactly.
  void damage_every_byte(const char* type, uint8_t flip) {
    const size_t at = find_chunk(good_, type);
    ASSERT_NE(at, std::string::npos) << type;
    const uint32_t len = chunk_len(good_, at);
    const std::string z = tmp_.file("bad.capz"), out = tmp_.file("out");
    for (uint32_t i = 0; i < len; ++i) {
      std::vector<uint8_t> b = good_;
      b[at + 8 + i] ^= flip;
      fix_crc(&b, at);
      capz::write_file(z, b, true);
      fs::remove_all(out);
      bool thrown = false;
      try {
        capz::rebuild_original(z, out, true);
      } catch (const capz::Error&) {
        thrown = true;
      }
      if (thrown) {
        EXPECT_FALSE(fs::exists(out)) << type << " byte " << i;
        EXPECT_THROW(capz::test_original(z), capz::Error) << type << " byte " << i;
        continue;
      }
      for (size_t f = 0; f < orig_.size(); ++f)
        EXPECT_EQ(capz::read_file(out + "/f" + std::to_string(f) + ".pcd"), orig_[f])
            << type << " byte " << i << " xor " << int(flip) << ": a wrong file was written";
    }
  }

  capz_test::TempDir tmp_{"capz_pcd_rcorrupt"};
  std::string in_;
  std::vector<std::vector<uint8_t>> orig_;
  std::vector<uint8_t> good_;
};

}  // namespace

TEST_F(PcdResidueCorrupt, DamagedFileResidueIsCaught) {
  damage_every_byte("PCDR", 0x01);
  damage_every_byte("PCDR", 0x80);
}

TEST_F(PcdResidueCorrupt, DamagedWindowResidueIsCaught) {
  damage_every_byte("PCDP", 0x01);
  damage_every_byte("PCDP", 0x40);  // flags bit 6: LZF variant 1
  damage_every_byte("PCDP", 0x80);
}

TEST_F(PcdResidueCorrupt, DamagedFolderHashIsCaught) {
  damage_every_byte("HASH", 0x01);
}

// A window whose PCDP is gone (its tag renamed, CRC fixed): corrupt, nothing written.
TEST_F(PcdResidueCorrupt, MissingWindowResidueIsCorrupt) {
  std::vector<uint8_t> b = good_;
  const size_t at = find_chunk(b, "PCDP");
  ASSERT_NE(at, std::string::npos);
  b[at] = 'p';  // an ancillary type no decoder knows (FORMAT.md 2): skipped, so PCDP is missing
  fix_crc(&b, at);
  const std::string z = tmp_.file("gone.capz"), out = tmp_.file("out");
  capz::write_file(z, b, true);
  try {
    capz::rebuild_original(z, out, true);
    FAIL() << "rebuilt without PCDP";
  } catch (const capz::Error& e) {
    EXPECT_EQ(e.code(), capz::ErrorCode::kCorrupt) << e.what();
    EXPECT_NE(std::string(e.what()).find("PCDP"), std::string::npos) << e.what();
  }
  EXPECT_FALSE(fs::exists(out));
}
