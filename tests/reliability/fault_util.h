// Running code or the capz CLI in a child process under a file-size limit, to simulate a disk
// that fills up mid-write: with RLIMIT_FSIZE set and SIGXFSZ ignored, a write past the limit
// fails with EFBIG exactly as a full disk fails with ENOSPC (a short or failed write(2)).
// No root, no mount, and it works the same under the sanitizers.
#pragma once

#include <signal.h>
#include <sys/resource.h>
#include <sys/wait.h>
#include <unistd.h>

#include <algorithm>
#include <cstdio>
#include <cstdlib>
#include <filesystem>
#include <fstream>
#include <functional>
#include <iterator>
#include <string>
#include <vector>

#include "capz/error.h"

namespace capz_test {

// Exit status of a child: its exit code, or 128 + signal number.
inline int wait_status(pid_t pid) {
  int st = 0;
  while (waitpid(pid, &st, 0) < 0) {
  }
  if (WIFEXITED(st)) return WEXITSTATUS(st);
  if (WIFSIGNALED(st)) return 128 + WTERMSIG(st);
  return -1;
}

inline void limit_file_size(size_t max_bytes) {
  signal(SIGXFSZ, SIG_IGN);
  struct rlimit rl;
  rl.rlim_cur = rl.rlim_max = static_cast<rlim_t>(max_bytes);
  setrlimit(RLIMIT_FSIZE, &rl);
}

// Runs fn in a child whose files cannot grow past max_bytes. Returns 0 if fn returned, the
// capz::ErrorCode number if it threw capz::Error, 100 for any other exception.
inline int run_with_file_limit(size_t max_bytes, const std::function<void()>& fn) {
  std::fflush(nullptr);
  pid_t pid = fork();
  if (pid == 0) {
    limit_file_size(max_bytes);
    int code = 0;
    try {
      fn();
    } catch (const capz::Error& e) {
      code = static_cast<int>(e.code());
    } catch (...) {
      code = 100;
    }
    _exit(code);  // no atexit handlers, no gtest teardown in the child
  }
  return wait_status(pid);
}

// Runs `capz args...` with its files limited to max_bytes (0 = no limit); stderr to err_file.
inline int run_cli(const std::vector<std::string>& args, size_t max_bytes,
                   const std::string& err_file = "/dev/null") {
  std::fflush(nullptr);
  pid_t pid = fork();
  if (pid == 0) {
    if (max_bytes) limit_file_size(max_bytes);
    if (FILE* f = std::freopen(err_file.c_str(), "w", stderr)) (void)f;
    if (FILE* f = std::freopen("/dev/null", "w", stdout)) (void)f;
    std::vector<char*> argv;
    std::string cli = CAPZ_CLI;
    argv.push_back(&cli[0]);
    std::vector<std::string> copy = args;
    for (auto& a : copy) argv.push_back(&a[0]);
    argv.push_back(nullptr);
    execv(cli.c_str(), argv.data());
    _exit(127);
  }
  return wait_status(pid);
}

inline std::vector<char> slurp(const std::string& path) {
  std::ifstream in(path, std::ios::binary);
  return std::vector<char>(std::istreambuf_iterator<char>(in), std::istreambuf_iterator<char>());
}

// Every entry of `dir` (names only), to see what a failed write left behind.
inline std::vector<std::string> list_dir(const std::string& dir) {
  std::vector<std::string> v;
  for (const auto& e : std::filesystem::directory_iterator(dir))
    v.push_back(e.path().filename().string());
  std::sort(v.begin(), v.end());
  return v;
}

}  // namespace capz_test
