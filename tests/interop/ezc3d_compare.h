// Field-by-field comparison of two ezc3d reads (an original C3D and the C3D capz wrote from it).
#pragma once

#include <array>
#include <cstddef>
#include <string>

#include "interop/ezc3d_snapshot.h"

namespace capz_interop {

// Classes of difference, one bit each (a known-bad entry allows a set of them).
enum DiffClass : unsigned {
  kShape = 1u << 0,      // frames, points, analog channels or samples per frame differ
  kHeader = 1u << 1,     // a header word or header event differs
  kParams = 1u << 2,     // a group or parameter is missing, added, or differs (type, dims, ...)
  kPoints = 1u << 3,     // a coordinate outside the bound (lossless: not identical)
  kGaps = 1u << 4,       // gap (residual < 0) in one read and not in the other
  kResiduals = 1u << 5,  // residual or camera mask of a sample valid in both differs
  kAnalog = 1u << 6,     // an analog sample differs (bit for bit)
  kRotations = 1u << 7,  // rotation matrices or reliabilities differ
  kRefused = 1u << 8,    // capz threw while compressing, decompressing or writing the take
};
constexpr int kDiffClasses = 9;
const char* diff_name(int bit);        // "shape", "header", ...
std::string diff_names(unsigned set);  // "params+gaps", or "none"

struct Diffs {
  unsigned found = 0;                        // DiffClass bits
  std::array<size_t, kDiffClasses> count{};  // differing items per class
  std::array<std::string, kDiffClasses>
      examples;                // the first 3 differences of each class, in words
  double max_point_error = 0;  // over samples valid in both reads
  void add(DiffClass c, const std::string& what);
  std::string describe() const;  // one clause per class found: "params: 3 (POINT:SCALE ...)"
};

// Compares `got` with `want`. bound: largest allowed coordinate difference in the file's units,
// 0 for exact (bit-identical) coordinates; each coordinate may also differ by one float32 step
// of its magnitude (the writer's rounding of the decoded value).
Diffs compare(const EzTake& want, const EzTake& got, double bound);

}  // namespace capz_interop
