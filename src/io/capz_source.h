// A .capz as a frame source (capz/stream.h): HEAD, META and INDX are read up front; a range of
// frames decodes the windows it touches. Part of the decoder library.
#pragma once

#include <memory>
#include <string>

#include "capz/stream.h"
#include "codec/stream_reader.h"

namespace capz {

class CapzSource : public FrameSource {
 public:
  // whole: the stream will be read whole, so check that its windows tile it exactly.
  CapzSource(std::unique_ptr<StreamBytes> bytes, const std::string& name, bool whole);
  bool has_sample_words() const override { return ps_.words; }
  size_t preferred_block() const override { return ps_.h.window_frames; }
  uint64_t bytes_read() const override { return bytes_->bytes_read(); }
  const ParsedStream& parsed() const { return ps_; }

  // The last window decoded is kept, so reading in window-sized steps decodes each window once;
  // a block that is exactly one window is handed over without a copy.
  void read(size_t first, size_t count, FrameBlock* out) override;

 private:
  void decode(size_t w);

  std::unique_ptr<StreamBytes> bytes_;
  std::string name_;
  ParsedStream ps_;
  FrameBlock win_;
  size_t cached_ = 0;
  bool have_ = false;
};

}  // namespace capz
