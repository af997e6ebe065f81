// Pipes for compress and decompress: stdin spooled to a private temporary folder (so the
// streaming readers, which read files by ranges, and the original's checksum and residue work
// as for a file; memory stays bounded as for a file), outputs written there and copied to
// stdout. The folder and everything in it is removed when the PipeSpace goes (or when SIGINT,
// SIGTERM, SIGHUP, SIGQUIT or SIGPIPE ends capz: capz::remove_temporaries_on_signals).
#pragma once

#include <cstdint>
#include <functional>
#include <string>

#include "batch.h"
#include "capz/tool/file.h"

namespace capz_cli {

class PipeSpace {
 public:
  PipeSpace();  // a fresh folder under $TMPDIR (or /tmp); Error(kIo) when it cannot be made
  PipeSpace(const PipeSpace&) = delete;
  PipeSpace& operator=(const PipeSpace&) = delete;

  std::string path(const std::string& name) const { return folder_.path() + "/" + name; }
  // Copies stdin to path(name) and returns that path. More than `max_bytes` (the limit
  // capz::read_file applies to a whole file) is Error(kIo); an empty stream is left to the
  // format check, which names it.
  std::string spool_stdin(const std::string& name, uint64_t max_bytes = uint64_t{1} << 34);
  // `message` with this folder's path taken out ("<dir>/stdin: x" -> "stdin: x").
  std::string tidy(const std::string& message) const;

 private:
  capz::TemporaryFolder folder_;  // removed with what it holds (signals too)
};

// Copies the file at `path` to stdout; Error(kIo) naming stdout when a write fails. A pipe
// closed by its reader (`| head`) ends capz by SIGPIPE, its temporaries removed first
// (capz::remove_temporaries_on_signals), or, with SIGPIPE ignored when capz started, is such an
// error.
void copy_to_stdout(const std::string& path);

// Runs `work` for a job, with a PipeSpace when the job reads stdin or writes stdout (else
// nullptr), and the space's folder taken out of the messages of the errors it throws.
FileRecord with_pipe_space(const Job& job, const std::function<FileRecord(PipeSpace*)>& work);

// Error(kUsage) when stdout is a terminal: binary output there would help nobody.
void refuse_terminal_stdout(const std::string& what);

}  // namespace capz_cli
