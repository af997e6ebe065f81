// Decoder stage: the chunk frame of a .capz (stream_reader.h). Part of the decoder library.
#include "codec/stream_reader.h"

#include <algorithm>

#include "capz/error.h"
#include "coding/bytes.h"
#include "coding/meta.h"

namespace capz {

const uint8_t* FileBytes::get(size_t off, size_t n) {
  buf_.resize(n);
  file_.read_at(off, buf_.data(), n);
  return buf_.data();
}

Chunk chunk_at(StreamBytes& b, size_t off, const std::string& name) {
  const size_t size = b.size();
  if (off > size || size - off < kChunkOverhead) return read_chunk(nullptr, size, off, name, off);
  const uint32_t len = load_le32(b.get(off, 8) + 4);
  const size_t n = len <= size - off - kChunkOverhead ? kChunkOverhead + len : 8;
  return read_chunk(b.get(off, n), size, off, name, off);
}

StreamContext read_context(const StreamHeader& h, const Chunk& meta, const StreamFeatures& f,
                           const std::string& name) {
  StreamContext c;
  c.name = name;
  c.features = f;
  c.h = h;
  c.take.frames = static_cast<size_t>(c.h.frames);
  c.take.points = c.h.points;
  c.take.format = c.h.source_format;
  c.take.analog.channels = static_cast<int>(std::min<uint32_t>(c.h.analog_channels, 1u << 30));
  c.take.analog.samples_per_frame =
      static_cast<int>(std::min<uint32_t>(c.h.analog_samples_per_frame, 1u << 30));
  c.take.rotations.segments = static_cast<int>(std::min<uint32_t>(c.h.rotation_segments, 1u << 30));
  c.take.rotations.samples_per_frame =
      static_cast<int>(std::min<uint32_t>(c.h.rotation_samples_per_frame, 1u << 30));
  if (c.h.bin_record_declared) {  // META's fields are the record (FORMAT.md "Frame-file sources")
    c.take.bin = std::make_shared<BinExtra>();
    c.take.bin->declared = true;
  }
  decode_meta(meta, name, &c.take, &c.words, c.h.ragged);
  if (organized_points(c) > 0 && c.h.points_reordered)
    fail(ErrorCode::kCorrupt, name,
         "frames of one organized shape in a reordered stream of ragged frames");
  return c;
}

namespace {

// INDX ends the file; its payload's last 4 bytes give its payload length.
Chunk index_chunk(StreamBytes& b, size_t meta_end, const std::string& name) {
  const size_t size = b.size();
  if (size < meta_end + kChunkOverhead + 4)
    fail(ErrorCode::kCorrupt, name, "truncated: the stream ends before its INDX chunk");
  const uint64_t ilen = load_le32(b.get(size - 8, 4));
  if (ilen + kChunkOverhead > size - meta_end)
    fail(ErrorCode::kCorrupt, name, "truncated or damaged: no INDX chunk at the end of the stream");
  const size_t ioff = size - kChunkOverhead - static_cast<size_t>(ilen);
  Chunk k = chunk_at(b, ioff, name);
  if (k.type != "INDX" || k.end != size)
    fail(ErrorCode::kCorrupt, name, "truncated or damaged: no INDX chunk at the end of the stream");
  return k;
}

}  // namespace

namespace {

// The file-level chunks after META (HASH, C3DR, TRCR, PCDR, or an ancillary type; an unknown
// critical type is refused), each checked, recorded in ps->file_chunks; returns the offset of
// the first window (its POSW, or SCNW in a stream of ragged frames, format 1.1).
size_t file_level_chunks(StreamBytes& b, size_t off, const std::string& name, ParsedStream* ps) {
  const size_t size = b.size();
  while (off + 4 <= size) {
    const uint8_t* t = b.get(off, 4);
    const std::string type(reinterpret_cast<const char*>(t), 4);
    if (type == "POSW" || type == "SCNW" || type == "INDX") break;
    const Chunk x = chunk_at(b, off, name);
    check_chunk_known(x, ps->features, name);
    if (ps->file_chunks.count(x.type)) fail(ErrorCode::kCorrupt, name, "two " + x.type + " chunks");
    ps->file_chunks[x.type] = {x.offset, x.end};
    ps->chunk_bytes[x.type] += x.end - x.offset;
    off = x.end;
  }
  return off;
}

}  // namespace

ParsedStream parse_stream(StreamBytes& b, const std::string& name) {
  const size_t size = b.size();
  const uint8_t* fh = b.get(0, std::min(size, kFileHeaderBytes));
  const StreamFeatures f = check_file_header(fh, std::min(size, kFileHeaderBytes), name);
  Chunk c = chunk_at(b, kFileHeaderBytes, name);
  if (c.type != "HEAD") fail(ErrorCode::kCorrupt, name, "first chunk is " + c.type + ", not HEAD");
  // HEAD's payload pointer is invalidated by the next get(): decode it before reading META.
  const StreamHeader h = decode_header(c, name, f);
  const size_t head_bytes = c.end - c.offset;
  Chunk m = chunk_at(b, c.end, name);
  if (m.type != "META") fail(ErrorCode::kCorrupt, name, "second chunk is " + m.type + ", not META");
  check_header_fits(h, size, name);
  ParsedStream ps;
  static_cast<StreamContext&>(ps) = read_context(h, m, f, name);
  ps.chunk_bytes["HEAD"] += head_bytes;
  ps.chunk_bytes["META"] += m.end - m.offset;
  ps.first_window_offset = file_level_chunks(b, m.end, name, &ps);
  Chunk k = index_chunk(b, ps.first_window_offset, name);
  ps.index = decode_index(k, name);
  ps.index_offset = k.offset;
  ps.chunk_bytes["INDX"] += k.end - k.offset;
  if (ps.index.size() != ps.h.windows())
    fail(ErrorCode::kCorrupt, name,
         "INDX lists " + std::to_string(ps.index.size()) + " windows, HEAD implies " +
             std::to_string(ps.h.windows()));
  return ps;
}

void check_tiling(const ParsedStream& ps, size_t size, const std::string& name) {
  size_t expect = ps.first_window_offset;
  for (size_t w = 0; w < ps.index.size(); ++w) {
    if (ps.index[w].offset != expect)
      fail(ErrorCode::kCorrupt, name,
           "INDX: window " + std::to_string(w) + " starts at byte " +
               std::to_string(ps.index[w].offset) + ", expected " + std::to_string(expect));
    expect += static_cast<size_t>(std::min<uint64_t>(ps.index[w].bytes, size));
  }
  if (expect != ps.index_offset)
    fail(ErrorCode::kCorrupt, name,
         "INDX: windows end at byte " + std::to_string(expect) + ", the index starts at " +
             std::to_string(ps.index_offset));
}

namespace {

// Elements [first, first + count) of v, when v holds one per frame of a take of F frames.
template <typename T>
void slice(size_t first, size_t count, size_t F, std::vector<T>* v) {
  if (v->size() != F) return;
  const auto b = v->begin() + static_cast<std::ptrdiff_t>(first);
  *v = std::vector<T>(b, b + static_cast<std::ptrdiff_t>(count));
}

// A copy of a frame-file extras (PCD, PLY, .bin) with its frame names sliced, when it is set.
template <typename Extra>
void slice_frame_names(size_t first, size_t count, size_t F, std::shared_ptr<Extra>* extra) {
  if (!*extra) return;
  auto x = std::make_shared<Extra>(**extra);
  slice(first, count, F, &x->frame_names);
  *extra = x;
}

}  // namespace

// The per-frame metadata of *t (a take of F frames) cut to frames [first, first + count).
void slice_frame_metadata(size_t first, size_t count, size_t F, Take* t) {
  t->first_frame += static_cast<decltype(t->first_frame)>(first);
  if (t->trc) {
    auto x = std::make_shared<TRCExtra>(*t->trc);
    slice(first, count, F, &x->times);
    slice(first, count, F, &x->frame_numbers);
    t->trc = x;
  }
  slice_frame_names(first, count, F, &t->pcd);
  slice_frame_names(first, count, F, &t->ply);
  slice_frame_names(first, count, F, &t->bin);
}

}  // namespace capz
