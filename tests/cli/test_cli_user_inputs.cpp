// Frame files as other writers leave them (docs/lab/2026-11-30-user-inputs.md): headers PCL
// would not write, folders holding more than frames, coordinates far from the origin. Each
// through `capz compress` and `decompress` as a user runs them: the files come back (byte for
// byte with --lossless), or one line names the file and nothing is left behind.
#include <gtest/gtest.h>

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
