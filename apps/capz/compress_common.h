// Helpers shared by compress / decompress / verify: sizes, names, progress, .capz loading.
#pragma once

#include <unistd.h>

#include <chrono>
#include <cstdio>
#include <ctime>
#include <filesystem>
#include <string>
#include <vector>

#include "capz/codec.h"
#include "capz/error.h"
#include "capz/metrics.h"
#include "capz/tool/file.h"
#include "cli_util.h"
#include "commands.h"

namespace capz_cli {

namespace fs = std::filesystem;

// A progress line on stderr, only at normal verbosity on a terminal, at most ~10 times a second.
class Progress {
 public:
  explicit Progress(const char* what)
      : what_(what),
        on_(g_verbosity >= 1 && isatty(STDERR_FILENO)),
        last_(std::chrono::steady_clock::now()) {}
  void operator()(size_t done, size_t total) {
    if (!on_ || total == 0) return;
    auto now = std::chrono::steady_clock::now();
    if (done < total && now - last_ < std::chrono::milliseconds(100)) return;
    last_ = now;
    std::fprintf(stderr, "\r%s: %3d%% (%zu / %zu frames)", what_,
                 static_cast<int>(100.0 * static_cast<double>(done) / static_cast<double>(total)),
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

// `compress --rm` (check_written.cpp): reads OUT back from disk and decodes it, a window at a
// time, against IN read again from disk (in_header: the metadata compress coded; a .bin IN in its
// declared record, read_options_of), as
// OUT's header promises (capz/verify.h). On any difference or decoding error, removes OUT and
// throws Error(kCorrupt) saying IN was kept. The rule is the library's (capz/verify.h).
void check_written(const std::string& out, const std::string& in, const capz::Take& in_header);

// Called by check_written just before OUT is read back. The release binary's does nothing
// (release_hooks.cpp); the CLI built for the tests (tests/support/flip_written_byte.cpp) damages
// OUT there, as a disk returning bad data would, so a test can see --rm keep its input.
void before_reading_back(const std::string& out);

// `capz info` on a .capz (cmd_info_capz.cpp).
int info_capz(const std::string& path, bool json);
// capz info FILE --parameters (cmd_info_params.cpp): the C3D parameter section and header events
// of a .c3d, or of the C3D an archive holds (archive: FILE is a .capz).
int info_parameters(const std::string& path, bool json, bool archive);

// The error measures as JSON members.
inline void json_error_stats(Json* j, const capz::ErrorStats& e) {
  j->member("max_error_per_coordinate", e.max_abs);
  j->member("max_error_euclidean", e.max_error);
  j->member("rmse", e.rmse);
  j->member("kg_error_percent", e.kg_error);
  j->member("psnr_db", e.psnr);
  j->member("samples", static_cast<uint64_t>(e.samples));
  j->member("mask_mismatches", static_cast<uint64_t>(e.mask_mismatches));
}

// CPU time of this thread, seconds (speed figures stay meaningful on a loaded machine); with
// `whole_process`, of every thread of the process: for a file coded alone with window threads
// (-T above 1), whose workers' time the calling thread's clock would not count. A batch coding
// several files at once gives each file one thread, so there the thread's clock is the file's.
inline double cpu_seconds(bool whole_process = false) {
  timespec ts;
  clock_gettime(whole_process ? CLOCK_PROCESS_CPUTIME_ID : CLOCK_THREAD_CPUTIME_ID, &ts);
  return static_cast<double>(ts.tv_sec) + 1e-9 * static_cast<double>(ts.tv_nsec);
}

}  // namespace capz_cli
