// The TRC residue's decoder (see trc_residue.h; byte layout in docs/FORMAT.md 7, 14); the
// encoder is trc_residue_encode.cpp.
#include "io/residue/trc_residue.h"

#include <algorithm>
#include <cstring>
#include <map>

#include "capz/error.h"
#include "coding/bytes.h"
#include "io/residue/mode.h"
#include "io/residue/pack.h"
#include "io/residue/trc_comma_head.h"
#include "io/residue/trc_residue_shared.h"
#include "io/residue/windows.h"
#include "io/text_number.h"
#include "io/trc_internal.h"

namespace capz {
namespace residue {

using namespace trcr;

// ---- decoder ---------------------------------------------------------------------------------

TRCResidueDecoder::TRCResidueDecoder(const uint8_t* data, size_t size, const Take& header,
                                     const std::string& name, uint64_t file_size)
    : name_(name), header_(header) {
  const std::string what = name + ": TRC residue";
  ByteReader in(data, size, what);
  if (in.u8() != kKindTRC) fail(ErrorCode::kCorrupt, what, "not a TRC residue");
  const uint64_t limit = file_size ? file_size : UINT64_MAX;
  if (trc::take_delimiter(header) == ',') {
    comma_ = true;
    head_ = decode_comma_head(in, header, name, limit, &layout_);
  } else {
    const std::string dict = trc::header_text(header, name, '\t');
    head_ = unpack(in, std::vector<uint8_t>(dict.begin(), dict.end()), limit);
  }
  // A window payload: the model (a varint a column, gap and ending text) and exceptions, whose
  // texts are the window's own bytes plus two varints a field at most.
  if (file_size) window_limit_ = 3 * file_size + 3 * uint64_t{header.points} * 10 + 65536;
  if (!in.at_end()) fail(ErrorCode::kCorrupt, what, "bytes left after the payload");
}

void TRCResidueDecoder::window(const FrameBlock& block, const uint8_t* payload, size_t n,
                               std::vector<uint8_t>* out, bool exact) {
  const std::string what = name_ + ": TRC residue window at frame " + std::to_string(block.first);
  if (block.first != next_)
    fail(ErrorCode::kCorrupt, what, "expected frame " + std::to_string(next_) + " next");
  check_block(header_, block, name_, ErrorCode::kCorrupt);
  ByteReader packed(payload, n, what);
  const std::vector<uint8_t> body = unpack(packed, {}, window_limit_);
  if (!packed.at_end()) fail(ErrorCode::kCorrupt, what, "bytes left after the payload");
  ByteReader in(body.data(), body.size(), what);
  const uint64_t bytes = in.varint();
  RowModel m;
  m.time_decimals = in.varint();
  m.trailing = in.varint();
  m.gap = in.str();
  m.ending = in.str();
  if (m.time_decimals > kMaxDecimals || m.trailing > kMaxTrailing || m.gap.size() > kMaxGapText ||
      m.ending.size() > kMaxEnding)
    fail(ErrorCode::kCorrupt, what, "impossible row model");
  if (comma_) m.ending = swap_ending(m.ending, layout_);
  m.decimals.resize(3 * block.points);
  for (auto& d : m.decimals)
    if ((d = in.varint()) > kMaxDecimals) fail(ErrorCode::kCorrupt, what, "impossible decimals");
  const size_t at = out->size();
  uint64_t exceptions = in.count(2, "exceptions");
  uint64_t next_ex = exceptions ? in.varint() : block.frames;
  std::vector<std::string> fields;
  const char delim = trc::take_delimiter(header_);
  for (size_t k = 0; k < block.frames; ++k) {
    predict(m, header_, block, k, &fields, exact);
    std::string ending = m.ending;
    if (k == next_ex) {
      const uint8_t flags = in.u8();
      if (flags == 0 || flags > 7) fail(ErrorCode::kCorrupt, what, "bad exception flags");
      if (flags & kFieldCount) {
        const uint64_t count = in.varint();
        if (count == 0 || count > fields.size() + kMaxExtraFields)
          fail(ErrorCode::kCorrupt, what, "impossible field count");
        fields.resize(static_cast<size_t>(count));
      }
      if (flags & kFixFields) {
        const uint64_t nfix = in.count(2, "field fixes");
        for (uint64_t i = 0, field = 0; i < nfix; ++i) {
          field += in.varint();
          if (field >= fields.size()) fail(ErrorCode::kCorrupt, what, "field fix past the row");
          fields[field] = in.str();
        }
      }
      if (flags & kNewEnding) ending = comma_ ? swap_ending(in.str(), layout_) : in.str();
      const uint64_t step = --exceptions ? in.varint() : block.frames;
      if (exceptions && step == 0) fail(ErrorCode::kCorrupt, what, "exceptions out of order");
      next_ex = exceptions ? next_ex + step : block.frames;
    }
    for (size_t i = 0; i < fields.size(); ++i) {
      if (i) out->push_back(static_cast<uint8_t>(delim));
      out->insert(out->end(), fields[i].begin(), fields[i].end());
    }
    out->insert(out->end(), ending.begin(), ending.end());
  }
  if (exceptions || !in.at_end())
    fail(ErrorCode::kCorrupt, what, "exceptions beyond the window's rows");
  if (exact && out->size() - at != bytes)
    fail(ErrorCode::kCorrupt, what,
         "rebuilt " + std::to_string(out->size() - at) + " bytes, the residue says " +
             std::to_string(bytes));
  next_ += block.frames;
}

void TRCResidueDecoder::finish() const {
  if (next_ != header_.frames)
    fail(ErrorCode::kCorrupt, name_,
         "TRC residue: " + std::to_string(next_) + " of " + std::to_string(header_.frames) +
             " frames rebuilt");
}

// ---- whole-file helpers ----------------------------------------------------------------------

void rebuild_trc(const FileResidue& residue, FrameSource& frames, size_t block,
                 const std::function<void(const uint8_t*, size_t)>& write, const std::string& name,
                 uint64_t file_size) {
  TRCResidueDecoder dec(residue.file_part.data(), residue.file_part.size(), frames.header(), name,
                        file_size);
  write(dec.head().data(), dec.head().size());
  rebuild_windows(
      residue, frames, block,
      [&](const FrameBlock& b, const std::vector<uint8_t>& w, std::vector<uint8_t>* out) {
        dec.window(b, w.data(), w.size(), out);
      },
      write, name);
  dec.finish();
}

}  // namespace residue
}  // namespace capz
