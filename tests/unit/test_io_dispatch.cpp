// Format detection and dispatch (src/io/io.cpp).
#include <gtest/gtest.h>

#include <fstream>
#include <string>

#include "capz/error.h"
#include "capz/io.h"
#include "test_util.h"

using capz::ErrorCode;
using capz::Format;

namespace {

ErrorCode read_error(const std::string& path, std::string* msg = nullptr) {
  return capz_test::error_of([&] { capz::read_take(path); }, msg);
}

}  // namespace

TEST(IoDispatch, DetectsByContentThenExtension) {
  capz_test::TempDir d("capz_io");
  std::ofstream(d.file("a.txt")) << "PathFileType\t4\t(X/Y/Z)\ta.trc\n";
  std::ofstream(d.file("b.dat"), std::ios::binary) << std::string("\x02\x50\x00\x00", 4);
  std::ofstream(d.file("empty.trc"));
  std::ofstream(d.file("empty.c3d"));
  std::ofstream(d.file("x.xyz")) << "hello";
  EXPECT_EQ(capz::detect_format(d.path().string()), Format::kPCDFolder);  // no frame files
  std::ofstream(d.file("x.bin")) << "hello";
  EXPECT_EQ(capz::detect_format(d.path().string()), Format::kBinFolder);  // by its frame files
  EXPECT_EQ(capz::detect_format(d.file("a.txt")), Format::kTRC);
  std::ofstream(d.file("bom.txt")) << "\xEF\xBB\xBFPathFileType\t4\n";
  EXPECT_EQ(capz::detect_format(d.file("bom.txt")), Format::kTRC);
  EXPECT_EQ(capz::detect_format(d.file("b.dat")), Format::kC3D);
  EXPECT_EQ(capz::detect_format(d.file("empty.trc")), Format::kTRC);
  EXPECT_EQ(capz::detect_format(d.file("empty.c3d")), Format::kC3D);
  EXPECT_EQ(capz::detect_format(d.file("x.xyz")), Format::kUnknown);
  EXPECT_EQ(capz::detect_format(d.file("x.bin")), Format::kBinFolder);  // one .bin frame
  try {
    capz::detect_format(d.file("missing"));
    FAIL();
  } catch (const capz::Error& e) {
    EXPECT_EQ(e.code(), ErrorCode::kIo);
  }
}

TEST(IoDispatch, ReadTakeRoutesAndRefusesWhatIsNotATake) {
  capz_test::TempDir d("capz_io");
  std::ofstream(d.file("a.txt"))
      << "PathFileType\t4\nDataRate\tNumFrames\n100\t1\nFrame#\tTime\tA\n"
         "\t\tX1\tY1\tZ1\n1\t0\t1\t2\t3\n";
  std::ofstream(d.file("z.capz"), std::ios::binary) << "\x89"
                                                       "capz\r\n\x1a\n\x01\x00";
  std::ofstream(d.file("renamed.dat"), std::ios::binary) << "\x89"
                                                            "capz\r\n\x1a\n\x01\x00";
  std::ofstream(d.file("frame.pcd")) << "VERSION 0.7\n";
  std::ofstream(d.file("x.bin")) << "hello";
  capz::Take t = capz::read_take(d.file("a.txt"));
  EXPECT_EQ(t.format, Format::kTRC);
  EXPECT_EQ(t.points, 1u);
  std::string msg;
  EXPECT_EQ(read_error(d.file("z.capz"), &msg), ErrorCode::kNotOurFormat);
  EXPECT_NE(msg.find(".capz archive, not a take"), std::string::npos) << msg;
  EXPECT_EQ(read_error(d.file("renamed.dat"), &msg), ErrorCode::kNotOurFormat);
  EXPECT_NE(msg.find(".capz archive, not a take"), std::string::npos) << msg;
  // A single frame file is a one-frame take: these two are damaged ones.
  EXPECT_EQ(read_error(d.file("frame.pcd"), &msg), ErrorCode::kCorrupt);
  EXPECT_NE(msg.find("frame.pcd: PCD header has no DATA line"), std::string::npos) << msg;
  EXPECT_EQ(read_error(d.file("x.bin"), &msg), ErrorCode::kCorrupt);
  EXPECT_NE(msg.find("x.bin: .bin frame truncated mid-point"), std::string::npos) << msg;
  std::ofstream(d.file("x.dat")) << "hello";
  EXPECT_EQ(read_error(d.file("x.dat"), &msg), ErrorCode::kNotOurFormat);
  EXPECT_EQ(read_error(d.file("nope.trc"), &msg), ErrorCode::kIo);
}

TEST(IoDispatch, OutputFormatFollowsTheName) {
  capz_test::TempDir d("capz_io");
  EXPECT_EQ(capz::format_for_output("x/walk.c3d"), Format::kC3D);
  EXPECT_EQ(capz::format_for_output("x/walk.TRC"), Format::kTRC);
  EXPECT_EQ(capz::format_for_output("x/frames/"), Format::kPCDFolder);
  EXPECT_EQ(capz::format_for_output("x/frames"), Format::kPCDFolder);
  EXPECT_EQ(capz::format_for_output(d.path().string()), Format::kPCDFolder);
  EXPECT_EQ(capz::format_for_output("x/walk.capz"), Format::kUnknown);
  EXPECT_EQ(capz::format_for_output("x/walk.pcd"), Format::kPCDFolder);  // one frame file
  EXPECT_EQ(capz::format_for_output("x/walk.PLY"), Format::kPLYFolder);
  EXPECT_EQ(capz::format_for_output("x/000001.bin"), Format::kBinFolder);
  EXPECT_EQ(capz::format_for_output("x/walk.xyz"), Format::kUnknown);
  capz::Take t;
  t.resize(1, 1);
  try {
    capz::write_take(t, d.file("out.xyz"));
    FAIL();
  } catch (const capz::Error& e) {
    EXPECT_EQ(e.code(), ErrorCode::kUsage);
  }
  capz::write_take(t, d.file("seq") + "/");
  EXPECT_EQ(capz::read_take(d.file("seq")).frames, 1u);
}
