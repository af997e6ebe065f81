#include "pipe.h"

#include <unistd.h>

#include <cerrno>
#include <cstdio>
#include <cstdlib>
#include <cstring>
#include <fstream>
#include <memory>
#include <vector>

#include "capz/error.h"

namespace capz_cli {

namespace {

std::string sys_error() {
  return std::strerror(errno);
}

// Writes all of [data, data + n) to `fd`, retrying short writes.
void write_all(int fd, const char* data, size_t n, const std::string& name) {
  while (n > 0) {
    const ssize_t w = ::write(fd, data, n);
    if (w < 0 && errno == EINTR) continue;
    if (w <= 0) capz::fail(capz::ErrorCode::kIo, name, "write failed: " + sys_error());
    data += w;
    n -= static_cast<size_t>(w);
  }
}

}  // namespace

namespace {

// The pipe folder's mkdtemp template: under $TMPDIR, else /tmp.
std::string pipe_template() {
  const char* t = std::getenv("TMPDIR");
  return std::string(t && *t ? t : "/tmp") + "/capz-pipe-XXXXXX";
}

}  // namespace

PipeSpace::PipeSpace() : folder_(pipe_template()) {}

std::string PipeSpace::spool_stdin(const std::string& name, uint64_t max_bytes) {
  const std::string p = path(name);
  std::FILE* f = std::fopen(p.c_str(), "wb");
  if (!f) capz::fail(capz::ErrorCode::kIo, p, "cannot create: " + sys_error());
  std::vector<char> buf(1 << 16);
  uint64_t total = 0;
  for (;;) {
    const ssize_t r = ::read(STDIN_FILENO, buf.data(), buf.size());
    if (r < 0 && errno == EINTR) continue;
    if (r < 0) {
      std::fclose(f);
      capz::fail(capz::ErrorCode::kIo, "stdin", "read failed: " + sys_error());
    }
    if (r == 0) break;
    total += static_cast<uint64_t>(r);
    if (total > max_bytes) {
      std::fclose(f);
      capz::fail(capz::ErrorCode::kIo, "stdin",
                 "more than " + std::to_string(max_bytes) + " bytes, larger than capz reads");
    }
    if (std::fwrite(buf.data(), 1, static_cast<size_t>(r), f) != static_cast<size_t>(r)) {
      std::fclose(f);
      capz::fail(capz::ErrorCode::kIo, p, "write failed (disk full?): " + sys_error());
    }
  }
  if (std::fclose(f) != 0) capz::fail(capz::ErrorCode::kIo, p, "write failed: " + sys_error());
  return p;
}

std::string PipeSpace::tidy(const std::string& message) const {
  std::string m = message;
  const std::string prefix = folder_.path() + "/";
  for (size_t at; (at = m.find(prefix)) != std::string::npos;) m.erase(at, prefix.size());
  return m;
}

void copy_to_stdout(const std::string& path) {
  std::FILE* f = std::fopen(path.c_str(), "rb");
  if (!f) capz::fail(capz::ErrorCode::kIo, path, "cannot open: " + sys_error());
  std::fflush(stdout);
  std::vector<char> buf(1 << 16);
  try {
    for (size_t n; (n = std::fread(buf.data(), 1, buf.size(), f)) > 0;)
      write_all(STDOUT_FILENO, buf.data(), n, "stdout");
    if (std::ferror(f)) capz::fail(capz::ErrorCode::kIo, path, "read failed: " + sys_error());
  } catch (...) {
    std::fclose(f);
    throw;
  }
  std::fclose(f);
}

FileRecord with_pipe_space(const Job& job, const std::function<FileRecord(PipeSpace*)>& work) {
  std::unique_ptr<PipeSpace> space;
  if (job.from_stdin || job.to_stdout) space = std::make_unique<PipeSpace>();
  try {
    return work(space.get());
  } catch (const capz::Error& e) {
    if (space) throw capz::Error(e.code(), space->tidy(e.what()));
    throw;
  }
}

void refuse_terminal_stdout(const std::string& what) {
  if (isatty(STDOUT_FILENO))
    capz::fail(capz::ErrorCode::kUsage, "",
               "stdout is a terminal: not writing " + what + " there (redirect it or use -o)");
}

}  // namespace capz_cli
