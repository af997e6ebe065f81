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
#include <optional>
#include <string>
#include <vector>

#include "capz/take.h"
#include "coding/lzf.h"

namespace capz {

struct PcdFrameLayout {
  std::string version = "0.7";
  size_t width = 0, height = 1;   // width x height points
  std::vector<double> viewpoint;  // 7 values, or empty for 0 0 0 1 0 0 0
  std::vector<PCDField> fields;   // in order; a point is the sum of size x count bytes
  std::string encoding = "binary";
};

// The file's bytes for `points` (width x height points of the layout's point size each); a
// binary_compressed body is compressed by `lzf` (coding/lzf.h). scratch: a buffer the caller
// keeps from frame to frame for the body's field-major bytes, or null (the same file).
std::vector<uint8_t> pcd_frame_bytes(const PcdFrameLayout& layout, const uint8_t* points,
                                     LzfVariant lzf = LzfVariant::kCapz,
                                     std::vector<uint8_t>* scratch = nullptr);

// The header those bytes start with (through the DATA line's line feed).
std::string pcd_frame_header(const PcdFrameLayout& layout);

// How a take's frames become PCD points: the layout (fields from the take's PCD layout when it
// matches the take's attributes, else x y z then the attributes), each field's offset in a point.
struct PcdFramePlan {
  PcdFrameLayout layout;
  size_t step = 0;  // bytes per point
  size_t axis_offset[3] = {0, 0, 0};
  std::vector<size_t> attr_offset;  // per Take::attributes entry
  bool as_float = true;             // x y z float32 (else float64)
  bool xyz_from_data = false;       // as_float came from the coordinates (no layout said)
};

// The plan for `take` in encoding `enc`. Coordinates: float32 when the layout says so or, without
// a layout, when every valid coordinate is exactly a float: `xyz_float` when given (a sink that
// scanned the frames block by block), else take.xyz's (a take without frame arrays: float32).
// A ragged take's plan has width 0: set layout.width to each frame's count.
PcdFramePlan pcd_frame_plan(const Take& take, const std::string& enc,
                            std::optional<bool> xyz_float = std::nullopt);

// True when every valid coordinate of the `n` points (xyz n x 3, valid n) is exactly a float32.
bool coordinates_are_floats(size_t n, const double* xyz, const uint8_t* valid);

// One value of field f (little-endian bytes at p, f.size of them) as ASCII PCD writes it:
// integers in decimal, floats as the shortest text that reads back to the same value ("nan",
// "inf", "-inf"). Appended to *s. Shared with the PLY writer.
void append_value_text(const PCDField& f, const uint8_t* p, std::string* s);

// One frame's points (plan.step x points bytes into *out): xyz (points x 3), valid (points) and
// per attribute a pointer to the frame's bytes (points x count x size); gaps are NaN points.
void pcd_frame_points(const PcdFramePlan& plan, size_t points, const double* xyz,
                      const uint8_t* valid, const std::vector<const uint8_t*>& attrs,
                      std::vector<uint8_t>* out);

// One frame file's bytes from its arrays as pcd_frame_points gives them: pcd_frame_bytes of
// those points (capz's LZF), through the caller's buffers kept from frame to frame. A
// binary_compressed body is built field-major from the arrays, without the points (*points
// then unused).
std::vector<uint8_t> pcd_frame_file(const PcdFramePlan& plan, size_t points, const double* xyz,
                                    const uint8_t* valid, const std::vector<const uint8_t*>& attrs,
                                    std::vector<uint8_t>* point_bytes, std::vector<uint8_t>* body);

}  // namespace capz
