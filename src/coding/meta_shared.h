// What META's encoder (meta_encode.cpp) and decoder (meta.cpp) share (docs/FORMAT.md 5): the
// frame numbers' wrapping arithmetic and the labels the C3D reader derives from the parameters.
#pragma once

#include <algorithm>
#include <cstdint>
#include <string>
#include <vector>

#include "capz/take.h"
#include "coding/c3d_params.h"

namespace capz {
namespace meta {

// Frame numbers are coded with wrapping int64 arithmetic (FORMAT.md 5.4): every int64
// round-trips, and no input makes the sums overflow (signed overflow is undefined).
inline int64_t wrap_add64(int64_t a, int64_t b) {
  return static_cast<int64_t>(static_cast<uint64_t>(a) + static_cast<uint64_t>(b));
}
inline int64_t wrap_sub64(int64_t a, int64_t b) {
  return static_cast<int64_t>(static_cast<uint64_t>(a) - static_cast<uint64_t>(b));
}

// The lists the C3D reader derives from the parameters (FORMAT.md 5.3, "Labels from the
// parameters"; c3d_read.cpp read_labels_rates_units): cut or padded to the points (descriptions:
// when there are any) and to the channels.
inline void derive_labels(const C3DExtra& c, size_t points, int channels,
                          std::vector<std::string>* l, std::vector<std::string>* d,
                          std::vector<std::string>* a) {
  *l = c3d::string_list(c, "POINT", "LABELS");
  l->resize(points);
  *d = c3d::string_list(c, "POINT", "DESCRIPTIONS");
  if (!d->empty()) d->resize(points);
  *a = c3d::string_list(c, "ANALOG", "LABELS");
  a->resize(static_cast<size_t>(std::max(0, channels)));
}

// "Scans (format 1.1)": the PLY block's encoding codes 0, 1, 2.
inline constexpr const char* kPlyEncodings[] = {"ascii", "binary_little_endian",
                                                "binary_big_endian"};

}  // namespace meta
}  // namespace capz
