// capz — the one error type thrown by library code.
#pragma once

#include <stdexcept>
#include <string>

namespace capz {

// What kind of fault; the CLI maps each code to its exit status (see docs/CLI.md).
enum class ErrorCode {
  kUsage = 1,               // the caller asked for something impossible (bad option, bad path)
  kIo = 2,                  // open/read/write/rename failed, disk full
  kNotOurFormat = 3,        // wrong magic, not a C3D/TRC/PCD/.capz file at all
  kUnsupportedVersion = 4,  // a .capz from a newer major version, an unknown C3D variant
  kCorrupt = 5,             // the file is ours but inconsistent: truncated, bad CRC, lying counts
  kInvalidParameter = 6,    // an option value out of range (negative error bound, K = 0, ...)
  kInternal = 7,            // a bug in capz: an invariant did not hold
  kMemoryLimit = 8,         // decoding needs more memory than the caller's limit allows
};

const char* error_code_name(ErrorCode code);

// The message as what() can carry it: a NUL (from a file's bytes: a PCD TYPE, a label), which
// would end the C string there, written as \0.
std::string error_message(const std::string& message);

// Message convention: "<file>: <what is wrong>", e.g.
//   "walk.c3d: parameter section ends at byte 4096 but POINT:USED needs 5120".
class Error : public std::runtime_error {
 public:
  Error(ErrorCode code, const std::string& message)
      : std::runtime_error(error_message(message)), code_(code) {}
  ErrorCode code() const { return code_; }

 private:
  ErrorCode code_;
};

// Throws Error(code, file + ": " + what). `file` may be empty (then only `what`).
[[noreturn]] void fail(ErrorCode code, const std::string& file, const std::string& what);

}  // namespace capz
