// One PCD frame file's bytes, written by capz (not PCL) so every field keeps its name, type and
// order, padding fields ("_") included, and the bytes are capz's to reproduce.
//
// Header: "# .PCD v<version> - Point Cloud Data file format", VERSION, FIELDS, SIZE, TYPE, COUNT,
// WIDTH, HEIGHT, VIEWPOINT, POINTS, DATA, one line each. Bodies:
//   binary            the points as given (point-major, fields in order, little-endian);
//   binary_compressed uint32 compressed size, uint32 raw size, then LZF (coding/lzf.h) of the
//                     points rearranged field-major (each field's values for every point);
//   ascii             one line a point, the values separated by one blank: integers in decimal,
//                     floats as the shortest text that reads back to the same float32 / float64
//                     ("nan", "inf", "-inf" for those); a float32 field named rgb or rgba is
//                     written as TYPE U, its 4 bytes as one unsigned integer (as PCL does: the
//                     packed colours with alpha 255 are NaN patterns no float text keeps).
// Padding fields ("_") are written in binary bodies only (PCL's ASCII and compressed readers
// skip them, and its writers leave them out).
#pragma once

#include <cstddef>
#include <cstdint>
#include <string>
#include <vector>

#include "capz/take.h"

namespace capz {

struct PcdFrameLayout {
  std::string version = "0.7";
  size_t width = 0, height = 1;   // width x height points
  std::vector<double> viewpoint;  // 7 values, or empty for 0 0 0 1 0 0 0
  std::vector<PCDField> fields;   // in order; a point is the sum of size x count bytes
  std::string encoding = "binary";
};

// The file's bytes for `points` (width x height points of the layout's point size each).
std::vector<uint8_t> pcd_frame_bytes(const PcdFrameLayout& layout, const uint8_t* points);

}  // namespace capz
