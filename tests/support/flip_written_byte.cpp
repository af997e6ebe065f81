// The hook of the CLI built for the tests (capz_cli_faults; the release binary has none):
// CAPZ_TEST_FLIP_WRITTEN_BYTE=N flips one bit of byte N of OUT on disk before `compress --rm`
// reads it back, as a disk returning bad data would.
#include <cstdio>
#include <cstdlib>
#include <string>

#include "compress_common.h"

namespace capz_cli {

void before_reading_back(const std::string& out) {
  const char* at = std::getenv("CAPZ_TEST_FLIP_WRITTEN_BYTE");
  if (!at) return;
  std::FILE* f = std::fopen(out.c_str(), "r+b");
  if (!f) return;
  const long i = std::strtol(at, nullptr, 10);
  if (std::fseek(f, i, SEEK_SET) == 0) {
    const int c = std::fgetc(f);
    if (c != EOF && std::fseek(f, i, SEEK_SET) == 0) std::fputc(c ^ 0x10, f);
  }
  std::fclose(f);
}

}  // namespace capz_cli
