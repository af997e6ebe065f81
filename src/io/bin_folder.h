// KITTI-style .bin frames: a file per frame of float32 little-endian x y z intensity per point,
// no header (16 bytes a point). Read into a take with one point attribute, "intensity" (F 4);
// a point with a NaN or infinite coordinate is a gap, kept in place. Part of the decoder library.
#pragma once

#include <memory>
#include <string>
#include <vector>

#include "capz/io.h"
#include "capz/stream.h"
#include "capz/take.h"
#include "io/frame_files.h"

namespace capz {

// Reads a .bin frame's bytes (`name` for messages) into *out: xyz, valid, and the intensity's
// float32 bytes as its one attribute. Throws Error(kCorrupt) when `size` is not a whole number
// of points (a file truncated mid-point).
void read_bin_frame(const uint8_t* bytes, size_t size, const std::string& name, FrameData* out);

// The .bin file of `n` points: xyz (n x 3; gaps written as NaN points), intensity (n float32
// values, or null for zeros).
std::vector<uint8_t> bin_frame_bytes(size_t n, const double* xyz, const uint8_t* valid,
                                     const float* intensity);

// The intensity of `n` points as a .bin frame holds it: the bytes of field `a` (its type and
// size; COUNT 1, any numeric type) converted to float32, a float32 field bit for bit.
std::vector<float> bin_intensity(const PointAttribute& a, const uint8_t* bytes, size_t n);

// A folder of .bin frames written block by block (frame_folder_sink): the files write_bin_folder
// writes of the whole take.
std::unique_ptr<FrameSink> bin_folder_sink(const Take& header, const std::string& path,
                                           const WriteOptions& opts);

}  // namespace capz
