// An interrupted run leaves nothing behind (docs/CLI.md "Exit status"): capz stopped by SIGTERM,
// SIGINT (Ctrl-C), SIGHUP or SIGQUIT while it writes removes its temporaries ("OUT.tmp-XXXXXX"
// files and folders, the pipe folder under $TMPDIR) and ends by that signal. Each case starts the
// CLI on a take big enough to take a while, waits until a temporary appears, sends the signal, and
// checks how the process ended and what is left. A stdout whose reader has gone (`| head`) ends
// capz the same way, by SIGPIPE, quietly.
#include <fcntl.h>
#include <gtest/gtest.h>
#include <sys/resource.h>
#include <sys/wait.h>
#include <unistd.h>

#include <chrono>
#include <cmath>
#include <csignal>
#include <cstdio>
#include <filesystem>
#include <fstream>
#include <string>
#include <thread>
#include <vector>

#include "test_util.h"

extern char** environ;

namespace {

namespace fs = std::filesystem;
using capz_test::TempDir;
using Clock = std::chrono::steady_clock;

// A TRC of 8000 frames of 100 markers (20 MB): about a second to compress or decompress here,
// so a temporary stays long enough to be seen.
void write_big_trc(const std::string& path, int frames = 8000) {
  const int markers = 100;
  std::ofstream out(path);
  out << "PathFileType\t4\t(X/Y/Z)\tbig.trc\nDataRate\tCameraRate\tNumFrames\tNumMarkers\tUnits\t"
         "OrigDataRate\tOrigDataStartFrame\tOrigNumFrames\n100\t100\t"
      << frames << "\t" << markers << "\tmm\t100\t1\t" << frames << "\nFrame#\tTime";
  for (int m = 0; m < markers; ++m) out << "\tM" << m << "\t\t";
  out << "\n\t";
  for (int m = 1; m <= markers; ++m) out << "\tX" << m << "\tY" << m << "\tZ" << m;
  out << "\n\n";
  char buf[32];
  for (int f = 0; f < frames; ++f) {
    out << f + 1 << "\t" << f / 100.0;
    for (int c = 0; c < markers * 3; ++c) {  // smooth paths with a little noise of their own
      const double v = 1000.0 + 300.0 * c / markers + 50.0 * std::sin(f * 0.01 + c) +
                       static_cast<double>((f * 7919 + c * 104729) % 1000) / 997.0;
      std::snprintf(buf, sizeof buf, "\t%.3f", v);
      out << buf;
    }
    out << "\n";
  }
}

// Made once: the take, and its archive when a case asks (by the CLI, which must succeed).
class CliSignals : public ::testing::Test {
 protected:
  static void SetUpTestSuite() {
    data_ = new TempDir("capz_cli_signals_data");
    write_big_trc(data_->file("big.trc"));
  }
  static void TearDownTestSuite() {
    delete data_;
    data_ = nullptr;
  }
  static std::string data(const std::string& name) { return data_->file(name); }
  static std::string archive() {
    const std::string path = data_->file("big.capz");
    if (!fs::exists(path)) {
      const auto r = capz_test::run_command(
          CAPZ_CLI, "compress -q '" + data("big.trc") + "' -o '" + path + "'", data("out"));
      EXPECT_EQ(r.status, 0) << r.out;
    }
    return path;
  }
  static TempDir* data_;
};

TempDir* CliSignals::data_ = nullptr;

bool is_temporary(const fs::path& p) {
  const std::string name = p.filename().string();
  return name.find(".tmp-") != std::string::npos || name.find(".old-") != std::string::npos ||
         name.rfind("capz-pipe-", 0) == 0;
}

// Every temporary under `dir` (what capz makes while it writes), as paths relative to `dir`.
std::vector<std::string> temporaries(const fs::path& dir) {
  std::vector<std::string> found;
  std::error_code ec;
  for (fs::recursive_directory_iterator it(dir, ec), end; !ec && it != end; it.increment(ec))
    if (is_temporary(it->path())) found.push_back(fs::relative(it->path(), dir, ec).string());
  return found;
}

// Starts the CLI with `args`, stdin from `in` (or /dev/null), stdout and stderr to files in
// `dir` (stdout to `out_fd` when it is given), TMPDIR set to `dir`/tmp, and the signals tested at
// their default action (as a terminal gives them; a shell's background job would ignore SIGINT),
// without core files (SIGQUIT's default action dumps one).
pid_t start(const std::vector<std::string>& args, const TempDir& dir, const std::string& in,
            int out_fd = -1) {
  fs::create_directories(dir.path() / "tmp");
  std::vector<std::string> words = {CAPZ_CLI};
  words.insert(words.end(), args.begin(), args.end());
  std::vector<char*> argv;
  for (auto& w : words) argv.push_back(&w[0]);
  argv.push_back(nullptr);
  std::string tmpdir = "TMPDIR=" + dir.file("tmp");
  std::vector<char*> envp;
  for (char** e = environ; *e; ++e)
    if (std::string(*e).rfind("TMPDIR=", 0) != 0) envp.push_back(*e);
  envp.push_back(&tmpdir[0]);
  envp.push_back(nullptr);
  const std::string stdin_path = in.empty() ? "/dev/null" : in, out = dir.file("stdout"),
                    err = dir.file("stderr");
  const pid_t pid = fork();
  if (pid == 0) {  // only async-signal-safe calls until exec
    const int i = open(stdin_path.c_str(), O_RDONLY);
    const int o = out_fd >= 0 ? out_fd : open(out.c_str(), O_WRONLY | O_CREAT | O_TRUNC, 0644);
    const int e = open(err.c_str(), O_WRONLY | O_CREAT | O_TRUNC, 0644);
    if (i < 0 || o < 0 || e < 0) _exit(99);
    dup2(i, 0);
    dup2(o, 1);
    dup2(e, 2);
    for (int sig : {SIGINT, SIGTERM, SIGHUP, SIGQUIT, SIGPIPE}) signal(sig, SIG_DFL);
    const struct rlimit no_core = {0, 0};
    setrlimit(RLIMIT_CORE, &no_core);
    sigset_t none;
    sigemptyset(&none);
    sigprocmask(SIG_SETMASK, &none, nullptr);
    execve(argv[0], argv.data(), envp.data());
    _exit(98);
  }
  return pid;
}

// Waits for `pid` until `deadline`; true with its status once it ended.
bool wait_until(pid_t pid, Clock::time_point deadline, int* status) {
  for (;;) {
    const pid_t r = waitpid(pid, status, WNOHANG);
    if (r == pid) return true;
    if (Clock::now() > deadline) return false;
    std::this_thread::sleep_for(std::chrono::milliseconds(1));
  }
}

// Waits up to 120 s for `pid`: true with its status once it ended, else false, killed.
bool ended_within_120s(pid_t pid, int* status) {
  if (wait_until(pid, Clock::now() + std::chrono::seconds(120), status)) return true;
  kill(pid, SIGKILL);
  waitpid(pid, status, 0);
  return false;
}

// Expects no temporary left under `dir`.
void expect_no_temporaries(const TempDir& dir) {
  const std::vector<std::string> left = temporaries(dir.path());
  EXPECT_TRUE(left.empty()) << left.size() << " left, the first " << left.front();
}

// Expects capz's `status` to say it ended by `sig` (its stderr shown otherwise).
void expect_ended_by(int status, int sig, const TempDir& dir) {
  ASSERT_TRUE(WIFSIGNALED(status))
      << "status " << status << ": " << capz_test::file_text(dir.file("stderr"));
  EXPECT_EQ(WTERMSIG(status), sig);
}

// Runs capz with `args` in `dir`, sends `sig` once a temporary shows under `dir`, and checks that
// capz ended by that signal leaving no temporary. Skips (saying so) when capz ended before a
// temporary was seen, or wrote `output` before the signal came.
void interrupt(const std::vector<std::string>& args, const TempDir& dir, int sig,
               const std::string& output, const std::string& in = "") {
  const pid_t pid = start(args, dir, in);
  ASSERT_GT(pid, 0);
  int status = 0;
  bool seen = false, ended = false;
  const auto deadline = Clock::now() + std::chrono::seconds(120);
  while (!seen && !ended && Clock::now() < deadline) {
    seen = !temporaries(dir.path()).empty();
    if (!seen) ended = waitpid(pid, &status, WNOHANG) == pid;
    if (!seen && !ended) std::this_thread::sleep_for(std::chrono::milliseconds(1));
  }
  if (!seen && !ended) {
    kill(pid, SIGKILL);
    waitpid(pid, &status, 0);
    FAIL() << "capz made no temporary in 120 s: " << capz_test::file_text(dir.file("stderr"));
  }
  if (ended) {
    EXPECT_TRUE(temporaries(dir.path()).empty());
    GTEST_SKIP() << "capz ended (status " << status
                 << ") before a temporary was seen: " << capz_test::file_text(dir.file("stderr"));
  }
  ASSERT_EQ(kill(pid, sig), 0);
  if (!ended_within_120s(pid, &status)) FAIL() << "capz did not end within 120 s of signal " << sig;
  expect_no_temporaries(dir);
  if (WIFEXITED(status) && WEXITSTATUS(status) == 0)  // done and renamed before the signal came
    GTEST_SKIP() << "capz finished before signal " << sig << " came";
  expect_ended_by(status, sig, dir);
  if (fs::exists(output))  // whole: renamed into place before the signal came
    GTEST_SKIP() << output << " was written before signal " << sig << " came";
}

// Runs capz with `args` in `dir`, its stdout a pipe whose reader is gone before it starts, and
// checks that it ended by SIGPIPE, said nothing on stderr and left no temporary.
void broken_pipe(const std::vector<std::string>& args, const TempDir& dir) {
  int fds[2];
  ASSERT_EQ(pipe(fds), 0);
  close(fds[0]);  // nobody reads: the first write fails
  const pid_t pid = start(args, dir, "", fds[1]);
  close(fds[1]);
  ASSERT_GT(pid, 0);
  int status = 0;
  if (!ended_within_120s(pid, &status)) FAIL() << "capz did not end within 120 s";
  expect_ended_by(status, SIGPIPE, dir);
  EXPECT_EQ(capz_test::file_text(dir.file("stderr")), "");
  expect_no_temporaries(dir);
}

}  // namespace

TEST_F(CliSignals, GivenCompressStoppedBySigtermThenNoTemporaryIsLeft) {
  TempDir dir;
  interrupt({"compress", "-q", data("big.trc"), "-o", dir.file("big.capz")}, dir, SIGTERM,
            dir.file("big.capz"));
}

TEST_F(CliSignals, GivenDecompressToAFileStoppedBySigintThenNoTemporaryIsLeft) {
  TempDir dir;
  interrupt({"decompress", "-q", archive(), "-o", dir.file("back.trc")}, dir, SIGINT,
            dir.file("back.trc"));
}

TEST_F(CliSignals, GivenDecompressToAFolderStoppedBySighupThenNoTemporaryIsLeft) {
  TempDir dir;
  interrupt({"decompress", "-q", archive(), "-o", dir.file("frames/")}, dir, SIGHUP,
            dir.file("frames"));
}

TEST_F(CliSignals, GivenConvertStoppedBySigtermThenNoTemporaryIsLeft) {
  TempDir dir;
  interrupt({"convert", "-q", data("big.trc"), dir.file("big.c3d")}, dir, SIGTERM,
            dir.file("big.c3d"));
}

TEST_F(CliSignals, GivenARecursiveBatchStoppedBySigtermThenNoTemporaryIsLeft) {
  TempDir dir;
  fs::create_directories(dir.path() / "in" / "s1");
  fs::copy_file(data("big.trc"), dir.path() / "in" / "s1" / "big.trc");
  interrupt({"compress", "-q", "-r", dir.file("in"), "--output-dir-flat", dir.file("out"),
             "--report", dir.file("report.jsonl")},
            dir, SIGTERM, dir.file("out/big.trc.capz"));
  EXPECT_FALSE(fs::exists(dir.file("report.jsonl")));
}

// The folders --output-dir-mirror made for the output not written go too (only those: m/ was
// there before).
TEST_F(CliSignals, GivenAMirrorBatchStoppedBySigintThenTheFoldersItMadeAreRemoved) {
  TempDir dir;
  fs::create_directories(dir.path() / "in" / "s1");
  fs::create_directories(dir.path() / "m");
  fs::copy_file(data("big.trc"), dir.path() / "in" / "s1" / "big.trc");
  const std::string mirror = dir.file("m"), in = dir.file("in");
  interrupt({"compress", "-q", "-r", in, "--output-dir-mirror", mirror}, dir, SIGINT,
            mirror + in + "/s1/big.trc.capz");
  EXPECT_TRUE(fs::is_directory(mirror));
  EXPECT_TRUE(fs::is_empty(mirror)) << "left: " << fs::directory_iterator(mirror)->path();
}

// stdin is spooled to a folder under $TMPDIR, the archive written there and copied to stdout.
TEST_F(CliSignals, GivenAPipeStoppedBySigtermThenItsTemporaryFolderIsRemoved) {
  TempDir dir;
  interrupt({"compress", "-q"}, dir, SIGTERM, dir.file("tmp/none"), data("big.trc"));
}

TEST_F(CliSignals, GivenDecompressStoppedBySigquitThenNoTemporaryIsLeft) {
  TempDir dir;
  interrupt({"decompress", "-q", archive(), "-o", dir.file("back.c3d")}, dir, SIGQUIT,
            dir.file("back.c3d"));
}

// SIGPIPE sent from outside (kill -PIPE) while a file is written: removed, ended by it.
TEST_F(CliSignals, GivenCompressSentSigpipeThenNoTemporaryIsLeft) {
  TempDir dir;
  interrupt({"compress", "-q", data("big.trc"), "-o", dir.file("big.capz")}, dir, SIGPIPE,
            dir.file("big.capz"));
}

// `capz decompress -c a.capz | head -c 10`: the take is written to the pipe folder, then copied
// to stdout, whose first write fails. It was an error ("stdout: write failed: Broken pipe",
// exit 2); it is now what other tools do there, a quiet end by SIGPIPE, the folder removed.
TEST_F(CliSignals, GivenStdoutClosedByItsReaderThenDecompressEndsQuietlyBySigpipe) {
  TempDir dir;
  broken_pipe({"decompress", archive(), "-c"}, dir);
}

// `capz compress -r in --output-dir-flat out -T 2 | head -n 1`: the first file's line meets the
// closed pipe while the second file is being written. SIGPIPE's default action ended capz there
// and left that file's OUT.tmp-XXXXXX; it is now removed first.
TEST_F(CliSignals, GivenStdoutClosedByItsReaderThenABatchLeavesNoTemporary) {
  TempDir dir;
  fs::create_directories(dir.path() / "in");
  // A quarter of the take first: its line is printed early in the second file's writing.
  write_big_trc(dir.file("in/a.trc"), 2000);
  fs::copy_file(data("big.trc"), dir.path() / "in" / "b.trc");
  broken_pipe({"compress", "-r", dir.file("in"), "--output-dir-flat", dir.file("out"), "-T", "2"},
              dir);
}
