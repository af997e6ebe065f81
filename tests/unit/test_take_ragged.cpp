// The ragged Take (frames of their own point count, include/capz/take.h): the helpers, blocks
// of a ragged take served and collected, measures and the promise on ragged takes, and the
// refusals of what cannot hold one yet (the encoder entry points, C3D and TRC writers).
#include <gtest/gtest.h>

#include <algorithm>
#include <filesystem>
#include <fstream>
#include <iterator>
#include <string>
#include <utility>
#include <vector>

#include "capz/codec.h"
#include "capz/error.h"
#include "capz/io.h"
#include "capz/metrics.h"
#include "capz/stream.h"
#include "capz/tool/verify.h"
#include "test_util.h"

using capz::ErrorCode;
using capz_test::TempDir;

namespace {

// Three frames of 2, 0 and 3 points; point i at (i, 10 i, 100 i), point 3 a gap; an
// intensity byte per point (i + 1).
capz::Take ragged_take() {
  capz::Take t;
  t.source = "ragged";
  t.format = capz::Format::kPCDFolder;
  t.resize_ragged({2, 0, 3});
  for (size_t i = 0; i < 5; ++i) {
    t.xyz[i * 3] = static_cast<double>(i);
    t.xyz[i * 3 + 1] = 10.0 * static_cast<double>(i);
    t.xyz[i * 3 + 2] = 100.0 * static_cast<double>(i);
    t.valid[i] = i == 3 ? 0 : 1;
  }
  capz::PointAttribute a;
  a.name = "intensity";
  a.type = 'U';
  a.size = 1;
  for (size_t i = 0; i < 5; ++i) a.data.push_back(static_cast<uint8_t>(i + 1));
  t.attributes.push_back(a);
  return t;
}

// The files of a folder, name -> bytes.
std::vector<std::pair<std::string, std::string>> folder_files(const std::string& dir) {
  std::vector<std::pair<std::string, std::string>> out;
  for (const auto& e : std::filesystem::directory_iterator(dir)) {
    std::ifstream in(e.path(), std::ios::binary);
    out.emplace_back(e.path().filename().string(),
                     std::string(std::istreambuf_iterator<char>(in), {}));
  }
  std::sort(out.begin(), out.end());
  return out;
}

template <typename F>
ErrorCode code_of(F&& f) {
  try {
    f();
  } catch (const capz::Error& e) {
    return e.code();
  }
  return static_cast<ErrorCode>(0);  // nothing thrown
}

}  // namespace

TEST(TakeRagged, GivenCountsWhenResizedThenOffsetsAndHelpersAgree) {
  const capz::Take t = ragged_take();
  ASSERT_TRUE(t.ragged());
  EXPECT_EQ(t.frames, 3u);
  EXPECT_EQ(t.points, 0u);
  EXPECT_EQ(t.frame_offsets, (std::vector<size_t>{0, 2, 2, 5}));
  EXPECT_EQ(t.total_points(), 5u);
  EXPECT_EQ(t.frame_begin(2), 2u);
  EXPECT_EQ(t.frame_points(0), 2u);
  EXPECT_EQ(t.frame_points(1), 0u);
  EXPECT_EQ(t.frame_points(2), 3u);
  EXPECT_EQ(t.at(2, 1)[0], 3.0);  // frame 2's second point is point 3 of the take
  EXPECT_FALSE(t.is_valid(2, 1));
  EXPECT_TRUE(t.is_valid(2, 2));
  EXPECT_EQ(t.gap_samples(), 1u);
  EXPECT_EQ(capz::frame_point_counts(t), (std::vector<size_t>{2, 0, 3}));
  EXPECT_EQ(t.shape_fault(), "");
}

TEST(TakeRagged, GivenFixedTakeWhenAskedThenHelpersGiveFramesTimesPoints) {
  capz::Take t;
  t.resize(4, 7);
  EXPECT_FALSE(t.ragged());
  EXPECT_EQ(t.total_points(), 28u);
  EXPECT_EQ(t.frame_begin(3), 21u);
  EXPECT_EQ(t.frame_points(2), 7u);
  EXPECT_EQ(t.shape_fault(), "");
  // resize after resize_ragged gives a fixed take again.
  t.resize_ragged({1, 2});
  t.resize(2, 2);
  EXPECT_FALSE(t.ragged());
}

TEST(TakeRagged, GivenBadShapesWhenCheckedThenFaultNamed) {
  capz::Take t = ragged_take();
  t.frame_offsets[1] = 4;  // decreasing at frame 1
  EXPECT_NE(t.shape_fault().find("decrease"), std::string::npos);
  t = ragged_take();
  t.frame_offsets.pop_back();
  EXPECT_NE(t.shape_fault(), "");
  t = ragged_take();
  t.valid.push_back(1);
  EXPECT_NE(t.shape_fault(), "");
  t = ragged_take();
  t.attributes[0].data.pop_back();
  EXPECT_NE(t.shape_fault().find("intensity"), std::string::npos);
  t = ragged_take();
  t.points = 2;
  EXPECT_NE(t.shape_fault(), "");
}

TEST(TakeRagged, GivenRaggedTakeWhenCompressedThenInvalidParameterNotACrash) {
  const capz::Take t = ragged_take();
  try {
    capz::compress(t, capz::CompressOptions());
    FAIL() << "compress accepted a ragged take";
  } catch (const capz::Error& e) {
    EXPECT_EQ(e.code(), ErrorCode::kInvalidParameter);
    EXPECT_NE(std::string(e.what()).find("ragged"), std::string::npos) << e.what();
  }
  TempDir dir;
  auto src = capz::take_frames(t);
  EXPECT_EQ(code_of([&] {
              capz::compress_stream(*src, capz::CompressOptions(), dir.file("x.capz"), false);
            }),
            ErrorCode::kInvalidParameter);
  EXPECT_FALSE(std::filesystem::exists(dir.file("x.capz")));
}

TEST(TakeRagged, GivenRaggedTakeWhenWrittenAsC3DOrTRCThenRefusedNamingTheFile) {
  capz::Take t = ragged_take();
  t.attributes.clear();
  TempDir dir;
  for (const char* name : {"x.c3d", "x.trc"}) {
    try {
      capz::write_take(t, dir.file(name));
      FAIL() << name << " accepted a ragged take";
    } catch (const capz::Error& e) {
      EXPECT_EQ(e.code(), ErrorCode::kUsage);
      EXPECT_NE(std::string(e.what()).find(name), std::string::npos) << e.what();
    }
    EXPECT_FALSE(std::filesystem::exists(dir.file(name)));
  }
  EXPECT_EQ(code_of([&] { capz::write_c3d(t, dir.file("y.c3d")); }), ErrorCode::kInvalidParameter);
  EXPECT_EQ(code_of([&] { capz::write_trc(t, dir.file("y.trc")); }), ErrorCode::kInvalidParameter);
  auto src = capz::take_frames(t);
  EXPECT_EQ(code_of([&] { capz::create_frame_sink(src->header(), false, dir.file("z.trc")); }),
            ErrorCode::kUsage);
}

TEST(TakeRagged, GivenRaggedTakeWhenReadByBlocksThenBlocksCarryRelativeOffsets) {
  const capz::Take t = ragged_take();
  auto src = capz::take_frames(t);
  EXPECT_EQ(src->header().frame_offsets, t.frame_offsets);
  EXPECT_TRUE(src->header().xyz.empty());
  capz::FrameBlock b;
  src->read(1, 5, &b);  // clipped to frames 1 and 2
  ASSERT_EQ(b.frames, 2u);
  EXPECT_EQ(b.frame_offsets, (std::vector<size_t>{0, 0, 3}));
  EXPECT_EQ(b.total_points(), 3u);
  ASSERT_EQ(b.xyz.size(), 9u);
  EXPECT_EQ(b.xyz[0], 2.0);
  EXPECT_EQ(b.valid, (std::vector<uint8_t>{1, 0, 1}));
  ASSERT_EQ(b.attributes.size(), 1u);
  EXPECT_EQ(b.attributes[0], (std::vector<uint8_t>{3, 4, 5}));
}

TEST(TakeRagged, GivenRaggedTakeWhenComparedAndPromiseCheckedThenPerFrame) {
  const capz::Take a = ragged_take();
  capz::Take b = a;
  b.xyz[4 * 3 + 2] += 0.5;  // frame 2, point 2
  const capz::ErrorStats s = capz::compare(a, b);
  EXPECT_EQ(s.samples, 4u);
  EXPECT_DOUBLE_EQ(s.max_error, 0.5);
  capz::Promise p;
  p.kind = capz::Promise::Kind::kBound;
  p.max_error = 0.25;
  capz::PromiseResult r = capz::check_promise(a, b, p);
  EXPECT_FALSE(r.holds);
  EXPECT_NE(r.why.find("frame 2, point 2"), std::string::npos) << r.why;
  p.max_error = 0.5;
  EXPECT_TRUE(capz::check_promise(a, b, p).holds) << capz::check_promise(a, b, p).why;
  // Other offsets: another shape.
  capz::Take c = a;
  c.frame_offsets = {0, 1, 2, 5};
  EXPECT_FALSE(capz::check_promise(a, c, p).holds);
  EXPECT_THROW(capz::compare(a, c), capz::Error);
}

// A folder of PCD, PLY or .bin frames written block by block (create_frame_sink, frame by frame
// into a temporary folder) holds the files write_take writes of the whole take, the coordinate
// type of the first block's frame (not a float: float64) included; a sink dropped before its
// commit leaves nothing.
TEST(TakeRagged, GivenRaggedTakeWhenSunkToFrameFolderThenWriteTakesFilesAndNothingOnFailure) {
  capz::Take t = ragged_take();
  t.xyz[0] = 0.1;  // no float32 has it: PCD and PLY coordinates become float64
  TempDir dir;
  const capz::Format formats[] = {capz::Format::kPCDFolder, capz::Format::kPLYFolder,
                                  capz::Format::kBinFolder};
  for (const capz::Format f : formats) {
    capz::WriteOptions wo;
    wo.folder_format = f;
    const std::string whole = dir.file("whole/"), sunk = dir.file("sunk/");
    capz::write_take(t, whole, wo);
    auto src = capz::take_frames(t);
    auto sink = capz::create_frame_sink(src->header(), false, sunk, wo);
    capz::copy_frames(*src, *sink, 2);
    const auto a = folder_files(whole), b = folder_files(sunk);
    EXPECT_EQ(a.size(), 3u);
    EXPECT_EQ(a, b) << static_cast<int>(f);
    std::filesystem::remove_all(whole);
    std::filesystem::remove_all(sunk);
    {
      auto part = capz::create_frame_sink(src->header(), false, sunk, wo);
      capz::FrameBlock block;
      src->read(0, 2, &block);
      part->write(block);
      EXPECT_EQ(code_of([&] { part->commit(); }), ErrorCode::kInternal);  // a frame missing
    }
    EXPECT_TRUE(std::filesystem::is_empty(dir.path())) << static_cast<int>(f);
  }
}
