// The three shared PCD sequences read with their known sizes; PCD -> PCD is exact, and a
// --lossless archive gives their frame files back byte for byte.
#include <gtest/gtest.h>

#include <algorithm>
#include <cmath>
#include <cstdio>
#include <filesystem>
#include <memory>
#include <string>
#include <vector>

#include "capz/codec.h"
#include "capz/error.h"
#include "capz/file.h"
#include "capz/io.h"
#include "capz/original.h"
#include "capz/stream.h"
#include "test_util.h"

namespace fs = std::filesystem;

namespace {

struct Seq {
  const char* name;
  size_t points, frames;
};
const Seq kSeqs[] = {
    {"chickenCrossing", 3030, 400}, {"horse-gallop", 8431, 48}, {"pcow", 2904, 204}};

}  // namespace

TEST(PcdConformance, SharedSequencesReadRoundTripExactly) {
  const std::string data = capz_test::shared_data_or_skip();
  if (data.empty()) return;
  capz_test::TempDir tmp("capz_pcd_conf");
  for (const auto& s : kSeqs) {
    SCOPED_TRACE(s.name);
    capz::Take t = capz::read_pcd_folder(data + "/pcd/" + s.name);
    EXPECT_EQ(t.format, capz::Format::kPCDFolder);
    EXPECT_EQ(t.points, s.points);
    EXPECT_EQ(t.frames, s.frames);
    ASSERT_TRUE(t.pcd);
    EXPECT_EQ(t.pcd->frame_names.size(), s.frames);
    EXPECT_EQ(t.pcd->encoding, "binary");
    // Positions are real geometry: finite, and frames differ (the sequences move).
    bool moves = false;
    for (size_t p = 0; p < t.points && !moves; ++p)
      for (int a = 0; a < 3; ++a) moves = moves || t.at(0, p)[a] != t.at(t.frames - 1, p)[a];
    EXPECT_TRUE(moves);
    // Binary for all, compressed for the shortest sequence (the slowest writer).
    for (const char* enc : {"binary", "binary_compressed"}) {
      if (std::string(enc) == "binary_compressed" && s.frames > 50) continue;
      const std::string out = tmp.file(std::string(s.name) + "_" + enc);
      capz::WriteOptions o;
      o.pcd_encoding = enc;
      capz::write_pcd_folder(t, out, o);
      capz::Take u = capz::read_pcd_folder(out);
      EXPECT_EQ(u.pcd->frame_names, t.pcd->frame_names);
      EXPECT_EQ(u.valid, t.valid);
      EXPECT_EQ(u.xyz, t.xyz) << enc;
    }
  }
}

TEST(PcdConformance, FrameOrderIsNatural) {
  const std::string data = capz_test::shared_data_or_skip();
  if (data.empty()) return;
  capz::Take t = capz::read_pcd_folder(data + "/pcd/chickenCrossing");
  EXPECT_EQ(t.pcd->frame_names.front(), "frame_0001.pcd");
  EXPECT_EQ(t.pcd->frame_names.back(), "frame_0400.pcd");
}

// --lossless archives of the shared sequences (and of the bundled LiDAR sweeps with fields)
// give back every frame file byte for byte through the PCD writer too (decompress with
// --pcd-data binary): their headers are in the form capz writes (PCL's) and their gaps are
// canonical NaNs. (Any other frame file comes back byte for byte through the residue only:
// LosslessArchivesRebuild... below, FORMAT.md 7.3, 14.3.)
TEST(PcdConformance, LosslessArchivesGiveBackTheSharedFramesByteForByte) {
  const std::string data = capz_test::shared_data_or_skip();
  if (data.empty()) return;
  capz_test::TempDir tmp("capz_pcd_exact");
  std::vector<std::string> dirs = {std::string(CAPZ_REPO_DATA) + "/lidar_small"};
  for (const auto& s : kSeqs) dirs.push_back(data + "/pcd/" + s.name);
  for (const std::string& dir : dirs) {
    SCOPED_TRACE(dir);
    std::unique_ptr<capz::FrameSource> src = capz::open_frames(dir);
    capz::CompressOptions o;
    o.lossless = true;
    const std::string z = tmp.file("a.capz"), out = tmp.file("back");
    capz::compress_stream(*src, o, z, true, nullptr);
    std::unique_ptr<capz::FrameSource> back = capz::open_capz_frames(z);
    capz::WriteOptions wo;
    wo.overwrite = true;
    std::unique_ptr<capz::FrameSink> sink =
        capz::create_frame_sink(back->header(), back->has_sample_words(), out + "/", wo);
    capz::copy_frames(*back, *sink, back->preferred_block());
    size_t files = 0;
    for (const auto& e : fs::directory_iterator(dir)) {
      ++files;
      EXPECT_EQ(capz::read_file((fs::path(out) / e.path().filename()).string()),
                capz::read_file(e.path().string()))
          << e.path().filename();
    }
    EXPECT_GT(files, 0u);
  }
}

namespace {

// Bytes of every chunk of `type` in an archive (12 bytes of framing each).
size_t chunk_bytes(const std::vector<uint8_t>& a, const char* type) {
  size_t n = 0;
  for (size_t i = 0; i + 4 <= a.size(); ++i)
    if (std::equal(type, type + 4, a.begin() + static_cast<long>(i))) {
      n += 12 + (a[i + 4] | a[i + 5] << 8 | a[i + 6] << 16 | static_cast<uint32_t>(a[i + 7]) << 24);
    }
  return n;
}

// A --lossless archive of `dir` rebuilt through its residue (FORMAT.md 7.3, 14.3): every frame file
// byte for byte, each frame's checksum and the folder's checked by capz test's path too. One
// line of the table per folder: files, bytes, archive, residue (HASH + PCDR + PCDP).
void rebuild_exactly(const std::string& dir) {
  SCOPED_TRACE(dir);
  capz_test::TempDir tmp("capz_pcd_rebuild");
  const std::string z = tmp.file("a.capz"), out = tmp.file("back");
  std::unique_ptr<capz::FrameSource> src = capz::open_frames(dir);
  capz::CompressOptions o;
  o.lossless = true;
  capz::compress_stream(*src, o, z, true, nullptr);
  const capz::OriginalInfo info = capz::original_info(z);
  ASSERT_TRUE(info.hashed && info.residue && info.exact);
  capz::test_original(z);
  capz::rebuild_original(z, out, true);
  size_t files = 0, bytes = 0;
  for (const auto& e : fs::directory_iterator(dir)) {
    const std::vector<uint8_t> orig = capz::read_file(e.path().string());
    EXPECT_EQ(capz::read_file((fs::path(out) / e.path().filename()).string()), orig)
        << e.path().filename();
    ++files;
    bytes += orig.size();
  }
  EXPECT_EQ(info.size, bytes);
  size_t back = 0;
  for (const auto& e : fs::directory_iterator(out)) back += e.is_regular_file() ? 1 : 0;
  EXPECT_EQ(back, files);
  const std::vector<uint8_t> a = capz::read_file(z);
  const size_t residue = chunk_bytes(a, "HASH") + chunk_bytes(a, "PCDR") + chunk_bytes(a, "PCDP");
  std::printf("  %-60s %5zu files %10zu bytes, archive %9zu, residue %6zu (%.3f%%): exact\n",
              dir.c_str(), files, bytes, a.size(), residue,
              100.0 * static_cast<double>(residue) / static_cast<double>(a.size()));
}

}  // namespace

// The bundled LiDAR sweeps, and the same frames written in each DATA encoding.
TEST(PcdConformance, LosslessArchivesRebuildTheBundledFramesWithTheirChecksums) {
  const std::string dir = std::string(CAPZ_REPO_DATA) + "/lidar_small";
  rebuild_exactly(dir);
  capz_test::TempDir tmp("capz_pcd_rebuild_enc");
  const capz::Take t = capz::read_pcd_folder(dir);
  for (const char* enc : {"ascii", "binary_compressed"}) {
    capz::WriteOptions wo;
    wo.pcd_encoding = enc;
    const std::string d = tmp.file(enc);
    capz::write_pcd_folder(t, d, wo);
    rebuild_exactly(d);
  }
}

TEST(PcdConformance, LosslessArchivesRebuildTheSharedFramesWithTheirChecksums) {
  const std::string data = capz_test::shared_data_or_skip();
  if (data.empty()) return;
  for (const auto& s : kSeqs) rebuild_exactly(data + "/pcd/" + s.name);
}
