// Scan frames in and out (issue 37): PCD folders whose frames' point counts differ (ragged
// takes), single frame files, KITTI .bin and PLY folders; each written back in its own format
// and read again; the streaming reader's ragged blocks; the bad inputs each named in an error.
// Every file is written here, by hand or by capz's writers.
#include <gtest/gtest.h>

#include <cmath>
#include <cstring>
#include <filesystem>
#include <fstream>
#include <functional>
#include <iterator>
#include <string>
#include <vector>

#include "capz/error.h"
#include "capz/io.h"
#include "capz/stream.h"
#include "capz/tool/compress_file.h"
#include "capz/tool/file.h"
#include "capz/tool/original.h"
#include "support/frame_files.h"
#include "test_util.h"

namespace fs = std::filesystem;
using capz::ErrorCode;
using capz_test::ascii_pcd;
using capz_test::binary_pcd;
using capz_test::floats;
using capz_test::put;
using capz_test::TempDir;

namespace {

// Bytes of float32 values (little-endian hosts).
std::vector<uint8_t> float_bytes(const std::vector<float>& v) {
  std::vector<uint8_t> b(v.size() * 4);
  std::memcpy(b.data(), v.data(), b.size());
  return b;
}

// A ragged take as the readers give it: frames of 3, 0 and 2 points, a NaN gap in frame 0,
// x y z float32 values and an intensity (F 4).
capz::Take scan_take() {
  capz::Take t;
  t.source = "scan";
  t.format = capz::Format::kBinFolder;
  t.units = "m";
  t.resize_ragged({3, 0, 2});
  const float v[5][3] = {{1.5f, -2.25f, 3}, {0, 0, 0}, {0.1f, 0.2f, 0.3f}, {7, 8, 9}, {-1, 0, 1}};
  for (size_t i = 0; i < 5; ++i)
    for (int a = 0; a < 3; ++a) t.xyz[i * 3 + static_cast<size_t>(a)] = v[i][a];
  for (size_t i = 0; i < 5; ++i) t.valid[i] = i == 1 ? 0 : 1;
  capz::PointAttribute in;
  in.name = "intensity";
  in.data = float_bytes({0.5f, 1.0f, 2.0f, 3.0f, 4.25f});
  t.attributes.push_back(in);
  return t;
}

ErrorCode code_of(const std::function<void()>& f, std::string* what = nullptr) {
  try {
    f();
  } catch (const capz::Error& e) {
    if (what) *what = e.what();
    return e.code();
  }
  return static_cast<ErrorCode>(0);
}

void expect_same_points(const capz::Take& a, const capz::Take& b) {
  ASSERT_EQ(a.frames, b.frames);
  ASSERT_EQ(a.frame_offsets, b.frame_offsets);
  ASSERT_EQ(a.points, b.points);
  ASSERT_EQ(a.valid, b.valid);
  for (size_t i = 0; i < a.valid.size(); ++i) {
    if (!a.valid[i]) continue;
    for (int k = 0; k < 3; ++k) {
      EXPECT_EQ(a.xyz[i * 3 + k], b.xyz[i * 3 + k]) << "point " << i;
    }
  }
}

}  // namespace

TEST(ScanIO, GivenPcdFramesOfDifferentCountsWhenReadThenRaggedWithFieldsAndGapsInPlace) {
  TempDir dir;
  put(dir.path() / "f1.pcd", ascii_pcd({{"1", "2", "3", "7", "0.5", "0.25"},
                                        {"nan", "nan", "nan", "8", "1", "2"},
                                        {"4", "5", "6", "9", "-1", "-2"}}));
  put(dir.path() / "f2.pcd", ascii_pcd({}));  // an empty frame, kept
  put(dir.path() / "f10.pcd", ascii_pcd({{"-1", "0", "1", "255", "3", "4"}}));
  const capz::Take t = capz::read_take(dir.path().string());
  ASSERT_TRUE(t.ragged());
  EXPECT_EQ(t.format, capz::Format::kPCDFolder);
  EXPECT_EQ(t.frame_offsets, (std::vector<size_t>{0, 3, 3, 4}));
  EXPECT_EQ(t.pcd->frame_names, (std::vector<std::string>{"f1.pcd", "f2.pcd", "f10.pcd"}));
  EXPECT_EQ(t.units, "m");
  EXPECT_TRUE(t.units_assumed);
  EXPECT_EQ(t.valid, (std::vector<uint8_t>{1, 0, 1, 1}));
  EXPECT_EQ(t.at(2, 0)[0], -1.0);
  ASSERT_EQ(t.attributes.size(), 2u);
  EXPECT_EQ(t.attributes[0].data, (std::vector<uint8_t>{7, 8, 9, 255}));
  ASSERT_EQ(t.attributes[1].count, 2);
  ASSERT_EQ(t.attributes[1].data.size(), 4u * 2 * 4);
  float n[8];
  std::memcpy(n, t.attributes[1].data.data(), sizeof n);
  EXPECT_EQ(n[1], 0.25f);
  EXPECT_EQ(n[7], 4.0f);
  EXPECT_EQ(t.shape_fault(), "");
}

TEST(ScanIO, GivenPcdFramesOfOneCountWhenReadThenFixedAsBefore) {
  TempDir dir;
  put(dir.path() / "a.pcd", binary_pcd(4, 0));
  put(dir.path() / "b.pcd", binary_pcd(4, 10));
  const capz::Take t = capz::read_take(dir.path().string());
  EXPECT_FALSE(t.ragged());
  EXPECT_EQ(t.points, 4u);
  EXPECT_TRUE(t.labels.empty());  // frame files' points have no labels (take.h)
  EXPECT_EQ(t.at(1, 2)[0], 12.0);
  ASSERT_EQ(t.attributes.size(), 1u);
  EXPECT_EQ(t.attributes[0].name, "_");
}

TEST(ScanIO, GivenRaggedTakeWhenWrittenInEachPcdEncodingThenReadBackEqual) {
  for (const char* enc : {"ascii", "binary", "binary_compressed"}) {
    TempDir dir;
    capz::Take t = scan_take();
    t.format = capz::Format::kPCDFolder;
    capz::WriteOptions wo;
    wo.pcd_encoding = enc;
    capz::write_take(t, dir.file("out/"), wo);
    const capz::Take back = capz::read_take(dir.file("out"));
    EXPECT_EQ(back.pcd->encoding, enc);
    expect_same_points(t, back);
    ASSERT_EQ(back.attributes.size(), 1u);
    EXPECT_EQ(back.attributes[0].data, t.attributes[0].data) << enc;
  }
}

TEST(ScanIO, GivenRaggedTakeWhenWrittenAsPlyThenEachEncodingReadsBackEqual) {
  for (const char* enc : {"ascii", "binary_little_endian", "binary_big_endian"}) {
    TempDir dir;
    const capz::Take t = scan_take();
    capz::WriteOptions wo;
    wo.folder_format = capz::Format::kPLYFolder;
    wo.ply_encoding = enc;
    capz::write_take(t, dir.file("ply"), wo);
    ASSERT_TRUE(fs::exists(dir.file("ply/frame_000002.ply"))) << enc;
    const capz::Take back = capz::read_take(dir.file("ply"));
    EXPECT_EQ(back.format, capz::Format::kPLYFolder);
    EXPECT_EQ(back.ply->encoding, enc);
    expect_same_points(t, back);
    ASSERT_EQ(back.attributes.size(), 1u);
    EXPECT_EQ(back.attributes[0].data, t.attributes[0].data) << enc;
    // Written again from what was read: the same files (the source's layout and names kept).
    capz::write_take(back, dir.file("again"));
    for (const auto& name : back.ply->frame_names) {
      std::ifstream a(dir.file("ply/" + name), std::ios::binary),
          b(dir.file("again/" + name), std::ios::binary);
      EXPECT_EQ(std::string(std::istreambuf_iterator<char>(a), {}),
                std::string(std::istreambuf_iterator<char>(b), {}))
          << enc << " " << name;
    }
  }
}

TEST(ScanIO, GivenRaggedTakeWhenWrittenAsBinThenFilesAreSixteenBytesAPointAndReadBack) {
  TempDir dir;
  const capz::Take t = scan_take();
  capz::write_take(t, dir.file("bin/"));  // a .bin take goes back to .bin frames
  EXPECT_EQ(fs::file_size(dir.file("bin/frame_000001.bin")), 3u * 16);
  EXPECT_EQ(fs::file_size(dir.file("bin/frame_000002.bin")), 0u);
  const capz::Take back = capz::read_take(dir.file("bin"));
  EXPECT_EQ(back.format, capz::Format::kBinFolder);
  expect_same_points(t, back);
  EXPECT_EQ(back.attributes[0].data, t.attributes[0].data);
}

TEST(ScanIO, GivenSingleFrameFilesWhenReadThenOneFrameTakes) {
  TempDir dir;
  put(dir.path() / "one.pcd", binary_pcd(5, 1));
  capz::Take t = capz::read_take(dir.file("one.pcd"));
  EXPECT_EQ(t.frames, 1u);
  EXPECT_EQ(t.points, 5u);
  EXPECT_EQ(t.pcd->frame_names, std::vector<std::string>{"one.pcd"});
  // Written as a single file of each format, and read again.
  for (const char* name : {"s.ply", "s.bin", "s.pcd"}) {
    capz::WriteOptions wo;
    wo.drop_fields = true;  // the padding field "_" and a .bin's missing intensity
    capz::write_take(t, dir.file(name), wo);
    ASSERT_TRUE(fs::is_regular_file(dir.file(name))) << name;
    const capz::Take back = capz::read_take(dir.file(name));
    EXPECT_EQ(back.frames, 1u) << name;
    expect_same_points(t, back);
  }
  // A single file holds one frame only.
  capz::Take two = scan_take();
  std::string what;
  EXPECT_EQ(code_of([&] { capz::write_take(two, dir.file("two.ply")); }, &what), ErrorCode::kUsage);
  EXPECT_NE(what.find("two.ply"), std::string::npos) << what;
}

TEST(ScanIO, GivenFolderWhenReadByBlocksThenRaggedBlocksBoundedByTheirFrames) {
  TempDir dir;
  capz::write_take(scan_take(), dir.file("bin/"));
  auto src = capz::open_frames(dir.file("bin"));
  EXPECT_EQ(src->header().frame_offsets, (std::vector<size_t>{0, 3, 3, 5}));
  EXPECT_TRUE(src->header().xyz.empty());
  capz::FrameBlock b;
  src->read(1, 2, &b);
  EXPECT_EQ(b.frame_offsets, (std::vector<size_t>{0, 0, 2}));
  ASSERT_EQ(b.xyz.size(), 6u);
  EXPECT_EQ(b.xyz[0], 7.0);
  ASSERT_EQ(b.attributes.size(), 1u);
  EXPECT_EQ(b.attributes[0].size(), 8u);
}

TEST(ScanIO, GivenBadFramesWhenReadThenErrorNamesTheFile) {
  struct Case {
    const char* name;
    std::string bytes;
    const char* expect;
  };
  std::string ply_head =
      "ply\nformat binary_little_endian 1.0\nelement vertex 2\nproperty float x\n"
      "property float y\nproperty float z\nend_header\n";
  const std::vector<Case> cases = {
      {"short.bin", std::string(16 * 2 + 5, '\0'), "truncated"},
      {"short.ply", ply_head + std::string(12 + 7, '\0'), "truncated"},
      {"lies.pcd", binary_pcd(3, 0, 5), "5 points"},
  };
  for (const Case& c : cases) {
    TempDir dir;
    put(dir.path() / c.name, c.bytes);
    std::string what;
    EXPECT_EQ(code_of([&] { capz::read_take(dir.file(c.name)); }, &what), ErrorCode::kCorrupt)
        << c.name << ": " << what;
    EXPECT_NE(what.find(c.name), std::string::npos) << what;
    EXPECT_NE(what.find(c.expect), std::string::npos) << what;
  }
}

TEST(ScanIO, GivenFrameWithOtherFieldsWhenFolderReadThenErrorNamesIt) {
  TempDir dir;
  put(dir.path() / "a.pcd", binary_pcd(2, 0));
  put(dir.path() / "b.pcd", ascii_pcd({{"1", "2", "3", "7", "0.5", "0.25"}}));
  std::string what;
  EXPECT_EQ(code_of([&] { capz::read_take(dir.path().string()); }, &what), ErrorCode::kCorrupt);
  EXPECT_NE(what.find("b.pcd"), std::string::npos) << what;
  EXPECT_NE(what.find("other fields"), std::string::npos) << what;
  EXPECT_EQ(code_of([&] { capz::open_frames(dir.path().string()); }), ErrorCode::kCorrupt);
}

TEST(ScanIO, GivenScanTakeWhenConvertedAmongFormatsThenPointsKept) {
  TempDir dir;
  capz::Take t = scan_take();
  t.format = capz::Format::kPCDFolder;
  capz::write_take(t, dir.file("pcd/"));
  capz::Take p = capz::read_take(dir.file("pcd"));
  capz::WriteOptions wo;
  wo.folder_format = capz::Format::kPLYFolder;
  capz::write_take(p, dir.file("ply/"), wo);
  EXPECT_TRUE(fs::exists(dir.file("ply/frame_000001.ply")));  // names of the PCD frames, .ply
  capz::Take q = capz::read_take(dir.file("ply"));
  wo.folder_format = capz::Format::kBinFolder;
  capz::write_take(q, dir.file("bin/"), wo);
  capz::Take r = capz::read_take(dir.file("bin"));
  expect_same_points(t, r);
  EXPECT_EQ(r.attributes[0].data, t.attributes[0].data);
  // A field a .bin frame cannot hold is an error naming it, unless dropped.
  capz::PointAttribute ring;
  ring.name = "ring";
  ring.type = 'U';
  ring.size = 2;
  ring.data.assign(5 * 2, 1);
  t.attributes.push_back(ring);
  std::string what;
  EXPECT_EQ(code_of([&] { capz::write_take(t, dir.file("bin2/"), wo); }, &what), ErrorCode::kUsage);
  EXPECT_NE(what.find("ring"), std::string::npos) << what;
  EXPECT_FALSE(fs::exists(dir.file("bin2")));
}

// A .bin frame of 0 bytes (a sweep the driver wrote nothing into) is a frame of no points; with
// --lossless the residue compared its bytes with memcmp from a null pointer, undefined behaviour
// that the sanitizer pass (scripts/test.sh, -fno-sanitize-recover) stops at.
TEST(ScanIO, GivenAnEmptyBinFrameWhenCompressedLosslessThenItRebuilds) {
  TempDir dir;
  put(dir.path() / "000000.bin", "");
  capz::CompressTarget target;
  target.lossless = true;
  capz::compress_file(dir.file("000000.bin"), dir.file("e.capz"), target, capz::CompressOptions(),
                      "", false);
  capz::test_original(dir.file("e.capz"));
  capz::rebuild_original(dir.file("e.capz"), dir.file("back.bin"), false);
  EXPECT_TRUE(fs::exists(dir.file("back.bin")));
  EXPECT_EQ(fs::file_size(dir.file("back.bin")), 0u);
}

// nuScenes (and Lyft) sweeps are .bin files of float32 x y z intensity ring, named NAME.pcd.bin:
// read with both fields, written back 20 bytes a point; converted to PCD as NAME.pcd; a folder
// mixing them with KITTI's files, or a file cut mid-point, is refused naming it.
TEST(ScanIO, GivenNuScenesPcdBinFramesThenReadWithTheirRingAndWrittenBackAsTheyWere) {
  TempDir dir;
  fs::create_directories(dir.path() / "nus");
  const float nan = std::nanf("");
  const std::vector<float> a = {1.5f, -2.25f, 3, 40, 7, nan, nan, nan, 5, 31};  // point 1 a gap
  const std::vector<float> b = {0.1f, 0.2f, 0.3f, 255, 0};
  const std::vector<uint8_t> ab = float_bytes(a), bb = float_bytes(b);
  put(dir.path() / "nus" / "s__LIDAR_TOP__1.pcd.bin", std::string(ab.begin(), ab.end()));
  put(dir.path() / "nus" / "s__LIDAR_TOP__2.pcd.bin", std::string(bb.begin(), bb.end()));
  const capz::Take t = capz::read_take(dir.file("nus"));
  ASSERT_EQ(t.frame_offsets, (std::vector<size_t>{0, 2, 3}));
  ASSERT_EQ(t.attributes.size(), 2u);
  EXPECT_EQ(t.attributes[0].name, "intensity");
  EXPECT_EQ(t.attributes[1].name, "ring");
  EXPECT_EQ(t.attributes[1].type, 'F');
  EXPECT_EQ(t.attributes[1].data, float_bytes({7, 31, 0}));
  EXPECT_EQ(t.valid, (std::vector<uint8_t>{1, 0, 1}));
  EXPECT_EQ(capz::bin_record_text(capz::bin_record_of(t)), "x y z intensity ring");
  capz::write_take(t, dir.file("back/"));
  EXPECT_EQ(capz::read_file(dir.file("back/s__LIDAR_TOP__1.pcd.bin")),
            ab);  // NaN's bits: 0x7fc00000
  EXPECT_EQ(capz::read_file(dir.file("back/s__LIDAR_TOP__2.pcd.bin")), bb);
  // One file written under another name keeps its source's record (its bytes).
  capz::Take one = capz::read_take(dir.file("nus/s__LIDAR_TOP__2.pcd.bin"));
  capz::write_take(one, dir.file("one.bin"));
  EXPECT_EQ(capz::read_file(dir.file("one.bin")), bb);
  // To PCD and back to .bin: NAME.pcd, then NAME.bin, KITTI's (the ring is not its field).
  capz::WriteOptions wo;
  wo.folder_format = capz::Format::kPCDFolder;
  capz::write_take(t, dir.file("pcd/"), wo);
  EXPECT_TRUE(fs::exists(dir.file("pcd/s__LIDAR_TOP__1.pcd")));
  const capz::Take p = capz::read_take(dir.file("pcd"));
  wo.folder_format = capz::Format::kBinFolder;
  std::string what;
  EXPECT_EQ(code_of([&] { capz::write_take(p, dir.file("kitti/"), wo); }, &what),
            ErrorCode::kUsage);
  EXPECT_NE(what.find("x y z intensity)"), std::string::npos) << what;
  // A PCD take written as one file named *.pcd.bin gets nuScenes' record.
  capz::Take p1 = capz::read_take(dir.file("pcd/s__LIDAR_TOP__2.pcd"));
  capz::write_take(p1, dir.file("p1.pcd.bin"));
  EXPECT_EQ(capz::read_file(dir.file("p1.pcd.bin")), bb);
  // Mixed with a KITTI file; cut mid-point (16 bytes is not a whole nuScenes point).
  put(dir.path() / "nus" / "kitti.bin", std::string(16, '\0'));
  EXPECT_EQ(code_of([&] { capz::read_take(dir.file("nus")); }, &what), ErrorCode::kNotOurFormat);
  EXPECT_NE(what.find("nus"), std::string::npos) << what;
  put(dir.path() / "cut.pcd.bin", std::string(16, '\0'));
  EXPECT_EQ(code_of([&] { capz::read_take(dir.file("cut.pcd.bin")); }, &what), ErrorCode::kCorrupt);
  EXPECT_NE(what.find("cut.pcd.bin"), std::string::npos) << what;
  EXPECT_NE(what.find("multiple of 20"), std::string::npos) << what;
}
