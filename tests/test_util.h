// Helpers shared by the test executables (header-only; tests/ is on their include path).
#pragma once

#include <gtest/gtest.h>
#include <unistd.h>

#include <filesystem>
#include <string>

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

}  // namespace capz_test
