// io/take_source.h: a ragged take given up to its source. A read of all its frames hands its
// arrays to the block (the take's points held once); any read after that is an internal error;
// reads of fewer frames copy. compress_ragged of a take given up writes the bytes of a copy's.
#include <gtest/gtest.h>

#include <cmath>
#include <memory>
#include <utility>
#include <vector>

#include "capz/codec.h"
#include "capz/error.h"
#include "capz/stream.h"
#include "codec/scan_encoder.h"
#include "io/take_source.h"
#include "synthetic.h"

namespace capz {
namespace {

// Three sweeps of their own counts, with NaN gaps and a ring field.
Take sweeps() {
  return capz_test::with_u2_field(capz_test::synthetic_sweeps(3, 150, 37, 5, 40, 3, 0.3, 7, 23, 5),
                                  "ring", [](size_t i) { return i % 2 ? 0 : i / 2 % 16; });
}

void expect_same_block(const FrameBlock& a, const FrameBlock& b) {
  EXPECT_EQ(a.first, b.first);
  EXPECT_EQ(a.frames, b.frames);
  EXPECT_EQ(a.frame_offsets, b.frame_offsets);
  ASSERT_EQ(a.xyz.size(), b.xyz.size());
  for (size_t i = 0; i < a.xyz.size(); ++i)  // a NaN gap matches a NaN gap
    EXPECT_EQ(std::isnan(a.xyz[i]) ? 1.0 : a.xyz[i], std::isnan(b.xyz[i]) ? 1.0 : b.xyz[i]) << i;
  EXPECT_EQ(a.valid, b.valid);
  EXPECT_EQ(a.attributes, b.attributes);
}

// Whether reading src's frames [first, first + count) throws Error(kInternal).
bool read_is_internal_error(FrameSource& src, size_t first, size_t count) {
  FrameBlock b;
  try {
    src.read(first, count, &b);
  } catch (const Error& e) {
    return e.code() == ErrorCode::kInternal;
  }
  return false;
}

TEST(TakeHandOver, GivenAllFramesReadThenTheBlockHoldsTheTakeAndNoMoreReads) {
  const Take t = sweeps();
  FrameBlock copied, handed;
  take_frames(t)->read(0, t.frames, &copied);
  std::unique_ptr<FrameSource> src = handing_take_frames(Take(t));
  src->read(0, t.frames, &handed);
  expect_same_block(copied, handed);
  EXPECT_TRUE(read_is_internal_error(*src, 0, t.frames));
  EXPECT_TRUE(read_is_internal_error(*src, 1, 1));
  EXPECT_EQ(src->header().frames, t.frames);  // the header stays
}

TEST(TakeHandOver, GivenFewerFramesReadThenCopiesAndTheTakeStays) {
  const Take t = sweeps();
  std::unique_ptr<FrameSource> src = handing_take_frames(Take(t));
  for (const auto& r : {std::make_pair(size_t{1}, size_t{2}), std::make_pair(size_t{0}, size_t{1}),
                        std::make_pair(size_t{1}, size_t{2})}) {
    FrameBlock a, b;
    take_frames(t)->read(r.first, r.second, &a);
    src->read(r.first, r.second, &b);
    expect_same_block(a, b);
  }
  FrameBlock all, handed;
  take_frames(t)->read(0, t.frames, &all);
  src->read(0, t.frames, &handed);
  expect_same_block(all, handed);
}

TEST(TakeHandOver, GivenATakeGivenUpThenCompressRaggedWritesACopysBytes) {
  const Take t = sweeps();
  for (size_t window : {size_t{0}, size_t{2}}) {  // one window of all three, then two windows
    CompressOptions o;
    o.max_error = 0.001;
    o.window_frames = window;
    const std::vector<uint8_t> copy = compress_ragged(t, o, nullptr);
    EXPECT_EQ(compress_ragged(Take(t), o, nullptr), copy) << window;
    EXPECT_EQ(decompress(copy.data(), copy.size()).frames, t.frames);
  }
}

}  // namespace
}  // namespace capz
