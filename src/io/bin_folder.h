// .bin frames: a file per frame, a record a point, no header, little-endian: KITTI's float32
// x y z intensity (16 bytes a point), nuScenes' x y z intensity ring (20) when the frames are named
// *.pcd.bin (bin_record_fields, capz/take.h), or a record the reader is given (--bin-fields:
// float32 x y z, then fields of any PCD type). Read into a take whose point attributes are the
// record's fields after x y z; a point with a NaN or infinite coordinate is a gap, kept in place.
// Part of the decoder library.
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

// Reads a .bin frame's bytes (`name` for messages) in `record` (the fields after float32 x y z)
// into *out: xyz, valid, and each field's bytes as an attribute. Throws Error(kCorrupt) when
// `size` is not a whole number of points (a file truncated mid-point).
void read_bin_frame(const uint8_t* bytes, size_t size, const std::string& name, FrameData* out,
                    const std::vector<PCDField>& record);

// The bytes of a point of `record` (float32 x y z and the fields).
size_t bin_point_bytes(const std::vector<PCDField>& record);

// Opens a .bin frame folder (or one .bin file) in `record` (the fields after x y z), or in its
// names' record (bin_record_fields) when `record` is null.
std::unique_ptr<FrameSource> open_bin_frames(const std::string& path,
                                             const std::vector<PCDField>* record);

// The fields after x y z of the record of `take`'s .bin frames written at `path`: a .bin
// source's own (bin_record_of, so that its frames come back as they were, whatever the output is
// named); else those of the names written (bin_record_fields: a file named *.pcd.bin gets
// nuScenes' record), KITTI's when they are of two kinds.
std::vector<PCDField> bin_output_record(const Take& take, const std::string& path);

// Per field of a .bin record, its layout and the take's field of that name and COUNT 1, or none
// (SIZE_MAX: zeros).
struct BinRecordSource {
  size_t k = SIZE_MAX;
  PCDField field;         // the record's (its type and size written)
  PointAttribute layout;  // the take's field's type and size
};
std::vector<BinRecordSource> bin_record_sources(const Take& take,
                                                const std::vector<PCDField>& record);
// The .bin file of a frame of `n` points in a record (bin_record_sources): attrs[k] the frame's
// bytes of the take's field k, each value written in the record's type (a field of the same type
// and size bit for bit; gaps' x y z as quiet NaNs). The one writer of .bin frames (the folder
// writers and the lossless residue's regenerated frames).
std::vector<uint8_t> bin_record_frame(const std::vector<BinRecordSource>& record, size_t n,
                                      const double* xyz, const uint8_t* valid,
                                      const std::vector<const uint8_t*>& attrs);

// A folder of .bin frames written block by block (frame_folder_sink): the files write_bin_folder
// writes of the whole take.
std::unique_ptr<FrameSink> bin_folder_sink(const Take& header, const std::string& path,
                                           const WriteOptions& opts);

}  // namespace capz
