// Helpers shared by the test executables (header-only; tests/ is on their include path).
#pragma once

#include <gtest/gtest.h>
#include <sys/wait.h>
#include <unistd.h>

#include <algorithm>
#include <cstdlib>
#include <cstring>
#include <filesystem>
#include <fstream>
#include <sstream>
#include <string>
#include <system_error>
#include <vector>

#include "capz/error.h"
#include "capz/take.h"

namespace capz_test {

// A fresh directory under the system temp folder, removed with everything in it on destruction.
class TempDir {
 public:
  explicit TempDir(const std::string& tag = "capz_test") {
    static int counter = 0;
    path_ = std::filesystem::temp_directory_path() /
            (tag + "_" + std::to_string(::getpid()) + "_" + std::to_string(counter++));
    std::filesystem::create_directories(path_);
  }
  ~TempDir() {
    std::error_code ec;
    std::filesystem::remove_all(path_, ec);
  }
  TempDir(const TempDir&) = delete;
  TempDir& operator=(const TempDir&) = delete;
  const std::filesystem::path& path() const { return path_; }
  std::string file(const std::string& name) const { return (path_ / name).string(); }

 private:
  std::filesystem::path path_;
};

// The shared real data (compile definition CAPZ_SHARED_DATA; README, "Real data"): the path of
// `rel` under it (the folder itself for ""). When the folder is absent the running test is
// marked skipped with a message saying so and "" is returned; when the folder is there but `rel`
// is not, the data set is incomplete, which is a failure (never a silent skip), and "" is
// returned too. Callers return at once on "":
//   const std::string path = capz_test::shared_data_or_skip("trc/opensim/x.trc");
//   if (path.empty()) return;
inline std::string shared_data_or_skip(const std::string& rel = "") {
  const std::filesystem::path root = CAPZ_SHARED_DATA;
  const std::filesystem::path path = rel.empty() ? root : root / rel;
  std::error_code ec;
  if (!std::filesystem::is_directory(root, ec)) {
    [&] {
      GTEST_SKIP() << "shared real data not found at " << root.string()
                   << " (configure with -DCAPZ_SHARED_DATA=<folder holding c3d/, trc/, pcd/>)";
    }();
    return "";
  }
  if (!std::filesystem::exists(path, ec)) {
    ADD_FAILURE() << path.string() << " is missing from the shared real data";
    return "";
  }
  return path.string();
}

// Whether this build runs under a sanitizer (cmake CAPZ_SANITIZE). The tests that code whole
// real sequences then code their first frames only: the same code paths in a fraction of the
// time (scripts/test.sh runs them whole in the Release build first).
#if defined(CAPZ_TEST_SANITIZED) && CAPZ_TEST_SANITIZED
constexpr bool kSanitized = true;
#else
constexpr bool kSanitized = false;
#endif

// The PCD folder `dir` as a test reads it: the folder itself, or in a sanitized build (kSanitized)
// a folder in `tmp` holding copies of its first `n` frame files (by name).
inline std::string folder_for_build(const std::string& dir, const TempDir& tmp, size_t n) {
  if (!kSanitized) return dir;
  std::vector<std::filesystem::path> frames;
  for (const auto& e : std::filesystem::directory_iterator(dir))
    if (e.path().extension() == ".pcd") frames.push_back(e.path());
  std::sort(frames.begin(), frames.end());
  const std::filesystem::path out =
      tmp.path() / ("first_frames_" + std::filesystem::path(dir).filename().string());
  std::filesystem::create_directories(out);
  for (size_t f = 0; f < frames.size() && f < n; ++f)
    std::filesystem::copy_file(frames[f], out / frames[f].filename());
  return out.string();
}

// Same shape, same gaps, and bit-identical coordinates at every valid sample.
inline void expect_same_samples(const capz::Take& a, const capz::Take& b) {
  ASSERT_EQ(a.frames, b.frames);
  ASSERT_EQ(a.points, b.points);
  ASSERT_EQ(a.valid, b.valid);
  size_t differ = 0, first = 0;
  for (size_t i = 0; i < a.valid.size(); ++i) {
    if (!a.valid[i]) continue;
    for (int k = 0; k < 3; ++k) {
      if (a.xyz[i * 3 + k] != b.xyz[i * 3 + k] && differ++ == 0) first = i;
    }
  }
  EXPECT_EQ(differ, 0u) << "first differing sample: frame " << first / (a.points ? a.points : 1)
                        << ", point " << first % (a.points ? a.points : 1);
}

// Every per-frame array of the two takes, bit for bit (x y z and analog samples by their bits,
// NaN payloads too), with the frame offsets, labels and warnings.
inline void expect_same_take(const capz::Take& a, const capz::Take& b) {
  ASSERT_EQ(a.frames, b.frames);
  ASSERT_EQ(a.points, b.points);
  EXPECT_EQ(a.frame_offsets, b.frame_offsets);
  EXPECT_EQ(a.valid, b.valid);
  ASSERT_EQ(a.xyz.size(), b.xyz.size());
  if (!a.xyz.empty()) {
    EXPECT_EQ(std::memcmp(a.xyz.data(), b.xyz.data(), a.xyz.size() * sizeof(double)), 0);
  }
  ASSERT_EQ(a.analog.values.size(), b.analog.values.size());
  if (!a.analog.values.empty()) {
    EXPECT_EQ(std::memcmp(a.analog.values.data(), b.analog.values.data(),
                          a.analog.values.size() * sizeof(double)),
              0);
  }
  EXPECT_EQ(a.rotations.matrices, b.rotations.matrices);
  EXPECT_EQ(a.rotations.reliability, b.rotations.reliability);
  ASSERT_EQ(a.attributes.size(), b.attributes.size());
  for (size_t i = 0; i < a.attributes.size(); ++i)
    EXPECT_TRUE(a.attributes[i].data == b.attributes[i].data) << a.attributes[i].name;
  ASSERT_EQ(a.c3d != nullptr, b.c3d != nullptr);
  if (a.c3d) {
    EXPECT_EQ(a.c3d->residual, b.c3d->residual);
    EXPECT_EQ(a.c3d->camera_mask, b.c3d->camera_mask);
  }
  EXPECT_EQ(a.labels, b.labels);
  EXPECT_EQ(a.warnings, b.warnings);
}

// Shapes *t for frames of these point counts: a fixed take when they are all the same, else a
// ragged one (all gaps, zero positions).
inline void resize_frames(capz::Take* t, const std::vector<size_t>& counts) {
  bool same = true;
  for (size_t c : counts) same = same && c == counts[0];
  if (same && !counts.empty())
    t->resize(counts.size(), counts[0]);
  else
    t->resize_ragged(counts);
}

// A PCD field (an ATTR attribute's spec): name, type F/U/I, size, count.
inline capz::PCDField field_spec(const std::string& name, char type, int size, int count = 1) {
  capz::PCDField s;
  s.name = name;
  s.type = type;
  s.size = size;
  s.count = count;
  return s;
}

// Runs `f` and returns the code of the capz::Error it throws (its message in *msg); a call that
// does not throw returns kInternal, which no test expects from a correct reader.
template <typename F>
capz::ErrorCode error_of(F&& f, std::string* msg = nullptr) {
  try {
    f();
  } catch (const capz::Error& e) {
    if (msg) *msg = e.what();
    return e.code();
  }
  return capz::ErrorCode::kInternal;
}

// A whole file's bytes as a string ("" when it cannot be read).
inline std::string file_text(const std::string& path) {
  std::ifstream in(path, std::ios::binary);
  std::stringstream ss;
  ss << in.rdbuf();
  return ss.str();
}

// A command line run through the shell: its exit status (-1 when it did not exit) and what it
// printed on stdout and stderr together (collected in `out_file`).
struct CliResult {
  int status = -1;
  std::string out;
};
inline CliResult run_command(const std::string& exe, const std::string& args,
                             const std::string& out_file) {
  const std::string cmd = "'" + exe + "' " + args + " >'" + out_file + "' 2>&1";
  const int rc = std::system(cmd.c_str());
  return {WIFEXITED(rc) ? WEXITSTATUS(rc) : -1, file_text(out_file)};
}

// `text` without its lines that carry a reader's warning ("capz compress: warning: ..."), which
// a command prints beside its other lines (in a batch, as its file is read).
inline std::string without_warnings(const std::string& text) {
  std::stringstream in(text);
  std::string line, kept;
  while (std::getline(in, line))
    if (line.find(": warning: ") == std::string::npos) kept += line + "\n";
  return kept;
}

}  // namespace capz_test
