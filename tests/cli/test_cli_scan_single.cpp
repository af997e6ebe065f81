// Single frame files and negative zeros through the built binary: a one-frame archive is shown by
// `capz info` (text and --json) as the fixed frame every reader gives it; `compress --lossless
// --rm` of one PCD file checks the archive against that file; a PLY of x y z alone compresses; a
// ragged folder of ascii and binary double PLY frames with `-0.000000`, `-0` and -0.0 comes back
// byte for byte (docs/FORMAT.md "Lossless ragged streams", negative zeros); the compress line of
// a lossless float32 split names its grids as `info` does.
#include <gtest/gtest.h>
#include <sys/wait.h>

#include <cstdlib>
#include <cstring>
#include <filesystem>
#include <fstream>
#include <string>

#include "test_util.h"

namespace {

namespace fs = std::filesystem;

// Runs `capz <args>`; returns the exit status, stdout and stderr into *out.
int capz_run(const std::string& args, const capz_test::TempDir& dir, std::string* out) {
  const std::string o = dir.file("stdout");
  const int rc = std::system((std::string(CAPZ_CLI) + " " + args + " >" + o + " 2>&1").c_str());
  *out = capz_test::file_text(o);
  return WIFEXITED(rc) ? WEXITSTATUS(rc) : -1;
}

void put(const std::string& path, const std::string& bytes) {
  std::ofstream f(path, std::ios::binary);
  f << bytes;
}

// A frame's double x y z on the 0.01 grid, with negative zeros, as ascii PLY text or binary.
const char* const kRows[] = {"1.100000 -0.000000 2.250000", "-0 0.100000 -3.500000",
                             "0.000000 4.010000 -0.000000", "5.500000 -0.000000 7.750000"};

std::string ascii_ply(size_t n) {
  std::string s = "ply\nformat ascii 1.0\nelement vertex " + std::to_string(n) +
                  "\nproperty double x\nproperty double y\nproperty double z\nend_header\n";
  for (size_t i = 0; i < n; ++i) s += std::string(kRows[i]) + "\n";
  return s;
}

std::string binary_ply(size_t n) {
  std::string s = "ply\nformat binary_little_endian 1.0\nelement vertex " + std::to_string(n) +
                  "\nproperty double x\nproperty double y\nproperty double z\nend_header\n";
  for (size_t i = 0; i < n; ++i) {
    char a[32], b[32], c[32];
    if (std::sscanf(kRows[i], "%31s %31s %31s", a, b, c) != 3) return "";
    for (const char* t : {a, b, c}) {
      const double d = std::strtod(t, nullptr);
      char bytes[8];
      std::memcpy(bytes, &d, 8);
      s.append(bytes, 8);
    }
  }
  return s;
}

}  // namespace

TEST(CliScanSingle, RaggedDoublePLYFoldersWithNegativeZerosComeBackByteForByte) {
  capz_test::TempDir dir("capz_cli_nz");
  std::string out;
  for (const char* form : {"ascii", "binary"}) {
    const std::string in = dir.file(form), back = dir.file(std::string(form) + "_back");
    fs::create_directories(in);
    for (size_t f = 0; f < 3; ++f)
      put(in + "/" + std::to_string(f) + ".ply",
          form[0] == 'a' ? ascii_ply(2 + f) : binary_ply(2 + f));
    const std::string z = dir.file(std::string(form) + ".capz");
    ASSERT_EQ(capz_run("compress " + in + " -o " + z + " --lossless", dir, &out), 0) << out;
    EXPECT_NE(out.find("lossless (decimal-grid)"), std::string::npos) << out;
    ASSERT_EQ(capz_run("decompress -q " + z + " -o " + back + "/", dir, &out), 0) << out;
    for (size_t f = 0; f < 3; ++f) {
      const std::string n = "/" + std::to_string(f) + ".ply";
      EXPECT_EQ(std::system(("cmp -s " + in + n + " " + back + n).c_str()), 0) << form << n;
    }
    ASSERT_EQ(capz_run("verify " + z + " --against " + in, dir, &out), 0) << out;
  }
}

// `capz info` of a one-frame archive coded by the scan coder (one ragged frame, SCNW) shows the
// fixed frame that decompress and every reader give: "1 frames x 4 points", JSON points 4 and an
// unorganized layout as wide, no "of their own point counts". With --lossless --rm the file goes
// once the archive rebuilds it (before, the check looked for a folder and kept the file).
TEST(CliScanSingle, OneFrameArchiveIsShownAsTheReaderGivesItAndRmChecksTheFile) {
  capz_test::TempDir dir("capz_cli_one");
  const std::string in = dir.file("one.pcd"), z = dir.file("one.capz"), back = dir.file("b.pcd");
  std::string text =
      "# .PCD v0.7\nVERSION 0.7\nFIELDS x y z\nSIZE 8 8 8\nTYPE F F F\nCOUNT 1 1 1\n"
      "WIDTH 4\nHEIGHT 1\nVIEWPOINT 0 0 0 1 0 0 0\nPOINTS 4\nDATA ascii\n";
  for (const char* row : kRows) text += std::string(row) + "\n";
  put(in, text);
  std::string out;
  ASSERT_EQ(capz_run("compress --lossless --rm " + in + " -o " + z, dir, &out), 0) << out;
  EXPECT_FALSE(fs::exists(in)) << out;
  ASSERT_EQ(capz_run("info " + z, dir, &out), 0) << out;
  EXPECT_NE(out.find("SCNW"), std::string::npos) << out;  // the one-ragged-frame stream
  EXPECT_NE(out.find("take:        1 frames x 4 points"), std::string::npos) << out;
  EXPECT_EQ(out.find("of their own point counts"), std::string::npos) << out;
  EXPECT_NE(out.find("layout:      unorganized"), std::string::npos) << out;
  ASSERT_EQ(capz_run("info --json " + z, dir, &out), 0) << out;
  EXPECT_NE(out.find("\"points\":4,"), std::string::npos) << out;
  EXPECT_NE(out.find("\"width\":4,"), std::string::npos) << out;
  ASSERT_EQ(capz_run("decompress -q " + z + " -o " + back, dir, &out), 0) << out;
  EXPECT_EQ(capz_test::file_text(back), text);
  ASSERT_EQ(capz_run("decompress --json -f " + z + " -o " + back, dir, &out), 0) << out;
  EXPECT_NE(out.find("\"points\":4,"), std::string::npos) << out;
}

// A PLY of x y z alone (no other property) compresses as one file, at a bound and losslessly;
// before, the scan coder's trial had no point layout for it ("frame-file source without a PCD
// layout").
TEST(CliScanSingle, PLYOfXYZAloneCompresses) {
  capz_test::TempDir dir("capz_cli_xyz_ply");
  const std::string in = dir.file("xyz.ply");
  put(in, ascii_ply(4));
  std::string out;
  ASSERT_EQ(capz_run("compress -e 1mm " + in + " -o " + dir.file("a.capz"), dir, &out), 0) << out;
  ASSERT_EQ(capz_run("compress --lossless " + in + " -o " + dir.file("l.capz"), dir, &out), 0)
      << out;
  ASSERT_EQ(capz_run("decompress -q " + dir.file("l.capz") + " -o " + dir.file("b.ply"), dir, &out),
            0)
      << out;
  EXPECT_EQ(capz_test::file_text(dir.file("b.ply")), capz_test::file_text(in));
}

// The compress line of a lossless folder whose windows take a float32 split names the grids as
// `capz info`'s coding line does, not a bare "float32-split".
TEST(CliScanSingle, CompressLineNamesTheFloat32SplitGrids) {
  capz_test::TempDir dir("capz_cli_split_line");
  const std::string src = std::string(CAPZ_REPO_DATA) + "/scan_small", z = dir.file("s.capz");
  std::string line, info;
  ASSERT_EQ(capz_run("compress " + src + " -o " + z + " --lossless --window 1", dir, &line), 0)
      << line;
  ASSERT_EQ(capz_run("info " + z, dir, &info), 0) << info;
  const size_t at = info.find("coding:      float32 split on the grid");
  ASSERT_NE(at, std::string::npos) << info;
  const size_t from = at + std::strlen("coding:      ");
  const std::string split = info.substr(from, info.find(", lossless", from) - from);
  EXPECT_NE(line.find("lossless (" + split + ")"), std::string::npos) << line << "\n" << split;
  EXPECT_EQ(line.find("(float32-split)"), std::string::npos) << line;
  ASSERT_EQ(
      capz_run("compress --json -f " + src + " -o " + z + " --lossless --window 1", dir, &line), 0)
      << line;
  EXPECT_NE(line.find("\"float32_split_windows\":{"), std::string::npos) << line;
}
