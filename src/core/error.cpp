// Decoder library (capz_decode): builds without PCL and without the transform encoders.
#include "capz/error.h"

namespace capz {

const char* error_code_name(ErrorCode code) {
  switch (code) {
    case ErrorCode::kUsage:
      return "usage";
    case ErrorCode::kIo:
      return "io";
    case ErrorCode::kNotOurFormat:
      return "not-our-format";
    case ErrorCode::kUnsupportedVersion:
      return "unsupported-version";
    case ErrorCode::kCorrupt:
      return "corrupt";
    case ErrorCode::kInvalidParameter:
      return "invalid-parameter";
    case ErrorCode::kInternal:
      return "internal";
    case ErrorCode::kMemoryLimit:
      return "memory-limit";
  }
  return "unknown";
}

void fail(ErrorCode code, const std::string& file, const std::string& what) {
  std::string m = file.empty() ? what : file + ": " + what;
  // A NUL from a file's bytes (a PCD TYPE, a label) would end what() there: written as \0.
  for (size_t i = m.find('\0'); i != std::string::npos; i = m.find('\0', i + 2))
    m.replace(i, 1, "\\0");
  throw Error(code, m);
}

}  // namespace capz
