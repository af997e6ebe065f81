// A .capz as a frame source (capz/stream.h): HEAD, META and INDX are read up front; a range of
// frames decodes the windows it touches. Part of the decoder library.
#pragma once

#include <cstdint>
#include <deque>
#include <exception>
#include <functional>
#include <future>
#include <memory>
#include <string>
#include <vector>

#include "capz/stream.h"
#include "codec/stream_reader.h"
#include "core/thread_pool.h"

namespace capz {

// What a reader gives one frame file, every .capz of one frame gives too: a stream of one ragged
// frame (the encoder codes a single unorganized frame with the scan coder when that is smaller)
// is a fixed take of one frame (header() and every block read()), its points without labels
// (as every frame file's, take.h), a PCD layout unorganized (width = its points, height 1).
// Likewise a ragged stream whose PCD layout has an organized shape W x H (FORMAT.md "Ragged
// frames: HEAD and the window chunk": every frame has W x H points; the encoder writes it for a
// take of frames of one count coded with the scan coder) is the fixed take of W x H points,
// its layout W x H, as the folder it came from reads. The one place these rules live:
// decompress(), `capz verify`, `capz compress --rm`'s read-back and every other .capz reader
// go through here. parsed() keeps the stream's own (ragged) shape.
class CapzSource : public FrameSource {
 public:
  // whole: the stream will be read whole, so check that its windows tile it exactly.
  // threads (0: all cores): above 1, windows after the one asked for are decoded ahead by that
  // many workers (docs/ARCHITECTURE.md "Threads"); what read() gives and throws is the same.
  // memory_limit (DecompressOptions::memory_limit; 0: none): bytes of decoded samples held at
  // once, the windows kept and the block read() fills; above it Error(kMemoryLimit).
  CapzSource(std::unique_ptr<StreamBytes> bytes, const std::string& name, bool whole,
             int threads = 1, uint64_t memory_limit = 0);
  ~CapzSource() override;
  bool has_sample_words() const override { return ps_.words; }
  size_t preferred_block() const override { return ps_.h.window_frames; }
  uint64_t bytes_read() const override { return bytes_->bytes_read(); }
  const ParsedStream& parsed() const { return ps_; }

  // The last window decoded is kept, so reading in window-sized steps decodes each window once;
  // a block that is exactly one window is handed over without a copy.
  void read(size_t first, size_t count, FrameBlock* out) override;
  // Called with a window's index after it is decoded (in the reading thread; not for a window
  // kept from before); an exception it throws leaves read() (DecompressOptions::progress).
  void after_window(std::function<void(size_t)> f) { after_window_ = std::move(f); }

 private:
  // A window decoded ahead: its chunks copied out of the stream (StreamBytes is not shared
  // with the workers), decoded by a worker into block.
  struct Ahead {
    size_t w = 0, base = 0, end = 0;
    std::vector<uint8_t> chunks;
    FrameBlock block;
    std::vector<int32_t> ints;
    std::exception_ptr error;  // rethrown when the window is read
    std::future<void> done;    // invalid when the chunks could not be fetched
  };
  // Decoded bytes of one frame (every per-frame array of FrameBlock).
  double frame_bytes() const;
  // Throws Error(kMemoryLimit) when `frames` frames of decoded samples exceed the limit.
  void check_memory(double frames, const char* what) const;
  void decode(size_t w);
  void hand_over(size_t w, FrameBlock* out);
  void read_ragged(size_t first, size_t count, FrameBlock* out);
  // The header_ of a ragged stream in the fixed shape (the rules above).
  void ragged_as_fixed();
  void decode_ahead(size_t w);
  void submit(size_t w);
  void drop_ahead();

  std::unique_ptr<StreamBytes> bytes_;
  std::function<void(size_t)> after_window_;
  std::string name_;
  ParsedStream ps_;
  FrameBlock win_;
  std::vector<int32_t> ints_;  // a scan window's grid integers, their memory kept (decoder.h)
  size_t cached_ = 0;
  bool have_ = false;
  bool ragged_as_fixed_ = false;  // a rule above applies
  uint64_t memory_limit_ = 0;
  size_t ahead_cap_ = 0;  // windows decoded ahead at most (threads + 1)
  size_t next_ = 0;       // the window after the last one submitted
  std::deque<std::unique_ptr<Ahead>> ahead_;
  std::vector<std::unique_ptr<Ahead>> spare_;  // their buffers are reused
  std::unique_ptr<ThreadPool> pool_;           // last: destroyed first, joining the workers
};

}  // namespace capz
