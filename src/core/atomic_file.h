// Output that appears whole or not at all: data goes to a temporary sibling ("<path>.tmp-XXXXXX"),
// is fsync'ed, then renamed over `path`. If commit() is never reached (exception, crash), the
// destructor removes the temporary; the destination is untouched.
#pragma once

#include <cstdint>
#include <string>
#include <vector>

namespace capz {

// Throws Error(kUsage) if `path` exists and !overwrite.
void check_output_free(const std::string& path, bool overwrite);

class AtomicFile {
 public:
  AtomicFile(const std::string& path, bool overwrite);
  ~AtomicFile();
  AtomicFile(const AtomicFile&) = delete;
  AtomicFile& operator=(const AtomicFile&) = delete;

  void write(const void* data, size_t size);  // throws Error(kIo) on a short write (disk full)
  void write(const std::vector<uint8_t>& v) { write(v.data(), v.size()); }
  void commit();  // flush, fsync, close, rename into place
  const std::string& temp_path() const { return tmp_; }

 private:
  std::string path_, tmp_;
  int fd_ = -1;
  bool overwrite_;
  bool committed_ = false;
};

// The same for a directory (a PCD folder): files are written inside temp_dir(), and commit()
// renames the directory into place (an existing destination is removed first when overwrite).
class AtomicDir {
 public:
  AtomicDir(const std::string& path, bool overwrite);
  ~AtomicDir();
  AtomicDir(const AtomicDir&) = delete;
  AtomicDir& operator=(const AtomicDir&) = delete;
  const std::string& temp_dir() const { return tmp_; }
  void commit();

 private:
  std::string path_, tmp_;
  bool overwrite_;
  bool committed_ = false;
};

// Whole-file read with a clear error; refuses files larger than `max_bytes`.
std::vector<uint8_t> read_file(const std::string& path, uint64_t max_bytes = (uint64_t{1} << 34));

}  // namespace capz
