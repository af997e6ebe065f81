// PCD frames capz reads without PCL: binary and binary_compressed bodies under a plain header,
// the kind PCL, Open3D and LiDAR drivers write. Part of the decoder library.
//
// Why: PCL's reader lives in a module loaded on first use (pcd_backend.h), and loading it costs a
// process about 55 ms of CPU, more than coding a 100k-point sweep. These two bodies are simple to
// read (binary: the points as they are; binary_compressed: one LZF stream of the fields one after
// another, coding/lzf.h), so capz reads them itself and asks PCL for everything else.
//
// The contract: read_native gives the cloud PCL's PCDReader gives for the same bytes (field
// offsets, types and counts, the point bytes), or declines. It declines whatever it is not sure
// PCL reads the same way: a header line PCL would parse otherwise (tabs, carriage returns, runs
// of blanks, a whitespace-only line, keys out of PCL's order), a COUNT below 1, a SIZE and TYPE
// PCL has no type for, a `_` padding field in a compressed body (PCL's unpacking skips it), a
// corrupt compressed body. The caller then asks PCL, so the answer and every error message stay
// those of PCL.
#pragma once

#include <cstdint>
#include <vector>

#include "io/pcd_backend.h"
#include "io/pcd_header.h"

namespace capz {
namespace pcd {

// `bytes` is the whole file, `h` its header as parse_header read it (the body checked to fit),
// with at least one point. True when *cloud now holds the frame; false when the file is left to
// PCL (*cloud unspecified). With `planar` given, a binary_compressed body's points are left in
// *planar as the body lays them out (each field's values for every point, field after field;
// a field's plane starts at points x its Field::offset) and cloud->data is empty: the caller
// skips interleaving them. With `coordinates` too, only the planes through the last of x y z's
// are decompressed (the others unspecified): a body whose runs give them is read, even if a run
// after them would make the whole body refused.
bool read_native(const std::vector<uint8_t>& bytes, const PcdHeader& h, Cloud* cloud,
                 std::vector<uint8_t>* planar = nullptr, bool coordinates = false);

}  // namespace pcd
}  // namespace capz
