// The decoder: one window of a .capz back to frames (docs/FORMAT.md 8 - 15). This is the one
// decoder: decompress(), the .capz frame source, `capz verify` / `test` and the encoder's
// self-check all call decode_window_chunks. Part of the decoder library.
#pragma once

#include <cstddef>
#include <cstdint>
#include <vector>

#include "capz/stream.h"
#include "codec/stream_reader.h"

namespace capz {

// The gaps of b made valid points at +0.0 +0.0 +0.0: a window whose gaps are origin points
// (FORMAT.md "Origin points", SCNW's gaps bit 0).
void origin_points(FrameBlock* b);

// Decodes window w of the stream described by ctx into *out (frames [w W, ...), every point).
// region holds the window's chunks, the file's bytes [base, end); offsets in messages are file
// offsets. Unknown chunks between the known ones are skipped. Throws kCorrupt naming ctx.name,
// the chunk and the window; kUnsupportedVersion for an unknown transform codec.
// ints: a buffer kept from window to window for a scan window's grid integers (its memory
// reused), or null.
void decode_window_chunks(const StreamContext& ctx, size_t w, const uint8_t* region, size_t base,
                          size_t end, FrameBlock* out, std::vector<int32_t>* ints = nullptr);

// Where window w's chunks are in a stream of `size` bytes, as INDX says: [*base, *end). Throws
// kCorrupt when the entry points outside the file.
void window_extent(const ParsedStream& ps, size_t size, size_t w, size_t* base, size_t* end);

// "Scans (format 1.1)": the frame offsets of a ragged stream (frames + 1), from the counts at
// the head of every window's SCNW payload (the payloads are not decoded). Throws kCorrupt for
// counts that disagree with HEAD or SCNW's total, kMemoryLimit for a window of more than
// ps.max_points points. `splits`, when given, gets each window's float32 split exponent E (mode
// 2; scan::kNoSplit for none, and in every other mode; "Lossless ragged streams").
std::vector<size_t> ragged_frame_offsets(StreamBytes& bytes, const ParsedStream& ps,
                                         std::vector<int>* splits = nullptr);

// Window w of a parsed stream, its chunks fetched from `bytes` as INDX says.
void decode_window(StreamBytes& bytes, const ParsedStream& ps, size_t w, FrameBlock* out,
                   std::vector<int32_t>* ints = nullptr);

}  // namespace capz
