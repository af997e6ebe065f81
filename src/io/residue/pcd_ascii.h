// capz — an ascii PCD body as other writers spell it (issue 38; byte layout: docs/FORMAT.md
// 14.6). The body is regenerated from the frame's values: one line a point, the columns (each
// element of each field but padding "_") joined by the frame's separator, each column's numbers
// in a style of its own (text_number.h NumberStyle: capz's, Python's repr, numpy's float32 str,
// %.Ng as PCL and Open3D, %.Ne as numpy savetxt, %.Nf), NaN as the frame's NaN spelling, the
// frame's line end; the lines that differ are stored as exceptions (their fields that differ, or
// the whole line), then the bytes after the last point's line.
#pragma once

#include <cstddef>
#include <cstdint>
#include <vector>

#include "coding/bytes.h"
#include "io/pcd_frame_writer.h"

namespace capz {
namespace residue {

// Appends the payload for `body` (size bytes, the frame file after its header) to *out, given
// the frame's point records as `plan` lays them out (n points); false (nothing appended) when
// the body has fewer than n lines, the layout has no column, or a line end is not found where
// one must be.
bool encode_ascii_body(const PcdFramePlan& plan, const uint8_t* points, size_t n,
                       const uint8_t* body, size_t size, ByteWriter* out);

// Reads a payload of encode_ascii_body from `in` and appends the body it rebuilds to *out.
// `limit`: the most bytes the body may have (the frame file's recorded size). Throws
// Error(kCorrupt) naming `what` on a malformed payload.
void decode_ascii_body(const PcdFramePlan& plan, const uint8_t* points, size_t n, ByteReader& in,
                       uint64_t limit, const std::string& what, std::vector<uint8_t>* out);

}  // namespace residue
}  // namespace capz
