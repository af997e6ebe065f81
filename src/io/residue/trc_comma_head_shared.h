// What the comma TRC head's encoder (trc_comma_head_encode.cpp) and decoder (trc_comma_head.cpp)
// share (docs/FORMAT.md 14.5): the layout flags and limits, a head's lines, and the dictionary
// both pack against; defined in trc_comma_head.cpp.
#pragma once

#include <cstddef>
#include <cstdint>
#include <string>
#include <vector>

#include "capz/take.h"

namespace capz {
namespace residue {
namespace comma {

inline constexpr uint64_t kCRLF = 1, kExceptions = 2;
// The most fields the padding width may exceed trc::comma_width by.
inline constexpr uint64_t kMaxExtraWidth = uint64_t{1} << 20;
// The most commas of a blank line swap_ending stands in for (a TRCP ending's limit, 14.2).
inline constexpr uint64_t kMaxBlank = 4000;

// One line of a head: [begin, body) its text without trailing commas, then `commas` commas,
// then [cr, end) its carriage returns and line feed.
struct Line {
  size_t begin, body, cr, end;
  uint64_t commas;
};

std::vector<Line> lines_of(const std::vector<uint8_t>& t, bool cut);
uint64_t fields_of(const uint8_t* b, const uint8_t* e);
uint64_t default_commas(uint64_t fields, uint64_t width);
std::vector<uint8_t> cut_text(const std::vector<uint8_t>& t, const std::vector<Line>& lines);
std::vector<uint8_t> dictionary(const Take& take, const std::string& path, bool crlf);

}  // namespace comma
}  // namespace residue
}  // namespace capz
