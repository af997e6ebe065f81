// A frame source with its original_file() hidden, for tests that compare a streamed encoding
// with compress() of the whole take.
#pragma once

#include <memory>

#include "capz/stream.h"

namespace capz_test {

// A file source with its original_file() hidden: streaming then writes no HASH or residue
// chunks (FORMAT.md 7, 14), so its bytes must be compress()'s of the whole take.
class WithoutOriginal : public capz::FrameSource {
 public:
  explicit WithoutOriginal(std::unique_ptr<capz::FrameSource> s) : s_(std::move(s)) {
    header_ = s_->header();
  }
  bool has_sample_words() const override { return s_->has_sample_words(); }
  void read(size_t first, size_t count, capz::FrameBlock* out) override {
    s_->read(first, count, out);
  }
  size_t preferred_block() const override { return s_->preferred_block(); }

 private:
  std::unique_ptr<capz::FrameSource> s_;
};

}  // namespace capz_test
