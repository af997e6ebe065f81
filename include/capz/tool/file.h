// NOT PART OF THE STABLE API (include/capz/tool/): what the capz CLI and the Python module share
// so that they behave alike. Installed for programs that want the CLI's exact behaviour, but it
// may change in any release; the stable API is the headers of include/capz/ itself.
// capz — whole files: what a program using the library needs around compress() / decompress().
// Outputs appear whole or not at all, as every writer of the library's (io.h) does.
#pragma once

#include <cstddef>
#include <cstdint>
#include <string>
#include <vector>

namespace capz {

// Whole-file read with a clear error (Error kIo naming the file); refuses files larger than
// `max_bytes` (kIo).
std::vector<uint8_t> read_file(const std::string& path, uint64_t max_bytes = (uint64_t{1} << 34));

// `path` without its trailing slashes ("a/b/" -> "a/b"; "/" stays "/"): a folder's path for the
// file system, once a trailing '/' has said "a folder".
std::string without_trailing_slashes(std::string path);

// Throws Error(kUsage) if `path` exists and !overwrite, unless `takes_files` (when given) says the
// existing `path` takes a folder output's files beside its own (io.h's frames_go_beside). It is
// asked only then: listing a folder is what costs.
void check_output_free(const std::string& path, bool overwrite,
                       bool (*takes_files)(const std::string& path) = nullptr);

// Writes `bytes` to `path` atomically: a temporary sibling, fsync'ed, then renamed over `path`
// (the destination is untouched on failure). Throws kUsage if `path` exists and !overwrite,
// kIo when the write fails (disk full).
void write_file(const std::string& path, const std::vector<uint8_t>& bytes, bool overwrite);

// Makes SIGINT (Ctrl-C), SIGTERM, SIGHUP, SIGQUIT and SIGPIPE (a write to a pipe whose reader
// has gone: `capz decompress -c a.capz | head -c 10`) remove the temporaries of the outputs not yet
// in place (the library's "<path>.tmp-XXXXXX" files and folders, TemporaryFolder's folders) before
// the process ends by that signal, as it would without this call (a shell sees status 128 + N): an
// interrupted run leaves no partial output. A signal ignored, blocked or handled at the call
// (SIGHUP under nohup) is left as it is. Call it once, first in main(), before any thread starts:
// it blocks the first four in the calling thread, so in every thread started after it, and starts
// a thread that waits for them; SIGPIPE, raised in the thread whose write failed, is handled there
// by passing it to that thread (the writing thread then waits for the end). Later calls do
// nothing.
void remove_temporaries_on_signals();

// Makes the folder `path` and the folders above it that do not exist yet (as
// std::filesystem::create_directories; Error kIo naming the folder that cannot be made), and
// records those it made: remove_empty_output_folders() removes those that hold nothing then, and
// so does a signal that remove_temporaries_on_signals() handles, after the temporaries. A batch's
// output folders (--output-dir-mirror, --output-dir-flat): a failed or interrupted run leaves no
// empty folder it made, and never removes one it did not make.
void create_output_folders(const std::string& path);
// Removes the folders create_output_folders() made that are empty now, deepest first (rmdir: a
// folder holding anything stays), and forgets every folder it made.
void remove_empty_output_folders();

// A fresh private folder made from `templ` (a path ending in XXXXXX, as mkdtemp(3) takes; Error
// kIo when it cannot be made), removed with what it holds when the object goes, or by a signal
// as remove_temporaries_on_signals() says.
class TemporaryFolder {
 public:
  explicit TemporaryFolder(const std::string& templ);
  ~TemporaryFolder();
  TemporaryFolder(const TemporaryFolder&) = delete;
  TemporaryFolder& operator=(const TemporaryFolder&) = delete;
  const std::string& path() const { return path_; }

 private:
  std::string path_;
};

}  // namespace capz
