// capz — the head of a comma-separated TRC in its TRCR payload (docs/FORMAT.md 14.5).
//
// A spreadsheet or pyomeca pads every line of a comma-separated TRC with commas to the widest
// line's field count. The head (five header lines and the blank lines before the first row) is
// stored with those runs cut: a `layout` varint names the line end (LF or CRLF) and the width
// each line is padded to, the lines whose padding differs are listed, and the cut text is packed
// against capz's own header text without padding, in that line end.
#pragma once

#include <cstdint>
#include <string>
#include <vector>

#include "capz/take.h"
#include "coding/bytes.h"

namespace capz {
namespace residue {

// What a comma-separated TRC's rows share with its head: the line end and the padding width.
struct CommaLayout {
  uint64_t width = 0;  // fields a padded line has
  bool crlf = false;   // lines end in "\r\n" (else "\n")
};

// The comma head's fields (layout, padding exceptions, packed text) for `head`, the file's bytes
// before its first row; `*layout` gets the layout chosen. `take`: the TRC's metadata
// (trc::comma_width, header_text); `path` names the file when the take has no PathFileType line.
std::vector<uint8_t> encode_comma_head(const std::vector<uint8_t>& head, const Take& take,
                                       const std::string& path, CommaLayout* layout);

// Reads what encode_comma_head wrote and returns the head's bytes, its layout in `*layout`.
// Throws Error(kCorrupt) naming `in.what()` when a field is out of range or the head would
// exceed `limit` bytes.
std::vector<uint8_t> decode_comma_head(ByteReader& in, const Take& take, const std::string& path,
                                       uint64_t limit, CommaLayout* layout);

// A row ending as a comma TRC's TRCP stores it, and back (the same involution both ways): "\n"
// and the layout's line end swap, and so do "\n\n" and a line end, a blank line padded with
// width - 1 commas and a line end; any other text is itself.
std::string swap_ending(const std::string& ending, const CommaLayout& layout);

}  // namespace residue
}  // namespace capz
