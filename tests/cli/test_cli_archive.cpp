// capz test and capz list (docs/CLI.md): one line per file, exit status 0 / 1, and decompress
// giving a --lossless C3D back byte for byte (--rm deleting only then).
#include <gtest/gtest.h>
#include <sys/wait.h>

#include <algorithm>
#include <cstdlib>
#include <filesystem>
#include <fstream>
#include <sstream>
#include <string>
#include <vector>

#include "capz/file.h"
#include "test_util.h"

namespace fs = std::filesystem;

namespace {

using Result = capz_test::CliResult;

Result run(const std::string& args) {
  static capz_test::TempDir io("capz_cli_archive_io");
  return capz_test::run_command(CAPZ_CLI, args, io.file("out"));
}

size_t lines(const std::string& s) {
  return static_cast<size_t>(std::count(s.begin(), s.end(), '\n'));
}

}  // namespace

TEST(CliArchive, LosslessRoundTripTestAndList) {
  capz_test::TempDir d("capz_cli_archive");
  const std::string src = std::string(CAPZ_REPO_DATA) + "/admarche2.c3d";
  const std::string in = d.file("a.c3d"), z = d.file("a.c3d.capz"), zb = d.file("b.capz");
  fs::copy_file(src, in);
  ASSERT_EQ(run("compress --lossless --rm -q '" + in + "' -o '" + z + "'").status, 0);
  EXPECT_FALSE(fs::exists(in));  // --rm: the archive rebuilt IN's bytes, hash checked
  ASSERT_EQ(run("compress -q '" + src + "' -o '" + zb + "'").status, 0);
  ASSERT_EQ(run("decompress -q '" + z + "'").status, 0);  // default OUT: a.c3d
  EXPECT_EQ(capz::read_file(in), capz::read_file(src));

  Result t = run("test '" + z + "' '" + zb + "'");
  EXPECT_EQ(t.status, 0) << t.out;
  EXPECT_EQ(lines(t.out), 2u) << t.out;
  EXPECT_NE(t.out.find(z + ": OK, 159 frames decoded, original rebuilt ("), std::string::npos)
      << t.out;
  // At a bound the archive rebuilds the C3D around regenerated frames: test checks its size.
  EXPECT_NE(t.out.find(zb +
                       ": OK, 159 frames decoded, not lossless: original rebuilt at the "
                       "bound (" +
                       std::to_string(fs::file_size(src)) + " bytes, size checked)"),
            std::string::npos)
      << t.out;

  Result l = run("list '" + z + "' '" + zb + "'");
  EXPECT_EQ(l.status, 0) << l.out;
  EXPECT_EQ(lines(l.out), 2u) << l.out;
  EXPECT_NE(l.out.find("admarche2.c3d (c3d) frames 159 points 17 analog 8"), std::string::npos)
      << l.out;
  EXPECT_NE(l.out.find("lossless ratio 0."), std::string::npos) << l.out;
  EXPECT_NE(l.out.find("max-error 0.1"), std::string::npos) << l.out;
}

TEST(CliArchive, TestAndListFailOnADamagedFile) {
  capz_test::TempDir d("capz_cli_archive_bad");
  const std::string src = std::string(CAPZ_REPO_DATA) + "/admarche2.c3d";
  const std::string z = d.file("a.capz"), bad = d.file("bad.capz");
  ASSERT_EQ(run("compress --lossless -q '" + src + "' -o '" + z + "'").status, 0);
  std::vector<uint8_t> b = capz::read_file(z);
  b[b.size() / 2] ^= 0x40;
  capz::write_file(bad, b, true);
  Result t = run("test '" + z + "' '" + bad + "'");
  EXPECT_EQ(t.status, 1) << t.out;
  EXPECT_EQ(lines(t.out), 2u) << t.out;
  EXPECT_NE(t.out.find(bad + ": FAILED"), std::string::npos) << t.out;
  Result l = run("list '" + d.file("missing.capz") + "'");
  EXPECT_EQ(l.status, 1) << l.out;
  EXPECT_EQ(lines(l.out), 1u) << l.out;
}
