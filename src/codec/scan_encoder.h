// The encoder of ragged takes (frames of their own point counts; docs/FORMAT.md "Scans
// (format 1.1)"): the grid chosen as for every take (grid_choice.h) in a first pass over the
// source, then windows of whole frames read one at a time,
// each window's positions coded by the scan geometry coder (coding/scan_geometry.h) into an SCNW
// chunk and its point fields, flattened, into an ATTR chunk (coding/attributes.h), and every
// window decoded again by the one decoder (decoder.h) and checked, fields byte for byte.
#pragma once

#include <cstdint>
#include <string>
#include <vector>

#include "capz/codec.h"
#include "capz/stream.h"
#include "codec/encoder.h"

namespace capz {

// The ragged take of `source` (its header ragged, a PLY or .bin layout settled:
// settle_frame_layout) to .capz bytes in *out, memory bounded by a window: pass 1 reads the
// source a window at a time for the grid, pass 2 reads, codes, checks and writes each window
// (docs/STREAMING.md). Throws Error(kInvalidParameter) for what format 1.1 does not code yet (a
// KG target, analog or rotations, other sources than frame files) and for fields that do not
// match the take (settle_fields, --attr-error naming no float field), Error(kInternal) when the
// self-check fails. Point fields are kept (exact, or within opts.attr_error) unless
// opts.drop_fields. `original`: the folder the frames were read from (FrameSource::original_file),
// or empty; a lossless stream of a PCD folder carries the residue that rebuilds its frame files
// byte for byte (FORMAT.md "Lossless ragged streams"). organized: every frame has one count,
// and META keeps the frames' shape (FORMAT.md "Ragged frames: HEAD and the window chunk": the
// source's PCD width x height when that is the count, else the count x 1), so that the stream
// decodes as the fixed take the frames were read as (capz_source.h); else kInvalidParameter.
void encode_ragged(FrameSource& source, const CompressOptions& opts, StreamOut* out,
                   CompressStats* stats, const std::string& original = "", bool organized = false);

// The same for a ragged take in memory (t.ragged()); the same bytes.
std::vector<uint8_t> compress_ragged(const Take& t, const CompressOptions& opts,
                                     CompressStats* stats, const std::string& original = "",
                                     bool organized = false);
// The same for a take given up: a window of all its frames takes its arrays instead of a copy
// (io/take_source.h).
std::vector<uint8_t> compress_ragged(Take&& t, const CompressOptions& opts, CompressStats* stats,
                                     const std::string& original = "", bool organized = false);

}  // namespace capz
