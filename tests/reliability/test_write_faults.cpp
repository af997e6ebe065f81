// Faults while writing: a write that fails part way (the disk fills up: simulated with
// RLIMIT_FSIZE, see fault_util.h) leaves no output and no temporary file behind, leaves an
// existing output it was told to replace untouched, and reports Error(kIo).
#include <gtest/gtest.h>

#include <filesystem>
#include <string>
#include <vector>

#include "capz/error.h"
#include "capz/io.h"
#include "fault_util.h"
#include "test_util.h"

namespace fs = std::filesystem;
using capz_test::list_dir;
using capz_test::run_with_file_limit;
using capz_test::slurp;

namespace {

constexpr int kIo = static_cast<int>(capz::ErrorCode::kIo);

// A real take (bundled: OpenSim's std_walking5_markers.trc, data/README.md) big enough that
// every writer's output exceeds the 4 KB limit used below.
const std::string kTrc = std::string(CAPZ_REPO_DATA) + "/std_walking5_markers.trc";

capz::Take sample_take() {
  return capz::read_trc(kTrc);
}

}  // namespace

TEST(WriteFaults, FileSizeLimitReallyFailsWrites) {
  // The simulation itself: without a limit the write succeeds, with one it fails with kIo.
  capz_test::TempDir dir("capz_faults");
  capz::Take t = sample_take();
  EXPECT_EQ(run_with_file_limit(size_t{1} << 30, [&] { capz::write_trc(t, dir.file("a.trc")); }),
            0);
  EXPECT_GT(fs::file_size(dir.file("a.trc")), 4096u);
  EXPECT_EQ(run_with_file_limit(4096, [&] { capz::write_trc(t, dir.file("b.trc")); }), kIo);
}

TEST(WriteFaults, EveryWriterLeavesNothingWhenTheDiskFills) {
  capz::Take t = sample_take();
  struct Case {
    const char* name;
    std::function<void(const std::string&, bool)> write;
    size_t limit;  // below the size of one output file (a PCD folder: of one frame file)
  };
  const std::vector<Case> cases = {
      {"out.trc",
       [&](const std::string& p, bool f) {
         capz::WriteOptions o;
         o.overwrite = f;
         capz::write_trc(t, p, o);
       },
       4096},
      {"out.c3d",
       [&](const std::string& p, bool f) {
         capz::WriteOptions o;
         o.overwrite = f;
         capz::write_c3d(t, p, o);
       },
       4096},
      {"out_pcd",
       [&](const std::string& p, bool f) {
         capz::WriteOptions o;
         o.overwrite = f;
         capz::write_pcd_folder(t, p, o);
       },
       300},
  };
  for (const auto& c : cases) {
    SCOPED_TRACE(c.name);
    // A new output: nothing at all may be left.
    {
      capz_test::TempDir dir("capz_faults");
      const std::string out = dir.file(c.name);
      EXPECT_EQ(run_with_file_limit(c.limit, [&] { c.write(out, false); }), kIo);
      EXPECT_TRUE(list_dir(dir.path().string()).empty())
          << "left behind: " << list_dir(dir.path().string()).front();
    }
    // Replacing an existing output (-f): the old one must survive a failed write unchanged.
    {
      capz_test::TempDir dir("capz_faults");
      const std::string out = dir.file(c.name);
      c.write(out, false);
      const bool is_dir = fs::is_directory(out);
      const std::string probe = is_dir ? (fs::path(out) / list_dir(out).front()).string() : out;
      const std::vector<char> before = slurp(probe);
      const size_t entries = is_dir ? list_dir(out).size() : 0;
      EXPECT_EQ(run_with_file_limit(c.limit, [&] { c.write(out, true); }), kIo);
      EXPECT_EQ(list_dir(dir.path().string()), std::vector<std::string>{c.name});
      EXPECT_EQ(slurp(probe), before);
      if (is_dir) {
        EXPECT_EQ(list_dir(out).size(), entries);
      }
    }
  }
}

// `capz compress` on a full disk: exit status 2 (kIo), no output or temporary file, the input
// unchanged, and --rm does not remove the input when the write failed. Without the fault, --rm
// removes it only after the output is in place.
TEST(WriteFaults, CompressOnAFullDiskKeepsTheInputAndLeavesNoOutput) {
  capz_test::TempDir dir("capz_faults");
  const std::string in = dir.file("walk.trc");
  fs::copy_file(kTrc, in);
  const std::vector<char> before = slurp(in);
  const std::string out = dir.file("walk.capz");
  for (bool rm : {false, true}) {
    std::vector<std::string> args = {"compress", in, "-o", out, "--lossless"};
    if (rm) args.push_back("--rm");
    EXPECT_EQ(capz_test::run_cli(args, 2048), kIo) << (rm ? "with --rm" : "");
    EXPECT_EQ(list_dir(dir.path().string()), std::vector<std::string>{"walk.trc"});
    EXPECT_EQ(slurp(in), before);
  }
  EXPECT_EQ(capz_test::run_cli({"compress", in, "-o", out, "--lossless", "--rm"}, 0), 0);
  EXPECT_EQ(list_dir(dir.path().string()), std::vector<std::string>{"walk.capz"});
  // And back: the decompressed file is the input, exactly (lossless TRC).
  EXPECT_EQ(capz_test::run_cli({"decompress", out, "-o", in}, 0), 0);
  capz_test::expect_same_samples(capz::read_trc(kTrc), capz::read_trc(in));
}
