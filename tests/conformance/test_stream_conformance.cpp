// The streaming path (include/capz/stream.h) against the whole-take path on the real files:
// the C3D frame source reads exactly what read_c3d reads, on every shared C3D file; compress_stream
// writes the same bytes as compress(); decompressing window by window into a writer gives the
// same file as decompress() + write_take(); a range read touches only the bytes of that range.
#include <gtest/gtest.h>

#include <algorithm>
#include <cstring>
#include <filesystem>
#include <string>
#include <vector>

#include "capz/codec.h"
#include "capz/error.h"
#include "capz/io.h"
#include "capz/stream.h"
#include "core/atomic_file.h"
#include "support/c3d_compare.h"
#include "support/without_original.h"
#include "test_util.h"

namespace fs = std::filesystem;
using namespace capz;

namespace {

// A take assembled from a source read in blocks of `block` frames.
Take assemble(FrameSource& src, size_t block) {
  Take t = src.header();
  const size_t F = t.frames;
  std::vector<float> res;
  std::vector<uint8_t> cam;
  FrameBlock b;
  for (size_t f = 0; f < F; f += block) {
    src.read(f, block, &b);
    EXPECT_EQ(b.first, f);
    EXPECT_EQ(b.frames, std::min(block, F - f));
    t.xyz.insert(t.xyz.end(), b.xyz.begin(), b.xyz.end());
    t.valid.insert(t.valid.end(), b.valid.begin(), b.valid.end());
    t.analog.values.insert(t.analog.values.end(), b.analog.begin(), b.analog.end());
    res.insert(res.end(), b.residual.begin(), b.residual.end());
    cam.insert(cam.end(), b.camera_mask.begin(), b.camera_mask.end());
  }
  if (t.c3d) {
    t.c3d = std::make_shared<C3DExtra>(*t.c3d);
    t.c3d->residual = res;
    t.c3d->camera_mask = cam;
  }
  return t;
}

// Every file under `root` with extension `ext` (".c3d", ".trc"), sorted.
std::vector<std::string> files_under(const std::string& root, const std::string& ext) {
  std::vector<std::string> v;
  for (const auto& e : fs::recursive_directory_iterator(root))
    if (e.is_regular_file() && e.path().extension() == ext) v.push_back(e.path().string());
  std::sort(v.begin(), v.end());
  return v;
}

// Reads `path` whole; when that throws, checks the frame source refuses it alike and returns
// false.
template <typename Whole, typename Open>
bool read_whole_or_same_refusal(const std::string& path, Whole whole_reader, Open open_source,
                                Take* out) {
  try {
    *out = whole_reader(path);
    return true;
  } catch (const Error& e) {
    try {
      open_source(path);
      ADD_FAILURE() << "the frame source opened a file the whole reader refuses: " << e.what();
    } catch (const Error& e2) {
      EXPECT_EQ(e.code(), e2.code());
      EXPECT_STREQ(e.what(), e2.what());
    }
    return false;
  }
}

TEST(StreamC3D, GivenEverySharedC3dWhenReadInBlocksThenSameAsTheWholeReader) {
  const std::string data = capz_test::shared_data_or_skip();
  if (data.empty()) return;
  const std::vector<std::string> files = files_under(data, ".c3d");
  ASSERT_GT(files.size(), 50u);
  size_t compared = 0;
  for (const std::string& path : files) {
    SCOPED_TRACE(path);
    Take whole;
    if (!read_whole_or_same_refusal(path, read_c3d, open_c3d_frames, &whole)) continue;
    std::unique_ptr<FrameSource> src = open_c3d_frames(path);
    Take parts = assemble(*src, 37);  // blocks that do not divide the frame count
    capz::testing_support::expect_same_take(whole, parts);
    capz::testing_support::expect_same_groups(whole.c3d->groups, parts.c3d->groups);
    EXPECT_EQ(whole.c3d->point_scale, parts.c3d->point_scale);
    EXPECT_EQ(whole.c3d->float_storage, parts.c3d->float_storage);
    EXPECT_EQ(whole.c3d->processor, parts.c3d->processor);
    // Same warnings: the header's, and those about frame contents after every frame was read.
    std::vector<std::string> w = parts.warnings;
    for (const std::string& fw : src->frame_warnings()) w.push_back(fw);
    std::vector<std::string> expect = whole.warnings;
    std::sort(w.begin(), w.end());
    std::sort(expect.begin(), expect.end());
    EXPECT_EQ(expect, w);
    ++compared;
  }
  EXPECT_GT(compared, 50u);
}

TEST(StreamTRC, GivenEverySharedTrcWhenReadInBlocksThenSameAsTheWholeReader) {
  const std::string data = capz_test::shared_data_or_skip();
  if (data.empty()) return;
  const std::vector<std::string> files = files_under(data, ".trc");
  ASSERT_GE(files.size(), 20u);
  size_t compared = 0;
  for (const std::string& path : files) {
    SCOPED_TRACE(path);
    Take whole;
    if (!read_whole_or_same_refusal(path, read_trc, open_trc_frames, &whole)) continue;
    std::unique_ptr<FrameSource> src = open_trc_frames(path);
    Take parts = assemble(*src, 7);
    capz_test::expect_same_samples(whole, parts);
    EXPECT_EQ(whole.labels, parts.labels);
    EXPECT_EQ(whole.units, parts.units);
    EXPECT_EQ(whole.rate, parts.rate);
    EXPECT_EQ(whole.first_frame, parts.first_frame);
    EXPECT_EQ(whole.warnings, parts.warnings);
    ASSERT_TRUE(whole.trc && parts.trc);
    EXPECT_EQ(whole.trc->times, parts.trc->times);
    EXPECT_EQ(whole.trc->frame_numbers, parts.trc->frame_numbers);
    EXPECT_EQ(whole.trc->decimals, parts.trc->decimals);
    EXPECT_EQ(whole.trc->time_decimals, parts.trc->time_decimals);
    EXPECT_EQ(whole.trc->path_file_type_line, parts.trc->path_file_type_line);
    EXPECT_EQ(whole.trc->orig_num_frames, parts.trc->orig_num_frames);
    ++compared;
  }
  EXPECT_GE(compared, 15u);
}

TEST(StreamTRC, GivenARangeThenOnlyItsRowsAreRead) {
  const std::string data = capz_test::shared_data_or_skip();
  if (data.empty()) return;
  const std::string path = data + "/trc/opensim/constraintTest.trc";
  const uint64_t size = fs::file_size(path);
  std::unique_ptr<FrameSource> src = open_trc_frames(path);
  const uint64_t opened = src->bytes_read();  // every line once per pass
  ASSERT_GT(src->header().frames, 100u);
  FrameBlock b;
  src->read(50, 10, &b);
  const uint64_t range = src->bytes_read() - opened;
  EXPECT_GT(range, 0u);
  EXPECT_LT(range, 20 * size / src->header().frames) << "read more than about its 10 rows";
  Take whole = read_trc(path);
  EXPECT_EQ(0, std::memcmp(b.xyz.data(), whole.at(50, 0), b.xyz.size() * sizeof(double)));
}

TEST(StreamC3D, GivenARangeThenOnlyItsFramesAreRead) {
  const std::string data = capz_test::shared_data_or_skip();
  if (data.empty()) return;
  const std::string path = data + "/c3d/c3dorg/sample_34/AlbertoREAL.c3d";  // 4921 frames
  const uint64_t size = fs::file_size(path);
  std::unique_ptr<FrameSource> src = open_c3d_frames(path);
  const Take& h = src->header();
  ASSERT_EQ(h.frames, 4921u);
  const uint64_t opened = src->bytes_read();
  EXPECT_LT(opened, size / 10) << "opening read more than the header and parameters";
  const size_t elem = h.c3d->float_storage ? 4 : 2;
  const size_t per_frame =
      (h.points * 4 + static_cast<size_t>(h.analog.channels * h.analog.samples_per_frame)) * elem;
  FrameBlock b;
  src->read(1000, 25, &b);
  EXPECT_EQ(src->bytes_read() - opened, 25 * per_frame);
  // The frames are the right ones.
  Take whole = read_c3d(path);
  ASSERT_EQ(b.xyz.size(), 25 * h.points * 3);
  EXPECT_EQ(0, std::memcmp(b.xyz.data(), whole.at(1000, 0), b.xyz.size() * sizeof(double)));
  // A range past the end is clipped, and reads nothing.
  const uint64_t before = src->bytes_read();
  src->read(h.frames + 5, 10, &b);
  EXPECT_EQ(b.frames, 0u);
  EXPECT_EQ(src->bytes_read(), before);
}

struct Case {
  const char* path;  // under ../shared/data
  const char* what;  // options: "lossless", "kg", "max", "ts"
  size_t window;
};

CompressOptions options_for(const Case& c, const Take& t) {
  CompressOptions o;
  o.window_frames = c.window;
  const std::string w = c.what;
  if (w == "lossless") {
    o.lossless = true;
  } else if (w == "kg") {
    o.kg_error = 0.5;
  } else {
    o.max_error = t.units.empty() ? 0.01 : parse_length("0.1mm", t.units);
    if (w == "ts") o.codec = "ts";
  }
  return o;
}

// int16 and float C3D, Intel / DEC / MIPS, with analog and gaps; TRC (read whole, served from
// memory); windows smaller than the take.
const Case kCases[] = {
    {"c3d/c3dorg/sample_34/AlbertoREAL.c3d", "max", 1024},
    {"c3d/c3dorg/sample_34/AlbertoREAL.c3d", "lossless", 500},
    {"c3d/c3dorg/sample_34/AlbertoREAL.c3d", "kg", 700},
    {"c3d/c3dorg/sample_26/Walking_Hybrid_2.c3d", "max", 100},
    {"c3d/c3dorg/sample_26/Walking_Hybrid_2.c3d", "lossless", 100},
    {"c3d/c3dorg/sample_03/gait-pig.c3d", "lossless", 50},
    {"c3d/c3dorg/sample_03/gait-pig.c3d", "max", 64},
    {"c3d/c3dorg/sample_01/Eb015si.c3d", "max", 128},
    {"c3d/c3dorg/sample_01/Eb015sr.c3d", "lossless", 128},
    {"c3d/btkdata/others/FunctionalLHip.c3d", "kg", 256},
    {"c3d/c3dorg/sample_23/Vicon_analysis.c3d", "ts", 200},
    {"trc/opensim/walk_free_01.trc", "lossless", 16},
    {"trc/opensim/dataWithNaNsWithSpaces.trc", "max", 16},
    {"pcd/horse-gallop", "max", 10},  // a PCD folder read file by file
};

TEST(StreamCodec, GivenRealTakesThenStreamingCompressWritesTheSameBytes) {
  const std::string data = capz_test::shared_data_or_skip();
  if (data.empty()) return;
  capz_test::TempDir dir("capz_stream");
  for (const Case& c : kCases) {
    const std::string path = data + "/" + c.path;
    SCOPED_TRACE(std::string(c.path) + " " + c.what + " window " + std::to_string(c.window));
    Take whole = read_take(path);
    ASSERT_GT(whole.frames, c.window) << "the case should span several windows";
    const CompressOptions o = options_for(c, whole);
    CompressStats st_whole, st_stream;
    const std::vector<uint8_t> expect = compress(whole, o, &st_whole);
    capz_test::WithoutOriginal src(open_frames(path));
    const std::string out = dir.file("s.capz");
    compress_stream(src, o, out, true, &st_stream);
    const std::vector<uint8_t> got = read_file(out);
    EXPECT_TRUE(got == expect) << "streamed " << got.size() << " bytes, whole-take "
                               << expect.size();
    EXPECT_EQ(st_whole.bytes, st_stream.bytes);
    EXPECT_EQ(st_whole.mode, st_stream.mode);
    EXPECT_EQ(st_whole.step, st_stream.step);
    EXPECT_EQ(st_whole.error.max_abs, st_stream.error.max_abs);
    EXPECT_EQ(st_whole.error.rmse, st_stream.error.rmse);
    EXPECT_EQ(st_whole.error.kg_error, st_stream.error.kg_error);
    EXPECT_EQ(st_whole.position_bytes, st_stream.position_bytes);
    EXPECT_EQ(st_whole.other_bytes, st_stream.other_bytes);
  }
}

TEST(StreamCodec, GivenRealStreamsThenWindowByWindowDecodeWritesTheSameFile) {
  const std::string data = capz_test::shared_data_or_skip();
  if (data.empty()) return;
  capz_test::TempDir dir("capz_stream");
  for (const Case& c : kCases) {
    const std::string path = data + "/" + c.path;
    SCOPED_TRACE(std::string(c.path) + " " + c.what);
    Take whole = read_take(path);
    const std::vector<uint8_t> bytes = compress(whole, options_for(c, whole));
    const std::string capz = dir.file("t.capz");
    {
      AtomicFile f(capz, true);
      f.write(bytes);
      f.commit();
    }
    if (whole.format == Format::kPCDFolder) continue;  // PCD output is written whole
    const std::string ext = whole.format == Format::kTRC ? ".trc" : ".c3d";
    const std::string a = dir.file("whole" + ext), b = dir.file("stream" + ext);
    WriteOptions wo;
    wo.overwrite = true;
    write_take(decompress(bytes.data(), bytes.size(), capz), a, wo);
    std::unique_ptr<FrameSource> src = open_capz_frames(capz);
    std::unique_ptr<FrameSink> sink =
        create_frame_sink(src->header(), src->has_sample_words(), b, wo);
    copy_frames(*src, *sink, src->preferred_block());
    EXPECT_TRUE(read_file(a) == read_file(b));
    // Read by the window: every window is read once, and little more than the stream.
    EXPECT_LE(src->bytes_read(), 2 * bytes.size());
  }
}

// A source that counts the frames read through it (a .capz source decodes each of them).
class CountingSource : public FrameSource {
 public:
  explicit CountingSource(std::unique_ptr<FrameSource> inner) : inner_(std::move(inner)) {
    edit_header() = inner_->header();
  }
  bool has_sample_words() const override { return inner_->has_sample_words(); }
  void read(size_t first, size_t count, FrameBlock* out) override {
    inner_->read(first, count, out);
    frames_read += out->frames;
  }
  size_t frames_read = 0;

 private:
  std::unique_ptr<FrameSource> inner_;
};

// The C3D writer fed block by block writes int16 frames before it has seen them all (a prescan
// would decode a .capz twice): a value that does not fit int16 at the take's scale, in the first
// block or a later one, must still give the float file the whole-take writer gives. It then
// writes every frame again as float, without a prescan: each frame is read at most twice (once
// when every value fits).
TEST(StreamCodec, GivenAnInt16TakeWithAnOutOfRangeValueThenTheStreamedC3DFallsBackToFloat) {
  const std::string data = capz_test::shared_data_or_skip();
  if (data.empty()) return;
  capz_test::TempDir dir("capz_stream");
  const Take orig = read_take(data + "/c3d/c3dorg/sample_34/AlbertoREAL.c3d");
  ASSERT_TRUE(orig.c3d && !orig.c3d->float_storage);
  WriteOptions wo;
  wo.overwrite = true;
  // Writes t whole and streamed; true when both files are the same. *float_out: the storage.
  size_t frames_read = 0;
  auto same_both_ways = [&](const Take& t, bool* float_out) {
    const std::string a = dir.file("whole.c3d"), b = dir.file("stream.c3d");
    write_take(t, a, wo);
    CountingSource src(take_frames(t));
    std::unique_ptr<FrameSink> sink = create_frame_sink(t, true, b, wo);
    copy_frames(src, *sink, 1024);
    frames_read = src.frames_read;
    *float_out = read_take(b).c3d->float_storage;
    return read_file(a) == read_file(b);
  };
  bool is_float = false;
  for (size_t frame : {size_t{0}, size_t{3000}, orig.frames - 1}) {
    SCOPED_TRACE("out-of-range value in frame " + std::to_string(frame));
    Take t = orig;
    const size_t i = frame * t.points + 5;
    t.valid[i] = 1;
    t.xyz[3 * i + 1] = 40000.0 * t.c3d->point_scale;  // beyond int16 at the file's scale
    EXPECT_TRUE(same_both_ways(t, &is_float));
    EXPECT_TRUE(is_float);
    EXPECT_GT(frames_read, t.frames);  // the blocks up to the failing one, then all again
    EXPECT_LE(frames_read, 2 * t.frames);
  }
  // And every value in range: int16, the same file as the whole-take writer's.
  EXPECT_TRUE(same_both_ways(orig, &is_float));
  EXPECT_FALSE(is_float);
  EXPECT_EQ(frames_read, orig.frames);
}

TEST(StreamCodec, GivenACapzThenARangeReadsOnlyTheWindowsItTouches) {
  const std::string data = capz_test::shared_data_or_skip();
  if (data.empty()) return;
  capz_test::TempDir dir("capz_stream");
  const std::string path = data + "/c3d/c3dorg/sample_34/AlbertoREAL.c3d";
  Take whole = read_take(path);
  CompressOptions o;
  o.max_error = 0.1;
  o.window_frames = 100;  // 50 windows
  const std::vector<uint8_t> bytes = compress(whole, o);
  const std::string capz = dir.file("t.capz");
  {
    AtomicFile f(capz, true);
    f.write(bytes);
    f.commit();
  }
  std::unique_ptr<FrameSource> src = open_capz_frames(capz);
  const uint64_t opened = src->bytes_read();
  FrameBlock b;
  src->read(2010, 50, &b);  // inside window 20
  const uint64_t one = src->bytes_read() - opened;
  EXPECT_GT(one, 0u);
  EXPECT_LT(one, bytes.size() / 20) << "a range in one window read more than about one window";
  Take ref = decompress_frames(bytes.data(), bytes.size(), 2010, 50);
  EXPECT_EQ(ref.valid, b.valid);
  EXPECT_EQ(0, std::memcmp(ref.xyz.data(), b.xyz.data(), b.xyz.size() * sizeof(double)));
}

}  // namespace
