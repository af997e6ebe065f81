// .bin frames: a file per frame of float32 little-endian values, a record a point, no header:
// KITTI's x y z intensity (16 bytes a point), or nuScenes' x y z intensity ring (20) when the
// frames are named *.pcd.bin (bin_record_fields, capz/take.h). Read into a take whose point
// attributes are the record's fields after x y z (F 4); a point with a NaN or infinite coordinate
// is a gap, kept in place. Part of the decoder library.
#pragma once

#include <cstdint>
#include <memory>
#include <string>
#include <vector>

#include "capz/io.h"
#include "capz/stream.h"
#include "capz/take.h"
#include "io/frame_files.h"

namespace capz {

// Reads a .bin frame's bytes (`name` for messages) of `fields` float32 values a point after
// x y z into *out: xyz, valid, and each of those values' bytes as an attribute. Throws
// Error(kCorrupt) when `size` is not a whole number of points (a file truncated mid-point).
void read_bin_frame(const uint8_t* bytes, size_t size, const std::string& name, FrameData* out,
                    size_t fields = 1);

// The .bin file of `n` points: xyz (n x 3; gaps written as NaN points), then per point one
// float32 of each of `fields` (n values each, or null for zeros).
std::vector<uint8_t> bin_frame_bytes(size_t n, const double* xyz, const uint8_t* valid,
                                     const std::vector<const float*>& fields);

// A field of `n` points as a .bin frame holds it: the bytes of field `a` (its type and size;
// COUNT 1, any numeric type) converted to float32, a float32 field bit for bit.
std::vector<float> bin_values(const PointAttribute& a, const uint8_t* bytes, size_t n);

// The fields after x y z of the record of `take`'s .bin frames written at `path`: a .bin
// source's own (bin_record_of, so that its frames come back as they were, whatever the output is
// named); else those of the names written (bin_record_fields: a file named *.pcd.bin gets
// nuScenes' record), KITTI's when they are of two kinds.
std::vector<std::string> bin_output_record(const Take& take, const std::string& path);

// Per field of a .bin record, the take's field of that name and COUNT 1 (its layout kept, not its
// values), or none (SIZE_MAX: zeros).
struct BinRecordSource {
  size_t k = SIZE_MAX;
  PointAttribute layout;  // its type and size
};
std::vector<BinRecordSource> bin_record_sources(const Take& take,
                                                const std::vector<std::string>& record);
// The .bin file of a frame of `n` points in a record (bin_record_sources): attrs[k] the frame's
// bytes of the take's field k. The one writer of .bin frames (the folder writers and the lossless
// residue's regenerated frames).
std::vector<uint8_t> bin_record_frame(const std::vector<BinRecordSource>& record, size_t n,
                                      const double* xyz, const uint8_t* valid,
                                      const std::vector<const uint8_t*>& attrs);

// A folder of .bin frames written block by block (frame_folder_sink): the files write_bin_folder
// writes of the whole take.
std::unique_ptr<FrameSink> bin_folder_sink(const Take& header, const std::string& path,
                                           const WriteOptions& opts);

}  // namespace capz
