// Decoder library (capz_decode): builds without PCL and without the transform encoders.
// capz — comma-separated TRC head (see trc_comma_head.h; byte layout in docs/FORMAT.md 14.5).
#include "io/residue/trc_comma_head.h"

#include <algorithm>
#include <map>

#include "capz/error.h"
#include "io/residue/pack.h"
#include "io/trc_internal.h"

namespace capz {
namespace residue {

namespace {

constexpr uint64_t kCRLF = 1, kExceptions = 2;
// The most fields the padding width may exceed trc::comma_width by.
constexpr uint64_t kMaxExtraWidth = uint64_t{1} << 20;
// The most commas of a blank line swap_ending stands in for (a TRCP ending's limit, 14.2).
constexpr uint64_t kMaxBlank = 4000;

// One line of a head: [begin, body) its text without trailing commas, then `commas` commas,
// then [cr, end) its carriage returns and line feed.
struct Line {
  size_t begin, body, cr, end;
  uint64_t commas;
};

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

uint64_t zigzag(uint64_t width, uint64_t base) {
  return width >= base ? 2 * (width - base) : 2 * (base - width) - 1;
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

// The head's fields for padding width `width`: layout, exceptions, packed cut text.
std::vector<uint8_t> encode_with(const std::vector<uint8_t>& head, const std::vector<Line>& lines,
                                 const std::vector<uint8_t>& dict, uint64_t width, uint64_t base,
                                 bool crlf) {
  const std::vector<uint8_t> cut = cut_text(head, lines);
  ByteWriter ex;
  size_t exceptions = 0, last = 0;
  for (size_t i = 0; i < lines.size(); ++i) {
    const Line& l = lines[i];
    if (l.commas == default_commas(fields_of(&head[l.begin], &head[l.body]), width)) continue;
    ex.varint(i - last);
    ex.varint(l.commas);
    last = i;
    ++exceptions;
  }
  ByteWriter out;
  out.varint(4 * zigzag(width, base) + (crlf ? kCRLF : 0) + (exceptions ? kExceptions : 0));
  if (exceptions) {
    out.varint(exceptions);
    out.bytes(ex.buffer());
  }
  // zstd's levels parse a short text differently: the smallest of a few (an encoder's choice).
  std::vector<uint8_t> best;
  for (int level : {19, 22, 12, 6, 3, 1}) {
    ByteWriter p;
    pack(cut, dict, p, level);
    if (best.empty() || p.buffer().size() < best.size()) best = std::move(p.buffer());
  }
  out.bytes(best);
  return std::move(out.buffer());
}

}  // namespace

std::vector<uint8_t> encode_comma_head(const std::vector<uint8_t>& head, const Take& take,
                                       const std::string& path, CommaLayout* layout) {
  const std::vector<Line> lines = lines_of(head, true);
  const bool crlf = !lines.empty() && lines[0].end - lines[0].cr >= 2;
  const std::vector<uint8_t> dict = dictionary(take, path, crlf);
  // Widths tried: the default, then each of the five header lines' field counts (an encoder's
  // choice; the smallest payload wins, the default on ties).
  const uint64_t base = trc::comma_width(take, path);
  std::vector<uint64_t> widths = {base};
  for (size_t i = 0; i < lines.size() && i < 5; ++i) {
    const Line& l = lines[i];
    const uint64_t w = fields_of(&head[l.begin], &head[l.body]) + l.commas;
    if (w <= base + kMaxExtraWidth && std::find(widths.begin(), widths.end(), w) == widths.end())
      widths.push_back(w);
  }
  std::vector<uint8_t> best;
  for (uint64_t w : widths) {
    std::vector<uint8_t> b = encode_with(head, lines, dict, w, base, crlf);
    if (best.empty() || b.size() < best.size()) best = std::move(b), layout->width = w;
  }
  layout->crlf = crlf;
  return best;
}

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
