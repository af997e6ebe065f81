// What the corrupt-residue tests of frame files share (test_scan_lossless_corrupt.cpp: PCD,
// test_frame_residue_corrupt.cpp: PLY and .bin): a folder of frame files f0<ext> .. compressed
// losslessly in windows of 3 frames, the n-th chunk of a type, every byte of a chunk flipped with
// its CRC recomputed, and the rebuild of a damaged stream, which must throw and leave no folder or
// give every frame file back exactly.
#pragma once

#include <gtest/gtest.h>

#include <cstring>
#include <filesystem>
#include <memory>
#include <string>
#include <vector>

#include "capz/codec.h"
#include "capz/error.h"
#include "capz/stream.h"
#include "capz/tool/file.h"
#include "capz/tool/original.h"
#include "chunk_util.h"
#include "coding/container.h"
#include "test_util.h"

namespace capz_test {

class FrameFilesResidue {
 protected:
  // Writes `files` as f0<ext>, f1<ext>, ... and compresses the folder losslessly into good_.
  void make(const std::vector<std::vector<uint8_t>>& files, const std::string& ext) {
    namespace fs = std::filesystem;
    in_ = tmp_.file("in");
    ext_ = ext;
    orig_ = files;
    fs::create_directories(in_);
    for (size_t f = 0; f < files.size(); ++f)
      capz::write_file(in_ + "/f" + std::to_string(f) + ext_, files[f], true);
    std::unique_ptr<capz::FrameSource> src = capz::open_frames(in_);
    ASSERT_TRUE(src->header().ragged());
    capz::CompressOptions o;
    o.lossless = true;
    o.window_frames = 3;  // two windows, two PCDP chunks
    const std::string z = tmp_.file("good.capz");
    capz::compress_stream(*src, o, z, true);
    good_ = capz::read_file(z);
  }

  // The n-th chunk of `type` (its offset), or npos.
  size_t nth(const char* type, int n) const {
    size_t at = capz::kFileHeaderBytes;
    while (at + 12 <= good_.size()) {
      if (std::memcmp(&good_[at], type, 4) == 0 && n-- == 0) return at;
      at += 12 + chunk_len(good_, at);
    }
    return std::string::npos;
  }

  bool rebuilds_or_throws(const std::vector<uint8_t>& b, const std::string& what) {
    namespace fs = std::filesystem;
    const std::string z = tmp_.file("bad.capz"), out = tmp_.file("out");
    capz::write_file(z, b, true);
    fs::remove_all(out);
    try {
      capz::rebuild_original(z, out, true);
    } catch (const capz::Error&) {
      EXPECT_FALSE(fs::exists(out)) << what;
      return false;
    }
    for (size_t f = 0; f < orig_.size(); ++f)
      EXPECT_EQ(capz::read_file(out + "/f" + std::to_string(f) + ext_), orig_[f])
          << what << ": a wrong file was written";
    return true;
  }

  void damage_every_byte(const char* type, int n) {
    const size_t at = nth(type, n);
    ASSERT_NE(at, std::string::npos) << type << " " << n;
    const uint32_t len = chunk_len(good_, at);
    for (uint32_t i = 0; i < len; ++i)
      for (uint8_t flip : {uint8_t{0x01}, uint8_t{0x80}}) {
        std::vector<uint8_t> b = good_;
        b[at + 8 + i] ^= flip;
        fix_crc(&b, at);
        rebuilds_or_throws(b, std::string(type) + " byte " + std::to_string(i));
      }
  }

  // The PCDP of window 1 claiming window 0: corrupt, nothing written.
  void expect_window_claim_corrupt() {
    std::vector<uint8_t> b = good_;
    const size_t at = nth("PCDP", 1);
    ASSERT_NE(at, std::string::npos);
    ASSERT_EQ(b[at + 8], 1);  // the window index varint
    b[at + 8] = 0;
    fix_crc(&b, at);
    EXPECT_FALSE(rebuilds_or_throws(b, "PCDP of window 0 in window 1"));
  }

  TempDir tmp_{"capz_frames_rcorrupt"};
  std::string in_, ext_;
  std::vector<std::vector<uint8_t>> orig_;
  std::vector<uint8_t> good_;
};

}  // namespace capz_test
