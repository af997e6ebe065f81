// A file read by ranges (pread), for the streaming readers: only the bytes asked for are read.
#pragma once

#include <cstddef>
#include <cstdint>
#include <string>

namespace capz {

class InputFile {
 public:
  // Throws Error(kIo) if the file cannot be opened, kUsage if it is a directory.
  explicit InputFile(const std::string& path);
  ~InputFile();
  InputFile(const InputFile&) = delete;
  InputFile& operator=(const InputFile&) = delete;

  uint64_t size() const { return size_; }
  // Reads bytes [offset, offset + n) into out; throws Error(kIo) on a read error or when the
  // range passes the end of the file (the callers check ranges against size() first).
  void read_at(uint64_t offset, void* out, size_t n);
  uint64_t bytes_read() const { return bytes_read_; }  // total over every read_at
  const std::string& path() const { return path_; }

 private:
  std::string path_;
  int fd_ = -1;
  uint64_t size_ = 0;
  uint64_t bytes_read_ = 0;
};

}  // namespace capz
