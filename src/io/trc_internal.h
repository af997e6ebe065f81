// capz — the TRC writer by parts (trc_write.cpp), for writing a take a block of frames at a time,
// and the delimiter rule the reader, the writer and the TRC residue share.
#pragma once

#include <cstddef>
#include <cstdint>
#include <string>

#include "capz/take.h"

namespace capz {
namespace trc {

// The delimiter of a TRC whose line 1 is `path_file_type_line`: ',' when the line holds no tab
// and either a comma follows "PathFileType" directly or the line ends in a comma (the comma form
// of pyomeca and of spreadsheets, which pad line 1 with commas; a spreadsheet keeps a
// blank-separated line 1 as one cell), else '\t' (tab- or blank-separated, OpenSim's forms).
char delimiter_of(const std::string& path_file_type_line);
// Cuts the trailing run of commas of a comma-separated line 1 (its padding to the widest line's
// field count, which the TRC residue codes as a width, docs/FORMAT.md 14.5), all of it when a
// comma follows PathFileType, else to one comma, so that the line stays comma-separated.
void cut_padding(std::string* path_file_type_line);
// The take's own delimiter: delimiter_of its TRC line 1; '\t' for a take not read from a TRC.
char take_delimiter(const Take& take);
// The delimiter to write `take` with when WriteOptions::trc_delimiter is `asked`: asked when
// it is '\t' or ',', the take's own when 0; anything else is kInvalidParameter naming `path`.
char output_delimiter(const Take& take, char asked, const std::string& path);
// Fields of every line of the comma form of `take` (the widest line's: line 1, the 8 header
// keys, or Frame#, Time and 3 per point).
size_t comma_width(const Take& take, const std::string& path);

// The five header lines and the blank line before the rows, with fields joined by `delim`
// ('\t' or ','). `take`: metadata and frame count (per-frame arrays not used); `path` names the
// file when the take has no PathFileType line. The take's line 1 is kept as it is when its own
// delimiter is `delim` (or for tab output, unless it is comma-separated), else its fields are
// joined by `delim`, empty trailing fields dropped. With ',' each line is padded with commas to
// comma_width fields (the blank line too).
std::string header_text(const Take& take, const std::string& path, char delim);
// The same with every line of the comma form padded to `width` fields instead (no line is cut;
// the blank line holds width - 1 commas) and `eol` ("\n" or "\r\n") ending each line: the TRC
// residue's dictionary for a comma-separated TRC (docs/FORMAT.md 14.5).
std::string header_text(const Take& take, const std::string& path, char delim, size_t width,
                        const std::string& eol);

// Appends the rows of frames [first, first + count) of `take` (times and frame numbers from its
// metadata); xyz: count x points x 3, valid: count x points, for those frames only. '\t': a
// closing tab on each row; ',': each row padded to `width` fields (comma_width).
void append_rows(const Take& take, size_t first, size_t count, const double* xyz,
                 const uint8_t* valid, char delim, size_t width, std::string* out);

}  // namespace trc
}  // namespace capz
