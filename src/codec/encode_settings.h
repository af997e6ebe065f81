// What CompressOptions settle on a source's header before encoding (docs/FORMAT.md 5.7, 5.5):
// the PCD layout of its point fields (or their removal), the bounds of float fields and the
// bounds of analog channels. Each edits the header through FrameSource::edit_header and throws
// Error(kInvalidParameter) for a request the take cannot meet.
#pragma once

#include <cstdint>
#include <string>
#include <vector>

#include "capz/codec.h"
#include "capz/stream.h"
#include "capz/take.h"

namespace capz {

// A take with point fields gets a PCD layout for META (one read from a PCD folder keeps its own;
// any other: x y z as float64, then the fields, one row); with opts.drop_fields the fields are
// left out instead.
void settle_fields(FrameSource& source, const CompressOptions& opts);
void settle_fields(Take& header, const CompressOptions& opts);
// "Scans (format 1.1)": a take of PLY or .bin frames (t->format) without a PCD layout gets the
// one META stores for it (FORMAT.md, frame-file sources): encoding binary, its frame names, its
// fields (a PLY's properties, a .bin's x y z intensity; else x y z float64 and the attributes).
// Fields the format cannot hold: with drop_fields the layout is the source's x y z alone, else
// Error(kInvalidParameter) (--drop-fields leaves them out).
void settle_frame_layout(Take* t, bool drop_fields = false);
// Whether the stream of take t says its .bin record is a declared one (HEAD's frame_format 6,
// FORMAT.md "Frame-file sources"): t's record is declared (t.bin->declared) and its fields are
// kept, or it has none (x y z alone). Dropped, the stream takes the names' record (4).
inline bool declares_bin_record(const Take& t, bool drop_fields) {
  return t.format == Format::kBinFolder && t.bin && t.bin->declared &&
         (t.bin->record.empty() || !drop_fields);
}
// The per-field bounds of opts.attr_error on the header's PCD layout (field_bounds).
void set_field_bounds(FrameSource& source, const CompressOptions& opts);
void set_field_bounds(Take& header, const CompressOptions& opts);
// The per-channel bounds of opts.analog_max_error on the header's analog channels: a key names
// a channel's label or its unit; a label's bound wins over its unit's. Returns the keys that
// name no channel.
std::vector<std::string> set_analog_bounds(FrameSource& source, const CompressOptions& opts);

}  // namespace capz
