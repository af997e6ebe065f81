// Helpers shared by compress / decompress / verify: sizes, names, progress, .capz loading.
#pragma once

#include <unistd.h>

#include <chrono>
#include <cstdio>
#include <filesystem>
#include <string>
#include <vector>

#include "capz/error.h"
#include "core/atomic_file.h"
#include "commands.h"

namespace capz_cli {

namespace fs = std::filesystem;

// Bytes of a file, or of the regular files directly inside a folder.
inline uint64_t input_bytes(const std::string& path) {
  std::error_code ec;
  if (fs::is_directory(path, ec)) {
    uint64_t n = 0;
    for (const auto& e : fs::directory_iterator(path, ec))
      if (e.is_regular_file(ec)) n += e.file_size(ec);
    return n;
  }
  uint64_t n = fs::file_size(path, ec);
  return ec ? 0 : n;
}

// "a/b/frames/" -> "a/b/frames"
inline std::string strip_slashes(std::string p) {
  while (p.size() > 1 && p.back() == '/') p.pop_back();
  return p;
}

// A progress line on stderr, only at normal verbosity on a terminal, at most ~10 times a second.
class Progress {
 public:
  explicit Progress(const char* what)
      : what_(what), on_(g_verbosity >= 1 && isatty(STDERR_FILENO)),
        last_(std::chrono::steady_clock::now()) {}
  void operator()(size_t done, size_t total) {
    if (!on_ || total == 0) return;
    auto now = std::chrono::steady_clock::now();
    if (done < total && now - last_ < std::chrono::milliseconds(100)) return;
    last_ = now;
    std::fprintf(stderr, "\r%s: %3d%% (%zu / %zu frames)", what_, static_cast<int>(100.0 * done / total),
                 done, total);
    shown_ = true;
  }
  ~Progress() {
    if (shown_) std::fprintf(stderr, "\r\033[K");
  }

 private:
  const char* what_;
  bool on_;
  bool shown_ = false;
  std::chrono::steady_clock::time_point last_;
};

inline double seconds_since(std::chrono::steady_clock::time_point t0) {
  return std::chrono::duration<double>(std::chrono::steady_clock::now() - t0).count();
}

// Number formatting with a sensible number of significant digits.
inline std::string num(double v, int digits = 4) {
  char buf[64];
  std::snprintf(buf, sizeof buf, "%.*g", digits, v);
  return buf;
}

}  // namespace capz_cli
