// read_all_frames (include/capz/stream.h): every frame of a source as one take, block by block,
// with progress after each block. For every kind of input the repository's data holds (C3D, TRC,
// PCD folders of one count, of their own counts and organized, PLY and .bin frames), the take
// open_frames gives is read_take's; a progress that throws stops the read.
#include <gtest/gtest.h>

#include <memory>
#include <stdexcept>
#include <string>
#include <utility>
#include <vector>

#include "capz/io.h"
#include "capz/stream.h"
#include "test_util.h"

namespace capz {
namespace {

std::string data(const std::string& rel) {
  return std::string(CAPZ_REPO_DATA) + "/" + rel;
}

TEST(ReadAllFrames, EveryKindOfInputGivesReadTakesTake) {
  for (const char* rel :
       {"Capture0004.c3d", "std_walking5_markers.trc", "scan_small", "organized_small",
        "lidar_small", "scan_small_ply", "scan_small_bin", "depth_small"}) {
    SCOPED_TRACE(rel);
    const std::string path = data(rel);
    std::unique_ptr<FrameSource> src = open_frames(path);
    size_t calls = 0, last = 0;
    const Take t = read_all_frames(
        *src,
        [&](size_t done, size_t total) {
          EXPECT_GT(done, last);
          EXPECT_EQ(total, src->header().frames);
          last = done;
          ++calls;
        },
        2);
    EXPECT_EQ(last, t.frames);
    EXPECT_EQ(calls, (t.frames + 1) / 2);
    capz_test::expect_same_take(t, read_take(path));
    if (t.pcd) {
      EXPECT_EQ(t.pcd->frame_names, read_take(path).pcd->frame_names);
    }
  }
}

// A source that prefers blocks of 0 frames (a user's FrameSource may) is read a frame at a time.
class NoBlockSource : public FrameSource {
 public:
  explicit NoBlockSource(std::unique_ptr<FrameSource> s) : s_(std::move(s)) {
    header_ = s_->header();
  }
  bool has_sample_words() const override { return s_->has_sample_words(); }
  void read(size_t first, size_t count, FrameBlock* out) override { s_->read(first, count, out); }
  size_t preferred_block() const override { return 0; }

 private:
  std::unique_ptr<FrameSource> s_;
};

TEST(ReadAllFrames, ASourcePreferringNoBlockIsReadAFrameAtATime) {
  NoBlockSource src(open_frames(data("scan_small")));
  size_t calls = 0;
  const Take t = read_all_frames(src, [&](size_t, size_t) { ++calls; });
  EXPECT_EQ(calls, t.frames);
  capz_test::expect_same_take(t, read_take(data("scan_small")));
}

TEST(ReadAllFrames, AProgressThatThrowsStopsTheRead) {
  std::unique_ptr<FrameSource> src = open_frames(data("scan_small"));
  ASSERT_GE(src->header().frames, 3u);
  size_t calls = 0;
  EXPECT_THROW(read_all_frames(
                   *src,
                   [&](size_t, size_t) {
                     if (++calls == 2) throw std::runtime_error("stop");
                   },
                   1),
               std::runtime_error);
  EXPECT_EQ(calls, 2u);
}

}  // namespace
}  // namespace capz
