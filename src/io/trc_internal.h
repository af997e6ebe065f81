// capz — the TRC writer by parts (trc.cpp), for writing a take a block of frames at a time.
#pragma once

#include <cstddef>
#include <cstdint>
#include <string>

#include "capz/take.h"

namespace capz {
namespace trc {

// The five header lines and the blank line before the rows. `take`: metadata and frame count
// (per-frame arrays not used); `path` names the file when the take has no PathFileType line.
std::string header_text(const Take& take, const std::string& path);

// Appends the rows of frames [first, first + count) of `take` (times and frame numbers from its
// metadata); xyz: count x points x 3, valid: count x points, for those frames only.
void append_rows(const Take& take, size_t first, size_t count, const double* xyz,
                 const uint8_t* valid, std::string* out);

}  // namespace trc
}  // namespace capz
