// For fuzz targets whose API takes a path: one scratch file per process and target, under the
// system temp folder, rewritten for every input and removed at exit.
#pragma once

#include <unistd.h>

#include <cstdint>
#include <filesystem>
#include <fstream>
#include <string>

namespace capz_fuzz {

class TempFile {
 public:
  explicit TempFile(const std::string& tag)
      : path_((std::filesystem::temp_directory_path() /
               ("capz_fuzz_" + tag + "_" + std::to_string(::getpid()) + ".capz"))
                  .string()) {}
  ~TempFile() { remove(); }
  TempFile(const TempFile&) = delete;
  TempFile& operator=(const TempFile&) = delete;

  const std::string& path() const { return path_; }
  // Replaces the file's contents with `size` bytes.
  void write(const uint8_t* data, size_t size) const {
    std::ofstream f(path_, std::ios::binary | std::ios::trunc);
    f.write(reinterpret_cast<const char*>(data), static_cast<std::streamsize>(size));
  }
  void remove() const {
    std::error_code ec;
    std::filesystem::remove(path_, ec);
  }

 private:
  std::string path_;
};

}  // namespace capz_fuzz
