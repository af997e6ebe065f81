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

std::string error_message(const std::string& message) {
  std::string m = message;
  for (size_t i = m.find('\0'); i != std::string::npos; i = m.find('\0', i + 2))
    m.replace(i, 1, "\\0");
  return m;
}

void fail(ErrorCode code, const std::string& file, const std::string& what) {
  throw Error(code, file.empty() ? what : file + ": " + what);
}

}  // namespace capz
