// Output that appears whole or not at all: data goes to a temporary sibling ("<path>.tmp-XXXXXX"),
// is fsync'ed, then renamed over `path`. If commit() is never reached (exception), the destructor
// removes the temporary; the destination is untouched. Temporaries are registered
// (core/temporaries.h), so a program that calls remove_temporaries_on_signals() loses them to
// SIGINT, SIGTERM and SIGHUP too.
#pragma once

#include <cstdint>
#include <string>
#include <vector>

#include "capz/tool/file.h"  // check_output_free, read_file, write_file

namespace capz {

class AtomicFile {
 public:
  AtomicFile(const std::string& path, bool overwrite);
  ~AtomicFile();
  AtomicFile(const AtomicFile&) = delete;
  AtomicFile& operator=(const AtomicFile&) = delete;

  void write(const void* data, size_t size);  // throws Error(kIo) on a short write (disk full)
  void write(const std::vector<uint8_t>& v) { write(v.data(), v.size()); }
  // Writes at file offset `offset` without moving where write() appends (a file laid out ahead,
  // e.g. a C3D's rotation section after frames not written yet; a gap left reads as zeros).
  void write_at(uint64_t offset, const void* data, size_t size);
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
// `beside`, when given, says whether an existing `path` takes the files in beside what it holds
// (io's frames_go_beside: a folder of an archive tree); commit() then moves them in one by one,
// under names it does not hold yet (Error kUsage naming one otherwise, nothing moved), and
// takes them all back if one fails: they appear together as far as any error or signal can
// tell, though a SIGKILL or power cut while they move may leave some.
class AtomicDir {
 public:
  AtomicDir(const std::string& path, bool overwrite,
            bool (*beside)(const std::string& path) = nullptr);
  ~AtomicDir();
  AtomicDir(const AtomicDir&) = delete;
  AtomicDir& operator=(const AtomicDir&) = delete;
  const std::string& temp_dir() const { return tmp_; }
  void commit();

 private:
  void move_in();  // commit() into an existing folder that takes the files beside its own

  std::string path_, tmp_;
  bool overwrite_;
  bool (*beside_)(const std::string&);
  bool committed_ = false;
};

}  // namespace capz
