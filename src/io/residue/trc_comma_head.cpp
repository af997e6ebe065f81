// A comma-separated TRC head read back (see trc_comma_head.h; byte layout in docs/FORMAT.md
// 14.5), the line ends swapped, and what the encoder (trc_comma_head_encode.cpp) shares with it
// (trc_comma_head_shared.h).
#include "io/residue/trc_comma_head.h"

#include <algorithm>
#include <map>

#include "capz/error.h"
#include "io/residue/pack.h"
#include "io/residue/trc_comma_head_shared.h"
#include "io/trc_internal.h"

namespace capz {
namespace residue {

namespace comma {

// The lines of `t` that end in a line feed (a last line without one is kept as it is). With
// `cut`, each line's trailing commas are its padding, unless cutting them leaves a carriage
// return last (which would join the line end); without, [begin, cr) is the line's text.
std::vector<Line> lines_of(const std::vector<uint8_t>& t, bool cut) {
  std::vector<Line> out;
  size_t b = 0;
  for (size_t i = 0; i < t.size(); ++i) {
    if (t[i] != '\n') continue;
    size_t cr = i;
    while (cr > b && t[cr - 1] == '\r') --cr;
    size_t body = cr;
    if (cut) {
      while (body > b && t[body - 1] == ',') --body;
      if (body > b && t[body - 1] == '\r') body = cr;
    }
    out.push_back({b, body, cr, i + 1, cr - body});
    b = i + 1;
  }
  return out;
}

uint64_t fields_of(const uint8_t* b, const uint8_t* e) {
  return static_cast<uint64_t>(std::count(b, e, ',')) + 1;
}

// The commas a cut line of `fields` fields gets without an exception.
uint64_t default_commas(uint64_t fields, uint64_t width) {
  return width > fields ? width - fields : 0;
}

// `t` with each of `lines` cut of its padding (lines_of(t, true)).
std::vector<uint8_t> cut_text(const std::vector<uint8_t>& t, const std::vector<Line>& lines) {
  std::vector<uint8_t> cut;
  size_t at = 0;
  for (const Line& l : lines) {
    cut.insert(cut.end(), t.begin() + static_cast<long>(l.begin),
               t.begin() + static_cast<long>(l.body));
    cut.insert(cut.end(), t.begin() + static_cast<long>(l.cr),
               t.begin() + static_cast<long>(l.end));
    at = l.end;
  }
  cut.insert(cut.end(), t.begin() + static_cast<long>(at), t.end());
  return cut;
}

// capz's header text in the comma form with the layout's line end, each line cut of its
// trailing commas (as the stored head's lines are).
std::vector<uint8_t> dictionary(const Take& take, const std::string& path, bool crlf) {
  const std::string d = trc::header_text(take, path, ',', 0, crlf ? "\r\n" : "\n");
  const std::vector<uint8_t> text(d.begin(), d.end());
  return cut_text(text, lines_of(text, true));
}

}  // namespace comma

using namespace comma;

std::string swap_ending(const std::string& ending, const CommaLayout& layout) {
  const std::string eol = layout.crlf ? "\r\n" : "\n";
  if (ending == "\n") return eol;
  if (ending == eol) return "\n";
  // The padded blank line: only for a width whose blank line fits an ending (kMaxBlank).
  if (layout.width == 0 || layout.width - 1 > kMaxBlank) return ending;
  const size_t commas = static_cast<size_t>(layout.width - 1);
  if (ending == "\n\n") return eol + std::string(commas, ',') + eol;
  const bool blank = ending.size() == 2 * eol.size() + commas &&
                     ending.compare(0, eol.size(), eol) == 0 &&
                     ending.compare(eol.size() + commas, eol.size(), eol) == 0 &&
                     ending.find_first_not_of(',', eol.size()) == eol.size() + commas;
  return blank ? "\n\n" : ending;
}

std::vector<uint8_t> decode_comma_head(ByteReader& in, const Take& take, const std::string& path,
                                       uint64_t limit, CommaLayout* layout) {
  const uint64_t code = in.varint();
  const uint64_t base = trc::comma_width(take, path), z = code >> 2;
  if ((z & 1) ? (z >> 1) + 2 > base : (z >> 1) > kMaxExtraWidth)
    fail(ErrorCode::kCorrupt, in.what(), "impossible comma padding width");
  const uint64_t width = (z & 1) ? base - (z >> 1) - 1 : base + (z >> 1);
  layout->width = width;
  layout->crlf = (code & kCRLF) != 0;
  std::map<uint64_t, uint64_t> commas;  // line -> its commas, for the exceptions
  if (code & kExceptions) {
    const uint64_t n = in.count(2, "padding exceptions");
    if (n == 0) fail(ErrorCode::kCorrupt, in.what(), "no padding exceptions");
    for (uint64_t i = 0, line = 0; i < n; ++i) {
      const uint64_t delta = in.varint();
      if (i && delta == 0) fail(ErrorCode::kCorrupt, in.what(), "padding exceptions out of order");
      if (delta > limit - line)  // line <= limit: no overflow
        fail(ErrorCode::kCorrupt, in.what(), "padding exception past the head");
      line += delta;
      commas[line] = in.varint();
    }
  }
  const std::vector<uint8_t> cut = unpack(in, dictionary(take, path, layout->crlf), limit);
  const std::vector<Line> lines = lines_of(cut, false);
  if (!commas.empty() && commas.rbegin()->first >= lines.size())
    fail(ErrorCode::kCorrupt, in.what(), "padding exception past the head");
  std::vector<uint8_t> head;
  size_t at = 0;
  for (size_t i = 0; i < lines.size(); ++i) {
    const Line& l = lines[i];
    const auto it = commas.find(i);
    const uint64_t n = it != commas.end()
                           ? it->second
                           : default_commas(fields_of(&cut[l.begin], &cut[l.body]), width);
    if (n > limit - head.size() || l.end - l.begin > limit - head.size() - n)
      fail(ErrorCode::kCorrupt, in.what(), "comma head beyond the original's size");
    head.insert(head.end(), cut.begin() + static_cast<long>(l.begin),
                cut.begin() + static_cast<long>(l.body));
    head.insert(head.end(), static_cast<size_t>(n), ',');
    head.insert(head.end(), cut.begin() + static_cast<long>(l.cr),
                cut.begin() + static_cast<long>(l.end));
    at = l.end;
  }
  head.insert(head.end(), cut.begin() + static_cast<long>(at), cut.end());
  if (head.size() > limit)
    fail(ErrorCode::kCorrupt, in.what(), "comma head beyond the original's size");
  return head;
}

}  // namespace residue
}  // namespace capz
