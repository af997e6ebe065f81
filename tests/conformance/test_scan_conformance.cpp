// Every scan file of the shared data (../shared/data/scan, README "Scan sequences"): each frame
// file read alone is a one-frame take, each sequence folder a take of its files, with the point
// counts and fields the files' own headers give (read here from the header text, not by capz),
// and the streaming reader giving the same frames as the whole read. Skips with a message when
// the data is absent.
#include <gtest/gtest.h>

#include <algorithm>
#include <filesystem>
#include <fstream>
#include <sstream>
#include <string>
#include <vector>

#include "capz/io.h"
#include "capz/stream.h"
#include "test_util.h"

namespace fs = std::filesystem;

namespace {

struct HeaderCounts {
  size_t points = 0;
  size_t fields = 0;  // FIELDS entries other than x y z
};

// POINTS and FIELDS of a PCD header, read line by line up to DATA.
HeaderCounts pcd_header_counts(const fs::path& file) {
  std::ifstream in(file, std::ios::binary);
  HeaderCounts h;
  std::string line;
  while (std::getline(in, line)) {
    std::istringstream is(line);
    std::string key;
    is >> key;
    if (key == "POINTS") is >> h.points;
    if (key == "FIELDS")
      for (std::string f; is >> f;) h.fields += f != "x" && f != "y" && f != "z";
    if (key == "DATA") break;
  }
  return h;
}

std::vector<fs::path> pcd_files(const fs::path& dir) {
  std::vector<fs::path> v;
  for (const auto& e : fs::directory_iterator(dir))
    if (e.path().extension() == ".pcd") v.push_back(e.path());
  std::sort(v.begin(), v.end());
  return v;
}

}  // namespace

TEST(ScanConformance, GivenEverySharedScanFileWhenReadAloneThenOneFrameOfItsHeaderCount) {
  const std::string root = capz_test::shared_data_or_skip("scan");
  if (root.empty()) return;
  size_t files = 0;
  for (const auto& d : fs::directory_iterator(root)) {
    if (!d.is_directory()) continue;
    for (const fs::path& file : pcd_files(d.path())) {
      SCOPED_TRACE(file.string());
      const HeaderCounts h = pcd_header_counts(file);
      const capz::Take t = capz::read_take(file.string());
      EXPECT_EQ(t.frames, 1u);
      EXPECT_FALSE(t.ragged());
      EXPECT_EQ(t.total_points(), h.points);
      EXPECT_EQ(t.attributes.size(), h.fields);
      EXPECT_EQ(t.units, "m");
      EXPECT_TRUE(t.units_assumed);
      EXPECT_GT(t.total_points() - t.gap_samples(), 0u);
      ++files;
    }
  }
  EXPECT_GE(files, 12u);
}

TEST(ScanConformance, GivenSharedSequencesWhenReadAsFoldersThenRaggedWithEachFilesCount) {
  const std::string root = capz_test::shared_data_or_skip("scan");
  if (root.empty()) return;
  for (const char* seq : {"pandar64-factory20", "robosense-e1", "robosense-helios16p"}) {
    SCOPED_TRACE(seq);
    const fs::path dir = fs::path(root) / seq;
    const std::vector<fs::path> files = pcd_files(dir);
    std::vector<size_t> counts;
    for (const fs::path& f : files) counts.push_back(pcd_header_counts(f).points);
    auto src = capz::open_frames(dir.string());
    const capz::Take& h = src->header();
    ASSERT_EQ(h.frames, files.size());
    EXPECT_TRUE(h.ragged());  // every shared sequence's counts differ
    std::vector<size_t> sorted_counts(h.frames);
    for (size_t f = 0; f < h.frames; ++f) sorted_counts[f] = h.frame_points(f);
    // The reader orders frames naturally; the counts are the files' whatever the order.
    std::sort(sorted_counts.begin(), sorted_counts.end());
    std::sort(counts.begin(), counts.end());
    EXPECT_EQ(sorted_counts, counts);
    // The last frames read by block agree with the whole read.
    const capz::Take whole = capz::read_take(dir.string());
    capz::FrameBlock b;
    const size_t first = h.frames - 2;
    src->read(first, 2, &b);
    ASSERT_EQ(b.total_points(), whole.total_points() - whole.frame_begin(first));
    EXPECT_TRUE(std::equal(b.valid.begin(), b.valid.end(),
                           whole.valid.begin() + static_cast<long>(whole.frame_begin(first))));
    for (size_t a = 0; a < whole.attributes.size(); ++a)
      EXPECT_TRUE(std::equal(
          b.attributes[a].begin(), b.attributes[a].end(),
          whole.attributes[a].data.begin() +
              static_cast<long>(whole.frame_begin(first) * whole.attributes[a].bytes_per_point())));
  }
}

TEST(ScanConformance, GivenSharedSequenceWhenWrittenAsEachFormatThenReadBackEqual) {
  const std::string root = capz_test::shared_data_or_skip("scan/robosense-helios16p");
  if (root.empty()) return;
  const capz::Take t = capz::read_take(root);
  capz_test::TempDir tmp;
  for (capz::Format f : {capz::Format::kPCDFolder, capz::Format::kPLYFolder}) {
    capz::WriteOptions wo;
    wo.folder_format = f;
    const std::string out = tmp.file(capz::format_name(f));
    capz::write_take(t, out + "/", wo);
    const capz::Take back = capz::read_take(out);
    ASSERT_EQ(back.frame_offsets, t.frame_offsets);
    EXPECT_EQ(back.valid, t.valid);
    EXPECT_EQ(back.xyz, t.xyz);
    ASSERT_EQ(back.attributes.size(), t.attributes.size());
    for (size_t a = 0; a < t.attributes.size(); ++a)
      EXPECT_EQ(back.attributes[a].data, t.attributes[a].data) << t.attributes[a].name;
  }
}
