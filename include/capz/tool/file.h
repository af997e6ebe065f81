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

// Throws Error(kUsage) if `path` exists and !overwrite.
void check_output_free(const std::string& path, bool overwrite);

// Writes `bytes` to `path` atomically: a temporary sibling, fsync'ed, then renamed over `path`
// (the destination is untouched on failure). Throws kUsage if `path` exists and !overwrite,
// kIo when the write fails (disk full).
void write_file(const std::string& path, const std::vector<uint8_t>& bytes, bool overwrite);

}  // namespace capz
