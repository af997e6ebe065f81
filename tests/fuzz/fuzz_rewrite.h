// Shared by the rewrite targets (c3d_rewrite, trc_rewrite): a file the reader accepts is written
// back and read again. A refusal by the reader or the writer (capz::Error) is allowed; a file
// capz wrote that does not read back is a finding.
#pragma once

#include <cstdio>
#include <cstdlib>
#include <string>

#include "capz/error.h"
#include "capz/io.h"
#include "fuzz_temp_file.h"

namespace capz_fuzz {

// read(data, size) -> the take; write(take, path, options); read_back(path) -> the take written.
// Returns false when the reader or the writer refused; else *t and *back are filled.
template <typename Read, typename Write, typename ReadBack>
bool rewrite(const TempFile& out, Read&& read, Write&& write, ReadBack&& read_back, capz::Take* t,
             capz::Take* back) {
  try {
    *t = read();
    capz::WriteOptions o;
    o.overwrite = true;
    write(*t, out.path(), o);
  } catch (const capz::Error&) {
    return false;  // a refusal is allowed (it names what it cannot read or write)
  }
  try {
    *back = read_back(out.path());
  } catch (const capz::Error& e) {
    std::fprintf(stderr, "a file capz wrote does not read back: %s\n", e.what());
    std::abort();
  }
  return true;
}

}  // namespace capz_fuzz
