// The TRC residue's encoder (see trc_residue.h; byte layout in docs/FORMAT.md 7, 14): the rows
// found in the file, each window's row model chosen by votes, and the rows it does not predict;
// the decoder is trc_residue.cpp.
#include <algorithm>
#include <cstring>
#include <map>

#include "capz/error.h"
#include "coding/bytes.h"
#include "io/residue/mode.h"
#include "io/residue/pack.h"
#include "io/residue/trc_comma_head.h"
#include "io/residue/trc_residue.h"
#include "io/residue/trc_residue_shared.h"
#include "io/residue/windows.h"
#include "io/text_number.h"
#include "io/trc_internal.h"

namespace capz {
namespace residue {

using namespace trcr;

namespace {

// A row's line split at tabs (no trimming) and what follows its last field.
struct Row {
  std::vector<std::string> fields;
  std::string ending;
};

// The TRC reader's blank characters (trc.cpp is_blank, and a comma-separated file's commas): a
// line of only these is not a row.
bool blank_char(char c, char delim) {
  return c == ' ' || c == '\t' || c == '\r' || c == '\0' || c == '\f' || c == '\v' ||
         (delim == ',' && c == ',');
}

// A row's line split at `delim` (the take's: trc::take_delimiter).
Row split_row(const char* b, const char* e, char delim) {
  const char* nl = static_cast<const char*>(std::memchr(b, '\n', static_cast<size_t>(e - b)));
  const char* ce = nl ? nl : e;
  while (ce > b && ce[-1] == '\r') --ce;
  Row r;
  r.ending.assign(ce, e);
  for (const char* s = b;;) {
    const char* t = std::find(s, ce, delim);
    r.fields.emplace_back(s, t);
    if (t == ce) break;
    s = t + 1;
  }
  return r;
}

// Digits after the point; 0 without one or with an exponent (format_decimal's shortest form).
uint64_t decimals_of(const std::string& s) {
  if (s.find_first_of("eE") != std::string::npos) return 0;
  const size_t dot = s.find('.');
  return dot == std::string::npos ? 0 : s.size() - dot - 1;
}

// Votes for the decimals a column is spelled with. A field with k decimals whose value's
// shortest text has s decimals is reproduced by format_decimal(v, d) for every d <= k when
// k == s (the text is the shortest), and only for d == k when k > s (zero padded).
struct DecimalVotes {
  std::map<uint64_t, size_t> exact, up_to;
  void add(const std::string& text, double v) {
    const uint64_t k = decimals_of(text);
    if (decimals_of(format_decimal(v, 0)) == k)
      ++up_to[k];
    else
      ++exact[k];
  }
  uint64_t best() const {
    uint64_t d_best = 0;
    size_t score_best = 0;
    std::vector<uint64_t> cands = {0};
    for (const auto& kv : exact) cands.push_back(kv.first);
    for (const auto& kv : up_to) cands.push_back(kv.first);
    for (uint64_t d : cands) {
      size_t score = exact.count(d) ? exact.at(d) : 0;
      for (auto it = up_to.lower_bound(d); it != up_to.end(); ++it) score += it->second;
      if (score > score_best || (score == score_best && d < d_best)) score_best = score, d_best = d;
    }
    return std::min(kMaxDecimals, d_best);
  }
};

RowModel choose_model(const std::vector<Row>& rows, const Take& t, const FrameBlock& b) {
  const size_t N = b.points;
  const TRCExtra* x = t.trc.get();
  const bool times = x && x->times.size() == t.frames;
  std::map<uint64_t, size_t> trailing;
  std::map<std::string, size_t> gap, ending;
  DecimalVotes tdec;
  std::vector<DecimalVotes> dec(3 * N);
  for (size_t k = 0; k < rows.size(); ++k) {
    const Row& row = rows[k];
    ++ending[row.ending];
    if (row.fields.size() >= 2 && times) tdec.add(row.fields[1], x->times[b.first + k]);
    if (row.fields.size() >= 2 + 3 * N) ++trailing[row.fields.size() - 2 - 3 * N];
    for (size_t c = 0; c < 3 * N && 2 + c < row.fields.size(); ++c) {
      if (b.valid[k * N + c / 3])
        dec[c].add(row.fields[2 + c], b.xyz[k * N * 3 + c]);
      else
        ++gap[row.fields[2 + c]];
    }
  }
  RowModel m;
  m.time_decimals = tdec.best();
  m.trailing = std::min(kMaxTrailing, mode<uint64_t>(trailing, 0));
  m.gap = mode<std::string>(gap, "");
  if (m.gap.size() > kMaxGapText) m.gap.clear();
  m.ending = mode<std::string>(ending, "\n");
  if (m.ending.size() > kMaxEnding) m.ending = "\n";
  m.decimals.resize(3 * N);
  for (size_t c = 0; c < 3 * N; ++c) m.decimals[c] = dec[c].best();
  return m;
}

}  // namespace

// ---- encoder ---------------------------------------------------------------------------------

TRCResidueEncoder::TRCResidueEncoder(const std::string& path, const Take& header)
    : in_(path), header_(header) {
  // One pass over the file a chunk at a time: past the BOM and five lines, then the start of
  // every non-blank line.
  const uint64_t size = in_.size();
  const char delim = trc::take_delimiter(header);
  std::vector<char> buf(size_t{1} << 20);
  size_t lines = 0;
  bool line_start = true, blank = true;
  uint64_t start = 0;
  for (uint64_t at = 0; at < size;) {
    const size_t n = static_cast<size_t>(std::min<uint64_t>(buf.size(), size - at));
    in_.read_at(at, buf.data(), n);
    for (size_t i = 0; i < n; ++i) {
      const char c = buf[i];
      if (line_start) start = at + i, blank = true, line_start = false;
      if (c == '\n') {
        if (lines >= 5 && !blank) offsets_.push_back(start);
        ++lines;
        line_start = true;
      } else if (!blank_char(c, delim)) {
        blank = false;
      }
    }
    at += n;
  }
  if (!line_start && lines >= 5 && !blank) offsets_.push_back(start);
  if (offsets_.size() != header.frames)
    fail(ErrorCode::kInternal, path,
         "TRC residue: " + std::to_string(offsets_.size()) + " rows found, the reader read " +
             std::to_string(header.frames));
  offsets_.push_back(size);
  if (delim == ',') {
    // The comma head's layout is chosen first: the windows' endings are stored by it.
    std::vector<uint8_t> head(static_cast<size_t>(offsets_.front()));
    in_.read_at(0, head.data(), head.size());
    comma_ = true;
    comma_head_ = encode_comma_head(head, header_, in_.path(), &layout_);
  }
}

std::vector<uint8_t> TRCResidueEncoder::window(const FrameBlock& block, bool exact) {
  check_block(header_, block, in_.path(), ErrorCode::kInternal);
  const uint64_t b0 = offsets_[block.first], b1 = offsets_[block.first + block.frames];
  text_.resize(static_cast<size_t>(b1 - b0));
  in_.read_at(b0, &text_[0], text_.size());
  std::vector<Row> rows;
  const char delim = trc::take_delimiter(header_);
  for (size_t k = 0; k < block.frames; ++k)
    rows.push_back(split_row(text_.data() + (offsets_[block.first + k] - b0),
                             text_.data() + (offsets_[block.first + k + 1] - b0), delim));
  const RowModel m = choose_model(rows, header_, block);
  ByteWriter w;
  w.varint(text_.size());
  w.varint(m.time_decimals);
  w.varint(m.trailing);
  w.str(m.gap);
  w.str(comma_ ? swap_ending(m.ending, layout_) : m.ending);
  for (uint64_t d : m.decimals) w.varint(d);
  std::vector<std::string> want;
  size_t last = 0, exceptions = 0;
  ByteWriter ex;
  for (size_t k = 0; k < block.frames; ++k) {
    predict(m, header_, block, k, &want, exact);
    const Row& row = rows[k];
    const bool same_count =
        row.fields.size() == want.size() || row.fields.size() > want.size() + kMaxExtraFields;
    if (!same_count || row.fields.size() > want.size()) want.resize(row.fields.size());
    std::vector<size_t> fix;
    const size_t N = block.points;
    for (size_t i = 0; i < row.fields.size(); ++i) {
      // At a bound a valid sample's coordinates are the decoder's to print: never fixed.
      const bool coordinate = i >= 2 && i < 2 + 3 * N && block.valid[k * N + (i - 2) / 3];
      if (row.fields[i] != want[i] && (exact || !coordinate)) fix.push_back(i);
    }
    const uint8_t flags =
        static_cast<uint8_t>((same_count ? 0 : kFieldCount) | (fix.empty() ? 0 : kFixFields) |
                             (row.ending != m.ending ? kNewEnding : 0));
    if (!flags) continue;
    ++exceptions;
    ex.varint(k - last);
    last = k;
    ex.u8(flags);
    if (flags & kFieldCount) ex.varint(row.fields.size());
    if (flags & kFixFields) {
      ex.varint(fix.size());
      for (size_t i = 0, prev = 0; i < fix.size(); prev = fix[i], ++i) {
        ex.varint(fix[i] - prev);
        ex.str(row.fields[fix[i]]);
      }
    }
    if (flags & kNewEnding) ex.str(comma_ ? swap_ending(row.ending, layout_) : row.ending);
  }
  w.varint(exceptions);
  w.bytes(ex.buffer());
  ByteWriter out;
  pack(w.buffer(), {}, out);
  return std::move(out.buffer());
}

std::vector<uint8_t> TRCResidueEncoder::file_part() {
  ByteWriter out;
  out.u8(kKindTRC);
  if (comma_) {
    out.bytes(comma_head_);
    return std::move(out.buffer());
  }
  std::vector<uint8_t> head(static_cast<size_t>(offsets_.front()));
  in_.read_at(0, head.data(), head.size());
  const std::string dict = trc::header_text(header_, in_.path(), '\t');
  pack(head, std::vector<uint8_t>(dict.begin(), dict.end()), out);
  return std::move(out.buffer());
}

FileResidue encode_trc_residue(const std::string& path, FrameSource& frames, size_t block) {
  TRCResidueEncoder enc(path, frames.header());
  FileResidue r;
  encode_windows(
      frames, block, [&](const FrameBlock& b) { return enc.window(b); }, &r);
  r.file_part = enc.file_part();
  return r;
}

}  // namespace residue
}  // namespace capz
