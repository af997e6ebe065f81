// `--bin-fields`: .bin frames in a record other than KITTI's or nuScenes', through compress,
// decompress, verify, info, convert and compress --rm as a user runs them; a record the frames
// do not fit draws a warning naming the option, and a bad record text is one line and no output.
#include <gtest/gtest.h>

#include <algorithm>
#include <cmath>
#include <cstdint>
#include <cstring>
#include <filesystem>
#include <string>

#include "support/frame_files.h"
#include "test_util.h"

namespace {

namespace fs = std::filesystem;
using capz_test::TempDir;

capz_test::CliResult capz_run(const std::string& args, const TempDir& dir) {
  return capz_test::run_command(CAPZ_CLI, args, dir.file("stdout"));
}

// A sweep of `n` points as float32 x y z, float32 intensity, uint16 ring, float64 time (22 bytes
// a point; n a multiple of 8 is a whole number of KITTI's 16-byte points too, and n not a multiple
// of 10 is not one of 20-byte points).
std::string sweep(size_t n, int f) {
  std::string s;
  for (size_t i = 0; i < n; ++i) {
    const double a = 0.013 * static_cast<double>(i) + 0.1 * f;
    capz_test::append_bytes(&s, static_cast<float>(15 * std::cos(a)));
    capz_test::append_bytes(&s, static_cast<float>(15 * std::sin(a)));
    capz_test::append_bytes(&s, static_cast<float>(-1.0 + 0.002 * static_cast<double>(i % 64)));
    capz_test::append_bytes(&s, static_cast<float>(i % 200));
    capz_test::append_bytes(&s, static_cast<uint16_t>(i % 64));
    capz_test::append_bytes(&s, 1.7e9 + 0.1 * f + 1e-5 * static_cast<double>(i));
  }
  return s;
}

const char kRecord[] = "'x y z intensity ring:U2 t:F8'";

// The folder `name` in dir of three sweeps of their own counts.
std::string make_folder(const TempDir& dir, const std::string& name) {
  fs::create_directories(dir.path() / name);
  const size_t counts[] = {808, 648, 728};
  for (int f = 0; f < 3; ++f)
    capz_test::put(dir.path() / name / ("00000" + std::to_string(f) + ".bin"), sweep(counts[f], f));
  return dir.file(name);
}

}  // namespace

TEST(CliBinFields, GivenADeclaredRecordThenEveryCommandReadsItAndLosslessGivesTheFilesBack) {
  TempDir dir;
  const std::string in = make_folder(dir, "in");
  auto r = capz_run("info '" + in + "' --bin-fields " + kRecord, dir);
  ASSERT_EQ(r.status, 0) << r.out;
  EXPECT_NE(r.out.find("x y z intensity ring:U2 t:F8, given by --bin-fields"), std::string::npos)
      << r.out;
  EXPECT_NE(r.out.find("2184 in all"), std::string::npos) << r.out;
  EXPECT_NE(r.out.find("warnings:  none"), std::string::npos) << r.out;
  r = capz_run("compress '" + in + "' --lossless --bin-fields " + kRecord + " -o '" +
                   dir.file("l.capz") + "'",
               dir);
  ASSERT_EQ(r.status, 0) << r.out;
  r = capz_run("decompress '" + dir.file("l.capz") + "' -o '" + dir.file("back") + "'", dir);
  ASSERT_EQ(r.status, 0) << r.out;
  for (const char* f : {"000000.bin", "000001.bin", "000002.bin"})
    EXPECT_EQ(capz_test::file_text(dir.file(std::string("back/") + f)),
              capz_test::file_text(in + "/" + f))
        << f;
  // At a bound: verify reads the original in the archive's record, without the option.
  r = capz_run("compress '" + in + "' --max-error 1mm --bin-fields " + kRecord + " -o '" +
                   dir.file("b.capz") + "'",
               dir);
  ASSERT_EQ(r.status, 0) << r.out;
  r = capz_run("verify '" + dir.file("b.capz") + "' --against '" + in + "'", dir);
  EXPECT_EQ(r.status, 0) << r.out;
  EXPECT_NE(r.out.find("bound 0.001 m holds"), std::string::npos) << r.out;
  // convert to PCD: the fields keep their types.
  r = capz_run("convert '" + in + "' '" + dir.file("pcd/") + "' --to pcd --bin-fields " + kRecord,
               dir);
  ASSERT_EQ(r.status, 0) << r.out;
  const std::string head = capz_test::file_text(dir.file("pcd/000001.pcd")).substr(0, 200);
  EXPECT_NE(head.find("FIELDS x y z intensity ring t"), std::string::npos) << head;
  EXPECT_NE(head.find("SIZE 4 4 4 4 2 8"), std::string::npos) << head;
  // --rm reads IN again in the record before it lets IN go.
  const std::string copy = make_folder(dir, "copy");
  r = capz_run("compress '" + copy + "' --max-error 1mm --rm --bin-fields " + kRecord + " -o '" +
                   dir.file("c.capz") + "'",
               dir);
  ASSERT_EQ(r.status, 0) << r.out;
  EXPECT_FALSE(fs::exists(copy + "/000000.bin"));
  EXPECT_TRUE(fs::exists(dir.file("c.capz")));
}

TEST(CliBinFields, GivenFramesOfAnotherRecordReadAsKittiThenAWarningNamesTheOption) {
  TempDir dir;
  const std::string in = make_folder(dir, "in");
  auto r = capz_run("info '" + in + "'", dir);
  ASSERT_EQ(r.status, 0) << r.out;
  EXPECT_NE(r.out.find("KITTI"), std::string::npos) << r.out;
  EXPECT_NE(r.out.find("--bin-fields gives it"), std::string::npos) << r.out;
  r = capz_run("compress '" + in + "' --lossless -o '" + dir.file("k.capz") + "'", dir);
  ASSERT_EQ(r.status, 0) << r.out;
  EXPECT_NE(r.out.find("capz compress: warning: " + in + ": 000000.bin: "), std::string::npos)
      << r.out;
}

TEST(CliBinFields, GivenABadRecordOrAnotherFormatThenOneLineAndNoOutput) {
  TempDir dir;
  const std::string in = make_folder(dir, "in");
  for (const char* bad : {"'x y z i:Q4'", "'y x z'", "'x y z i i'"}) {
    auto r = capz_run(
        "compress '" + in + "' --bin-fields " + bad + " -o '" + dir.file("x.capz") + "'", dir);
    EXPECT_EQ(r.status, 1) << bad << ": " << r.out;
    EXPECT_NE(r.out.find("--bin-fields"), std::string::npos) << r.out;
    EXPECT_EQ(std::count(r.out.begin(), r.out.end(), '\n'), 1) << r.out;
    EXPECT_FALSE(fs::exists(dir.file("x.capz")));
  }
  // 22 bytes a point: 808 points are not a whole number of points of a 20-byte record.
  auto r = capz_run(
      "compress '" + in + "' --bin-fields 'x y z i ring' -o '" + dir.file("x.capz") + "'", dir);
  EXPECT_NE(r.status, 0) << r.out;
  EXPECT_NE(r.out.find("not a multiple of 20"), std::string::npos) << r.out;
  EXPECT_FALSE(fs::exists(dir.file("x.capz")));
  capz_test::put(dir.path() / "one.pcd", capz_test::binary_pcd(10, 1.0f));
  r = capz_run("info '" + dir.file("one.pcd") + "' --bin-fields 'x y z i'", dir);
  EXPECT_EQ(r.status, 1) << r.out;
  EXPECT_NE(r.out.find("--bin-fields is for .bin frames"), std::string::npos) << r.out;
}
