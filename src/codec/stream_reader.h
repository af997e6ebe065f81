// Decoder stage: reading a .capz's frame of chunks (docs/FORMAT.md 3): the file header, HEAD and
// META up front, INDX from the end, and each window's chunks on demand. Part of the decoder
// library.
#pragma once

#include <cstddef>
#include <cstdint>
#include <map>
#include <memory>
#include <string>
#include <vector>

#include "capz/take.h"
#include "coding/container.h"
#include "core/input_file.h"

namespace capz {

// The .capz bytes a decoder reads: all in memory, or read from a file on demand (then only
// HEAD, META, INDX and one window's chunks are held at a time).
class StreamBytes {
 public:
  virtual ~StreamBytes() = default;
  virtual size_t size() const = 0;
  // Bytes [off, off + n), off + n <= size(); the pointer is valid until the next call.
  virtual const uint8_t* get(size_t off, size_t n) = 0;
  virtual uint64_t bytes_read() const { return 0; }
};

class MemoryBytes : public StreamBytes {
 public:
  MemoryBytes(const uint8_t* data, size_t size) : data_(data), size_(size) {}
  size_t size() const override { return size_; }
  const uint8_t* get(size_t off, size_t) override { return data_ + off; }

 private:
  const uint8_t* data_;
  size_t size_;
};

class FileBytes : public StreamBytes {
 public:
  explicit FileBytes(const std::string& path) : file_(path) {}
  size_t size() const override { return static_cast<size_t>(file_.size()); }
  const uint8_t* get(size_t off, size_t n) override;
  uint64_t bytes_read() const override { return file_.bytes_read(); }

 private:
  InputFile file_;
  std::vector<uint8_t> buf_;
};

// What the decoder knows of a stream before its windows: HEAD, META and the version. The
// encoder builds the same from the chunks it wrote (its self-check decodes with it).
struct StreamContext {
  std::string name;         // for messages
  StreamFeatures features;  // what the stream's version lets its chunks use
  StreamHeader h;
  Take take;           // metadata only: frames, points, analog layout, META's fields
  bool words = false;  // windows carry C3DW chunks
  // Ragged streams: the most points a window may hold (the caller's memory limit).
  size_t max_points = size_t{1} << 26;
};
// The points of every frame of a ragged stream whose PCD layout has an organized shape, width x
// height (FORMAT.md "Ragged frames: HEAD and the window chunk"); 0 for frames of their own
// counts, or a stream that is not ragged.
inline size_t organized_points(const StreamContext& c) {
  return c.h.ragged && c.take.pcd ? c.take.pcd->width * c.take.pcd->height : 0;
}
// Whether every .capz reader reads this ragged stream as a fixed take (capz_source.h): a stream
// of one frame, or of frames of one organized shape.
inline bool ragged_reads_fixed(const StreamContext& c) {
  return c.h.ragged && (c.take.frames == 1 || organized_points(c) > 0);
}
// The per-frame metadata of *t (a take of F frames: TRC times and frame numbers, frame-file
// names) cut to frames [first, first + count), its first frame moved on by `first`.
void slice_frame_metadata(size_t first, size_t count, size_t F, Take* t);
// The context of a stream with features f from its decoded HEAD and its META chunk.
StreamContext read_context(const StreamHeader& h, const Chunk& meta, const StreamFeatures& f,
                           const std::string& name);

// A stream's context plus where its windows are.
struct ParsedStream : StreamContext {
  std::vector<IndexEntry> index;
  size_t first_window_offset = 0;
  size_t index_offset = 0;
  std::map<std::string, size_t> chunk_bytes;  // HEAD, META, INDX sizes with framing
  // File-level chunks between META and the first window (HASH, C3DR, TRCR, PCDR; ancillary
  // ones), each checked: type -> [offset, end).
  std::map<std::string, std::pair<size_t, size_t>> file_chunks;
};

// The chunk at `off` (read_chunk's checks), its bytes fetched from `b`; its payload pointer is
// valid until the next b.get().
Chunk chunk_at(StreamBytes& b, size_t off, const std::string& name);
// Reads the file header, HEAD, META and INDX (found from the end of the stream).
ParsedStream parse_stream(StreamBytes& b, const std::string& name);
// Throws kCorrupt unless the windows tile the stream exactly from META's end to INDX (a
// whole-stream decode checks this).
void check_tiling(const ParsedStream& ps, size_t size, const std::string& name);

}  // namespace capz
