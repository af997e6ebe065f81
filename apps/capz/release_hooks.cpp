// The release binary's test hooks: none (compress_common.h; the tests' CLI links its own).
#include "compress_common.h"

namespace capz_cli {

void before_reading_back(const std::string&) {}

}  // namespace capz_cli
