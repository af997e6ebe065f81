// PLY point-cloud frames, read and written by capz (no outside library). Part of the decoder
// library.
//
// Reading: "ply", a format line (ascii, binary_little_endian or binary_big_endian, 1.0), comment
// and obj_info lines, elements with scalar properties, "end_header". The element "vertex" holds
// the points: x y z (float or double) and any other scalar properties, kept as point attributes
// (little-endian bytes whatever the file's byte order) in the file's order. Any other element
// must be empty (count 0, e.g. the "element face 0" point-cloud exporters write): capz keeps
// point clouds, not meshes, so a face or edge list is refused, as is a list property of the
// vertex element. A vertex with a NaN or infinite coordinate is a gap kept in place. Bytes after
// the last vertex of a binary body are ignored.
//
// Writing: the same header form (comments and obj_info kept, the property type names as the
// source spelled them), vertex element only, in the source's encoding unless asked otherwise;
// gaps are NaN points.
#pragma once

#include <cstddef>
#include <cstdint>
#include <memory>
#include <optional>
#include <string>
#include <vector>

#include "capz/io.h"
#include "capz/stream.h"
#include "capz/take.h"
#include "io/frame_files.h"

namespace capz {

// A PLY header as capz reads it.
struct PlyHeader {
  std::string encoding;  // "ascii", "binary_little_endian", "binary_big_endian"
  std::string version = "1.0";
  size_t vertices = 0;
  std::vector<PCDField> fields;         // the vertex properties in order (count 1)
  std::vector<std::string> type_names;  // each as the file spells its type
  std::vector<std::string> comments, obj_info;
  size_t body = 0;  // offset of the body (after end_header's line end)
  size_t step = 0;  // bytes per vertex in a binary body
};

// Parses the header of `bytes` (the file, or its first bytes through end_header). Throws
// Error(kNotOurFormat) when it is not a PLY file, kCorrupt naming `name` for a malformed or
// unsupported header.
PlyHeader parse_ply_header(const std::vector<uint8_t>& bytes, const std::string& name);

// Checks that a file of `file_size` bytes can hold the vertices `h` announces. Throws
// Error(kCorrupt) naming `name` ("truncated"): what a folder is checked with when opened, before
// anything is allocated for its frames.
void check_ply_body_fits(const PlyHeader& h, uint64_t file_size, const std::string& name);

// Reads a whole PLY file's vertices into *out (its xyz, valid, and one attribute byte array per
// property other than x y z). Throws Error(kCorrupt) naming `name` for a body truncated
// mid-vertex or a malformed ASCII line.
void read_ply_frame(const std::vector<uint8_t>& bytes, const PlyHeader& h, const std::string& name,
                    FrameData* out);

// How a take's frames become PLY vertices: the properties and each one's place.
struct PlyPlan {
  PlyHeader header;            // encoding, version, fields, type names, comments
  std::vector<int> attribute;  // per field: its Take::attributes index; -1 x, -2 y, -3 z
  bool xyz_from_data = false;  // the coordinates' type came from the coordinates
};

// The plan for `take` in `encoding` (empty: the source's, else binary_little_endian): the
// source's vertex layout when it matches the take's attributes, else x y z (float when every
// valid coordinate is exactly a float, else double) then each attribute of COUNT 1 (padding
// "_" fields and fields of COUNT above 1 left out: PLY properties hold one value).
// `xyz_float`, when given, says whether every valid coordinate is exactly a float (a sink that
// scanned the frames block by block) instead of take.xyz.
PlyPlan ply_plan(const Take& take, const std::string& encoding,
                 std::optional<bool> xyz_float = std::nullopt);

// The PLY file of `n` points: xyz (n x 3), valid (n; gaps are NaN vertices), and per take
// attribute a pointer to the frame's bytes (n x count x size; only COUNT 1 ones are written).
std::vector<uint8_t> ply_frame_bytes(const PlyPlan& plan, size_t n, const double* xyz,
                                     const uint8_t* valid,
                                     const std::vector<const uint8_t*>& attr_bytes);

// A folder of PLY frames written block by block (frame_folder_sink): the files write_ply_folder
// writes of the whole take.
std::unique_ptr<FrameSink> ply_folder_sink(const Take& header, const std::string& path,
                                           const WriteOptions& opts);

}  // namespace capz
