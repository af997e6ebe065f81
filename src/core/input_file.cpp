// Decoder library (capz_decode): builds without PCL and without the transform encoders.
#include "core/input_file.h"

#include <fcntl.h>
#include <sys/stat.h>
#include <unistd.h>

#include <cerrno>
#include <cstring>

#include "capz/error.h"

namespace capz {

InputFile::InputFile(const std::string& path) : path_(path) {
  fd_ = ::open(path.c_str(), O_RDONLY | O_CLOEXEC);
  if (fd_ < 0) fail(ErrorCode::kIo, path, std::string("cannot open: ") + std::strerror(errno));
  struct stat st;
  if (::fstat(fd_, &st) != 0) {
    const int e = errno;
    ::close(fd_);
    fail(ErrorCode::kIo, path, std::string("cannot stat: ") + std::strerror(e));
  }
  if (S_ISDIR(st.st_mode)) {
    ::close(fd_);
    fail(ErrorCode::kUsage, path, "is a directory, expected a file");
  }
  size_ = static_cast<uint64_t>(st.st_size);
}

InputFile::~InputFile() {
  if (fd_ >= 0) ::close(fd_);
}

void InputFile::read_at(uint64_t offset, void* out, size_t n) {
  if (offset > size_ || n > size_ - offset)
    fail(ErrorCode::kIo, path_,
         "read of " + std::to_string(n) + " bytes at " + std::to_string(offset) +
             " passes the end of the file (" + std::to_string(size_) + " bytes)");
  auto* p = static_cast<uint8_t*>(out);
  while (n > 0) {
    const ssize_t r = ::pread(fd_, p, n, static_cast<off_t>(offset));
    if (r < 0 && errno == EINTR) continue;
    if (r <= 0)
      fail(ErrorCode::kIo, path_,
           r == 0 ? std::string("file shrank while reading")
                  : std::string("read failed: ") + std::strerror(errno));
    p += r;
    n -= static_cast<size_t>(r);
    offset += static_cast<uint64_t>(r);
    bytes_read_ += static_cast<uint64_t>(r);
  }
}

}  // namespace capz
