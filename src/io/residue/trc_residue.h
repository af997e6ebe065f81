// capz — TRC residue: what a TRC file's text holds beyond its Take (issue 14, --lossless).
//
// The file is cut into the head (byte-order mark, the five header lines and any blank lines
// before the first row), kept whole and packed in the file-level payload, and the rows. Row r's
// span runs from its first byte to the next row's (its line end and any blank lines after it
// included; the last row's runs to the end of the file). Each window regenerates its rows from
// the decoded values with a row model chosen for the window and stored in its payload: fields
// joined by the take's delimiter (trc::take_delimiter: a tab, or a comma), the frame number as an
// integer, the time and each coordinate column with the window's most frequent number of decimals
// (capz's format_decimal: the shortest text that parses back, padded with zeros), gaps spelled as
// the window's most frequent gap field ("", "NaN", "       NaN"), the most frequent count of empty
// trailing fields and line end. Rows that differ store exceptions: the fields whose text differs, a
// different line end, or (when the field count differs) the whole line. Byte layout:
// docs/FORMAT.md 7.2, 14.2, 14.5.
#pragma once

#include <cstddef>
#include <cstdint>
#include <functional>
#include <string>
#include <vector>

#include "capz/stream.h"
#include "capz/take.h"
#include "core/input_file.h"
#include "io/residue/pack.h"
#include "io/residue/trc_comma_head.h"

namespace capz {
namespace residue {

class TRCResidueEncoder {
 public:
  // Opens the file and finds each row's span (the TRC reader's rules: five header lines, then
  // every non-blank line is a row). `header`: the take's metadata as open_trc_frames() gives it
  // (times and frame numbers); throws Error(kInternal) if the rows found are not its frames.
  TRCResidueEncoder(const std::string& path, const Take& header);
  // The per-window payload for `block`'s frames (in any order). `exact` false (an archive at a
  // bound): no field fix for a valid sample's coordinates, and the model prints coordinates
  // rounded to its decimals (docs/FORMAT.md 14.2).
  std::vector<uint8_t> window(const FrameBlock& block, bool exact = true);
  // The file-level payload: the head, packed.
  std::vector<uint8_t> file_part();

 private:
  InputFile in_;
  const Take& header_;
  std::vector<uint64_t> offsets_;  // each row's first byte, then the file size
  std::string text_;
  bool comma_ = false;               // a comma-separated TRC (docs/FORMAT.md 14.5)
  CommaLayout layout_;               // its line end and padding width
  std::vector<uint8_t> comma_head_;  // its head's fields, chosen with layout_
};

class TRCResidueDecoder {
 public:
  // `header`: the decoded take's metadata (times, frame numbers: as the encoder's).
  // `file_size`: the original's size when the archive records it (0: unknown), which bounds
  // what payloads may unpack to. Throws Error(kCorrupt) naming `name` when a payload is
  // malformed.
  TRCResidueDecoder(const uint8_t* file_part, size_t size, const Take& header,
                    const std::string& name, uint64_t file_size = 0);
  const std::vector<uint8_t>& head() const { return head_; }
  // The original text of block's rows, appended to *out; blocks in order from frame 0. `exact`
  // false (an archive at a bound): coordinates printed rounded to the model's decimals, the
  // window's size not checked.
  void window(const FrameBlock& block, const uint8_t* payload, size_t n, std::vector<uint8_t>* out,
              bool exact = true);
  // Throws Error(kCorrupt) unless every frame was given.
  void finish() const;

 private:
  std::string name_;
  const Take& header_;
  std::vector<uint8_t> head_;
  uint64_t next_ = 0;
  uint64_t window_limit_ = UINT64_MAX;  // most bytes a window payload may unpack to
  bool comma_ = false;                  // a comma-separated TRC: endings swapped (14.5)
  CommaLayout layout_;
};

// The whole residue of the TRC at `path`: frames read from `frames` in blocks of `block`.
FileResidue encode_trc_residue(const std::string& path, FrameSource& frames, size_t block);
// Rebuilds the original from `frames` (the decoded take, in the encoder's blocks) and the
// residue, handing consecutive byte ranges to `write`.
// `file_size`: as TRCResidueDecoder's.
void rebuild_trc(const FileResidue& residue, FrameSource& frames, size_t block,
                 const std::function<void(const uint8_t*, size_t)>& write, const std::string& name,
                 uint64_t file_size = 0);

}  // namespace residue
}  // namespace capz
