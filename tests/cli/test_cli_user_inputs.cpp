// Frame files as other writers leave them (docs/lab/2026-11-30-user-inputs.md): headers PCL
// would not write, folders holding more than frames, coordinates far from the origin. Each
// through `capz compress` and `decompress` as a user runs them: the files come back (byte for
// byte with --lossless), or one line names the file and nothing is left behind.
#include <gtest/gtest.h>

#include <cstdint>
#include <filesystem>
#include <string>
#include <vector>

#include "support/frame_files.h"
#include "test_util.h"

namespace {

namespace fs = std::filesystem;
using capz_test::TempDir;

capz_test::CliResult capz_run(const std::string& args, const TempDir& dir) {
  return capz_test::run_command(CAPZ_CLI, args, dir.file("stdout"));
}

}  // namespace

// One PCD file whose header differs from the one capz writes (here: no VIEWPOINT line) is a
// one-frame take; its archive used to describe the header against another WIDTH and POINTS than
// the decoder regenerates, so `decompress` refused it (hash differs) after `compress` had passed.
TEST(CliUserInputs, GivenOneFrameFileWithItsOwnHeaderThenLosslessGivesItBack) {
  TempDir dir;
  const std::string in = dir.file("sweep.pcd");
  capz_test::put(in, capz_test::binary_pcd(500, 3.0f));
  const std::string args = "'" + in + "' -o '" + dir.file("s.capz") + "' --lossless";
  auto r = capz_run("compress " + args, dir);
  ASSERT_EQ(r.status, 0) << r.out;
  r = capz_run("decompress '" + dir.file("s.capz") + "' -o '" + dir.file("back.pcd") + "'", dir);
  ASSERT_EQ(r.status, 0) << r.out;
  EXPECT_EQ(capz_test::file_text(dir.file("back.pcd")), capz_test::file_text(in));
  r = capz_run("test '" + dir.file("s.capz") + "'", dir);
  EXPECT_EQ(r.status, 0) << r.out;
}

// A folder holding .pcd and .ply frames was read as its .pcd frames alone: the .ply frames were
// left out of the archive without a word (a --lossless archive of the folder did not give them
// back). Now refused, naming a file of each format, and no archive is left.
TEST(CliUserInputs, GivenAFolderOfPcdAndPlyFramesThenRefusedNamingBoth) {
  TempDir dir;
  fs::create_directory(dir.path() / "mixed");
  capz_test::put(dir.path() / "mixed" / "0.pcd", capz_test::binary_pcd(20, 0.0f));
  capz_test::put(dir.path() / "mixed" / "1.ply",
                 "ply\nformat ascii 1.0\nelement vertex 1\nproperty float x\nproperty float y\n"
                 "property float z\nend_header\n1 2 3\n");
  for (const char* opt : {"", " --lossless"}) {
    const auto r =
        capz_run("compress '" + dir.file("mixed") + "' -o '" + dir.file("m.capz") + "'" + opt, dir);
    EXPECT_EQ(r.status, 3) << r.out;
    EXPECT_NE(r.out.find("0.pcd"), std::string::npos) << r.out;
    EXPECT_NE(r.out.find("1.ply"), std::string::npos) << r.out;
    EXPECT_FALSE(fs::exists(dir.file("m.capz")));
  }
}

// macOS leaves a "._NAME" file beside each file it copies to a foreign file system; one named
// "._0.pcd" made the folder's compression fail (not a PCD file). Hidden files are no frames.
TEST(CliUserInputs, GivenAHiddenFileBesideTheFramesThenItIsNoFrame) {
  TempDir dir;
  fs::create_directory(dir.path() / "sweeps");
  const std::string frame = capz_test::binary_pcd(50, 2.0f);
  capz_test::put(dir.path() / "sweeps" / "0.pcd", frame);
  capz_test::put(dir.path() / "sweeps" / "._0.pcd", std::string("\0\5\26\7", 4) + "Mac OS X");
  auto r = capz_run(
      "compress '" + dir.file("sweeps") + "' -o '" + dir.file("s.capz") + "' --lossless", dir);
  ASSERT_EQ(r.status, 0) << r.out;
  r = capz_run("decompress '" + dir.file("s.capz") + "' -o '" + dir.file("back") + "/'", dir);
  ASSERT_EQ(r.status, 0) << r.out;
  EXPECT_EQ(capz_test::file_text(dir.file("back/0.pcd")), frame);
  EXPECT_FALSE(fs::exists(dir.file("back/._0.pcd")));
  r = capz_run("info '" + dir.file("sweeps") + "'", dir);
  EXPECT_EQ(r.status, 0) << r.out;
}

// float32 frames far from the origin (UTM-like: y near 5e6 m, where float32 values are 0.5 m
// apart). A bound below half that spacing cannot hold once the decoded frames are written back
// as float32: refused, and the message spoke of "a C3D" and printed 1e30 in 37 digits. With no
// bound given, the default (1e-4 of the diagonal) was refused the same way, exit 6; it now keeps
// the float32 values as they are, and a note says why and which bound would hold (it was silent).
TEST(CliUserInputs, GivenFloat32FramesFarFromTheOriginThenDefaultIsLosslessAndFineBoundsSayWhy) {
  TempDir dir;
  const std::string in = dir.file("utm.pcd");
  const std::string frame = capz_test::binary_pcd(200, 5e6f);
  capz_test::put(in, frame);
  auto r = capz_run("compress '" + in + "' -o '" + dir.file("u.capz") + "'", dir);
  ASSERT_EQ(r.status, 0) << r.out;
  EXPECT_NE(r.out.find("lossless"), std::string::npos) << r.out;
  EXPECT_NE(r.out.find("note: " + in + ": float32 coordinates up to"), std::string::npos) << r.out;
  EXPECT_NE(r.out.find("0.5 m apart there"), std::string::npos) << r.out;
  EXPECT_NE(r.out.find("a --max-error above 0.25 m gives a bound"), std::string::npos) << r.out;
  r = capz_run("decompress '" + dir.file("u.capz") + "' -o '" + dir.file("back.pcd") + "'", dir);
  ASSERT_EQ(r.status, 0) << r.out;
  EXPECT_TRUE(capz_test::file_text(dir.file("back.pcd")) == frame);
  r = capz_run("compress '" + in + "' -o '" + dir.file("c.capz") + "' --max-error 1mm", dir);
  EXPECT_EQ(r.status, 6) << r.out;
  EXPECT_NE(r.out.find("utm.pcd"), std::string::npos) << r.out;
  EXPECT_EQ(r.out.find("C3D"), std::string::npos) << r.out;
  EXPECT_NE(r.out.find("--lossless"), std::string::npos) << r.out;
  EXPECT_FALSE(fs::exists(dir.file("c.capz")));
  // --point-order any has no lossless archive: its default bound is refused for what it is,
  // not for a --lossless the user did not give.
  r = capz_run("compress '" + in + "' -o '" + dir.file("c.capz") + "' --point-order any", dir);
  EXPECT_EQ(r.status, 6) << r.out;
  EXPECT_NE(r.out.find("float32 resolution"), std::string::npos) << r.out;
  EXPECT_FALSE(fs::exists(dir.file("c.capz")));
}

namespace {

// A .bin sweep of 20,000 points in a 100 x 100 x 10 m box plus one stray point at (x, 0, 0).
std::string sweep_with_a_stray(float x) {
  std::vector<float> v;
  uint32_t r = 12345;
  auto next = [&r] {
    return static_cast<float>((r = r * 1103515245u + 12345u) >> 8) / 16777216.0f;
  };
  for (int i = 0; i < 20000; ++i) {
    const float a = 100 * next(), b = 100 * next(), c = 10 * next();
    v.insert(v.end(), {i == 5 ? x : a, i == 5 ? 0.0f : b, i == 5 ? 0.0f : c, next()});
  }
  return capz_test::floats(v);
}

}  // namespace

// The default bound of data without units is 1e-4 of the box's diagonal, so one stray point (a
// driver's far garbage return) set it for every point: one point at 500 km gave a 50 m bound,
// one at 1e30 m put every other point at the origin's grid cell. The few far points no longer
// set it: the others' box does (made coarse enough to hold at the stray), or the sweep is kept
// lossless when no such bound holds; a note says so.
TEST(CliUserInputs, GivenAStrayPointThenTheDefaultBoundIsTheOthers) {
  TempDir dir;
  const std::string far = dir.file("far.bin"), wild = dir.file("wild.bin");
  capz_test::put(far, sweep_with_a_stray(5e5f));
  capz_test::put(wild, sweep_with_a_stray(1e30f));
  auto r = capz_run("compress '" + far + "' -o '" + dir.file("f.capz") + "' --json", dir);
  ASSERT_EQ(r.status, 0) << r.out;
  EXPECT_NE(r.out.find("far outside the others"), std::string::npos) << r.out;
  const size_t at = r.out.find("\"max_error_target\":");
  ASSERT_NE(at, std::string::npos) << r.out;
  const double bound = std::stod(r.out.substr(at + 19));
  EXPECT_GT(bound, 0.01) << r.out;  // 1e-4 of the others' 141.8 m, doubled for float32 at 5e5 m
  EXPECT_LT(bound, 0.05) << r.out;  // not 50 m
  r = capz_run("verify '" + dir.file("f.capz") + "' --against '" + far + "'", dir);
  EXPECT_EQ(r.status, 0) << r.out;
  r = capz_run("compress '" + wild + "' -o '" + dir.file("w.capz") + "'", dir);
  ASSERT_EQ(r.status, 0) << r.out;
  EXPECT_NE(r.out.find("kept lossless"), std::string::npos) << r.out;
  r = capz_run("decompress '" + dir.file("w.capz") + "' -o '" + dir.file("back.bin") + "'", dir);
  ASSERT_EQ(r.status, 0) << r.out;
  EXPECT_TRUE(capz_test::file_text(dir.file("back.bin")) == capz_test::file_text(wild));
  // A bound given is the bound used, note or none.
  r = capz_run("compress '" + far + "' -o '" + dir.file("g.capz") + "' --max-error 5cm", dir);
  ASSERT_EQ(r.status, 0) << r.out;
  EXPECT_EQ(r.out.find("far outside"), std::string::npos) << r.out;
}

// A .bin frame stores float32 x y z intensity: converting double-precision PCD frames to it
// rounded them without a word. A note says so now; float32 sources convert as they did.
TEST(CliUserInputs, GivenFloat64FramesThenConvertingToBinSaysTheyAreRounded) {
  TempDir dir;
  const std::string in = dir.file("d.pcd");
  capz_test::put(in,
                 "# .PCD v0.7\nVERSION 0.7\nFIELDS x y z intensity\nSIZE 8 8 8 4\nTYPE F F F F\n"
                 "COUNT 1 1 1 1\nWIDTH 2\nHEIGHT 1\nPOINTS 2\nDATA ascii\n"
                 "0.123456789012 1 2 3\n4 5 6.000000001 7\n");
  auto r = capz_run("convert '" + in + "' '" + dir.file("out") + "/' --to bin", dir);
  ASSERT_EQ(r.status, 0) << r.out;
  EXPECT_NE(r.out.find("float64 values (x y z: rounded to float32)"), std::string::npos) << r.out;
  EXPECT_TRUE(fs::exists(dir.file("out/d.bin")));
  capz_test::put(dir.file("f.pcd"), capz_test::binary_pcd(3, 1.0f));
  r = capz_run("convert '" + dir.file("f.pcd") + "' '" + dir.file("out2") + "/' --to bin", dir);
  ASSERT_EQ(r.status, 0) << r.out;
  EXPECT_EQ(r.out.find("float64"), std::string::npos) << r.out;
}

// CloudCompare writes its scalar fields as scalar_NAME, floats and integers side by side;
// --attr-error scalar=B (NAME_* stands for every such field) was refused because one of them
// holds integers. The float ones are bounded now, the integer ones kept as they are.
TEST(CliUserInputs, GivenScalarFieldsOfBothKindsThenAPrefixBoundsTheFloatOnes) {
  TempDir dir;
  const std::string in = dir.file("cc.ply");
  std::string body;
  for (int p = 0; p < 300; ++p) {
    body += capz_test::floats({0.1f * static_cast<float>(p), 2.0f, static_cast<float>(p % 7),
                               0.001f * static_cast<float>(p * p % 1000)});
    body += static_cast<char>(p % 5);
  }
  capz_test::put(in,
                 "ply\nformat binary_little_endian 1.0\ncomment Author: CloudCompare\n"
                 "element vertex 300\nproperty float x\nproperty float y\nproperty float z\n"
                 "property float scalar_Intensity\nproperty uchar scalar_Classification\n"
                 "end_header\n" +
                     body);
  auto r = capz_run("compress '" + in + "' -o '" + dir.file("c.capz") +
                        "' --max-error 1mm --attr-error scalar=0.01",
                    dir);
  ASSERT_EQ(r.status, 0) << r.out;
  r = capz_run("verify '" + dir.file("c.capz") + "' --against '" + in + "'", dir);
  EXPECT_EQ(r.status, 0) << r.out;
  r = capz_run("info '" + dir.file("c.capz") + "'", dir);
  EXPECT_NE(r.out.find("scalar_Intensity"), std::string::npos) << r.out;
  // An integer field named as it is stays an error.
  r = capz_run(
      "compress '" + in + "' -o '" + dir.file("d.capz") + "' --attr-error scalar_Classification=1",
      dir);
  EXPECT_EQ(r.status, 6) << r.out;
  EXPECT_FALSE(fs::exists(dir.file("d.capz")));
}

// Extensions in upper case (cameras' and Windows tools' habit): `decompress walk.C3D.capz` gave
// walk.C3D.c3d, and a one-frame archive of scan.PCD the folder scan.PCD/scan.PCD; each now
// comes back under its own name, byte for byte with --lossless.
TEST(CliUserInputs, GivenUpperCaseExtensionsThenDecompressGivesTheSameNamesBack) {
  TempDir dir;
  const std::string data = CAPZ_REPO_DATA;
  fs::copy_file(data + "/EB015PI.c3d", dir.file("walk.C3D"));
  fs::copy_file(data + "/std_walking5_markers.trc", dir.file("walk.TRC"));
  capz_test::put(dir.file("scan.PCD"), capz_test::binary_pcd(200, 1.0f));
  capz_test::put(dir.file("scan.PLY"),
                 "ply\nformat ascii 1.0\nelement vertex 3\nproperty float x\nproperty float y\n"
                 "property float z\nend_header\n1 2 3\n4 5 6\n7 8 9.5\n");
  std::string bin;
  for (int i = 0; i < 64; ++i) {
    const float p[4] = {0.5f * static_cast<float>(i), 2.0f, -1.0f, 0.25f};
    bin.append(reinterpret_cast<const char*>(p), sizeof p);
  }
  capz_test::put(dir.file("scan.BIN"), bin);
  for (const char* name : {"walk.C3D", "walk.TRC", "scan.PCD", "scan.PLY", "scan.BIN"}) {
    const std::string in = dir.file(name), original = capz_test::file_text(in);
    auto r = capz_run("compress -q --lossless '" + in + "'", dir);
    ASSERT_EQ(r.status, 0) << name << ": " << r.out;
    fs::remove(in);
    r = capz_run("decompress -q '" + in + ".capz'", dir);
    ASSERT_EQ(r.status, 0) << name << ": " << r.out;
    EXPECT_TRUE(fs::is_regular_file(in)) << name;
    EXPECT_TRUE(capz_test::file_text(in) == original) << name << " differs";
    for (const char* ext : {".c3d", ".trc", ".pcd", ".ply", ".bin"})
      EXPECT_FALSE(fs::exists(in + ext)) << name << ext;
  }
}
