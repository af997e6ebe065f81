// A comma-separated TRC head coded (see trc_comma_head.h; byte layout in docs/FORMAT.md 14.5):
// the padding width and line end chosen, the lines that differ as exceptions, the cut text
// packed; trc_comma_head.cpp reads it back.
#include <algorithm>
#include <map>

#include "capz/error.h"
#include "io/residue/pack.h"
#include "io/residue/trc_comma_head.h"
#include "io/residue/trc_comma_head_shared.h"
#include "io/trc_internal.h"

namespace capz {
namespace residue {

using namespace comma;

namespace {

uint64_t zigzag(uint64_t width, uint64_t base) {
  return width >= base ? 2 * (width - base) : 2 * (base - width) - 1;
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

}  // namespace residue
}  // namespace capz
