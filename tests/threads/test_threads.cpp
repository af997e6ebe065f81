// Threads inside one take (CompressOptions::threads, DecompressOptions::threads): the stream, the
// stats, the decoded take and the errors are the same for 1, 2 and 8 workers (docs/ARCHITECTURE.md
// "Threads"). The Synthetic and Repo tests are short and also run under ThreadSanitizer
// (scripts/test.sh); the Shared tests use the real data in ../shared/data.
#include <gtest/gtest.h>

#include <algorithm>
#include <cstring>
#include <filesystem>
#include <memory>
#include <stdexcept>
#include <string>
#include <vector>

#include "capz/codec.h"
#include "capz/error.h"
#include "capz/io.h"
#include "capz/stream.h"
#include "capz/tool/file.h"
#include "capz/tool/original.h"
#include "codec/transform.h"
#include "coding/container.h"
#include "coding/crc32c.h"
#include "test_util.h"
#include "unit/synthetic.h"

namespace {

using capz_test::TempDir;

const int kThreads[] = {1, 2, 8};

void expect_same_stats(const capz::CompressStats& a, const capz::CompressStats& b) {
  EXPECT_EQ(a.bytes, b.bytes);
  EXPECT_EQ(a.step, b.step);
  EXPECT_EQ(a.mode, b.mode);
  EXPECT_EQ(a.codec, b.codec);
  EXPECT_EQ(a.position_bytes, b.position_bytes);
  EXPECT_EQ(a.analog_bytes, b.analog_bytes);
  EXPECT_EQ(a.rotation_bytes, b.rotation_bytes);
  EXPECT_EQ(a.other_bytes, b.other_bytes);
  // Bit for bit: the error sums are added in window order whatever the thread count.
  EXPECT_EQ(std::memcmp(&a.error.max_abs, &b.error.max_abs, sizeof(double)), 0);
  EXPECT_EQ(std::memcmp(&a.error.rmse, &b.error.rmse, sizeof(double)), 0);
  EXPECT_EQ(std::memcmp(&a.error.kg_error, &b.error.kg_error, sizeof(double)), 0);
}

// compress() of the take with 1, 2 and 8 threads: the same bytes and stats; decompress() of them
// with 1, 2 and 8 threads: the same take. Returns the stream.
std::vector<uint8_t> check_compress(const capz::Take& take, capz::CompressOptions o,
                                    const std::string& what) {
  SCOPED_TRACE(what);
  o.threads = 1;
  capz::CompressStats s1;
  const std::vector<uint8_t> one = capz::compress(take, o, &s1);
  for (int t : kThreads) {
    if (t == 1) continue;
    o.threads = t;
    capz::CompressStats st;
    const std::vector<uint8_t> bytes = capz::compress(take, o, &st);
    EXPECT_TRUE(bytes == one) << "stream differs with " << t << " threads";
    expect_same_stats(s1, st);
  }
  capz::DecompressOptions d;
  const capz::Take back = capz::decompress(one.data(), one.size(), what, d);
  for (int t : kThreads) {
    if (t == 1) continue;
    d.threads = t;
    capz_test::expect_same_take(back, capz::decompress(one.data(), one.size(), what, d));
  }
  return one;
}

// The file streamed (compress_stream from open_frames, with HASH and residue for C3D and TRC)
// with 1, 2 and 8 threads: the same file; then read back through open_capz_frames window by
// window, and rebuilt as the original where the archive can, the same with each thread count.
void check_stream(const std::string& in, capz::CompressOptions o) {
  SCOPED_TRACE(in);
  TempDir dir("capz_threads");
  std::vector<std::vector<uint8_t>> files;
  for (int t : kThreads) {
    o.threads = t;
    const std::string out = dir.file("t" + std::to_string(t) + ".capz");
    std::unique_ptr<capz::FrameSource> src = capz::open_frames(in);
    capz::compress_stream(*src, o, out, false);
    files.push_back(capz::read_file(out));
  }
  for (size_t i = 1; i < files.size(); ++i)
    EXPECT_TRUE(files[i] == files[0]) << "stream differs with " << kThreads[i] << " threads";
  const std::string capz_path = dir.file("t1.capz");
  capz::Take first;
  for (int t : kThreads) {
    capz::DecompressOptions d;
    d.threads = t;
    std::unique_ptr<capz::FrameSource> src = capz::open_capz_frames(capz_path, d);
    capz::Take got = src->header();
    capz::FrameBlock b;
    for (size_t f = 0; f < got.frames; f += src->preferred_block()) {
      src->read(f, src->preferred_block(), &b);
      got.xyz.insert(got.xyz.end(), b.xyz.begin(), b.xyz.end());
      got.valid.insert(got.valid.end(), b.valid.begin(), b.valid.end());
      got.analog.values.insert(got.analog.values.end(), b.analog.begin(), b.analog.end());
    }
    if (t == 1)
      first = got;
    else
      capz_test::expect_same_take(first, got);
  }
  const capz::OriginalInfo info = capz::original_info(capz_path);
  if (!capz::can_rebuild(info, first.format == capz::Format::kC3D)) return;
  std::vector<uint8_t> rebuilt1;
  for (int t : kThreads) {
    const std::string out = dir.file("rebuilt" + std::to_string(t));
    capz::DecompressOptions d;
    d.threads = t;
    capz::rebuild_original(capz_path, out, false, d);
    std::vector<uint8_t> bytes;
    if (std::filesystem::is_directory(out)) {  // a PCD folder: its files' names and bytes
      std::vector<std::string> names;
      for (const auto& e : std::filesystem::directory_iterator(out))
        names.push_back(e.path().filename().string());
      std::sort(names.begin(), names.end());
      for (const std::string& n : names) {
        const std::vector<uint8_t> f = capz::read_file(out + "/" + n);
        bytes.insert(bytes.end(), n.begin(), n.end());
        bytes.insert(bytes.end(), f.begin(), f.end());
      }
    } else {
      bytes = capz::read_file(out);
    }
    if (t == 1)
      rebuilt1 = bytes;
    else
      EXPECT_TRUE(bytes == rebuilt1) << "rebuilt original differs with " << t << " threads";
  }
}

capz::Take synthetic_take(size_t frames, size_t points, double gap_rate) {
  const capz_test::Synth s = capz_test::make_synth(frames, points, 50, true, 7, gap_rate);
  capz::Take t;
  t.format = capz::Format::kTRC;
  t.source = "synthetic";
  t.units = "mm";
  t.rate = 100;
  t.frames = frames;
  t.points = points;
  t.xyz = s.xyz;
  for (double& v : t.xyz) v *= 100;
  t.valid = s.valid;
  for (size_t i = 0; i < points; ++i) t.labels.push_back("p" + std::to_string(i));
  return t;
}

TEST(ThreadsSynthetic, SameStreamAndTakeForEveryThreadCount) {
  const capz::Take t = synthetic_take(700, 20, 0.05);
  capz::CompressOptions o;
  o.window_frames = 64;  // 11 windows
  o.max_error = 0.05;
  check_compress(t, o, "bound");
  o.max_error = 0;
  o.lossless = true;
  check_compress(t, o, "lossless");
  o.lossless = false;
  o.kg_error = 0.5;
  check_compress(t, o, "kg");
  o.kg_error = 0;
  o.max_error = 0.05;
  o.codec = "ts";
  check_compress(t, o, "ts at a bound");
  o.codec = "pdct";
  check_compress(t, o, "pdct at a bound");
  o.max_error = 0;
  o.kg_error = 1;
  o.codec = "ts";
  check_compress(t, o, "ts transform output");
}

// Ragged sweeps through the scan coder, whose windows' self-checks run beside the next window's
// coding with threads: the same stream, stats and take for every count, at a bound (the fields
// kept, and dropped), with --point-order any and lossless (float32 splits).
TEST(ThreadsSynthetic, ScanWindowsTheSameForEveryThreadCount) {
  const capz::Take t =
      capz_test::with_u2_field(capz_test::synthetic_sweeps(7, 150, 37, 5, 40, 3, 0.3, 7, 23, 5),
                               "ring", [](size_t i) { return i % 2 ? 0 : i / 2 % 16; });
  capz::CompressOptions o;
  o.window_frames = 2;  // 4 windows
  o.max_error = 0.001;
  check_compress(t, o, "scan at a bound");
  o.drop_fields = true;
  check_compress(t, o, "scan without fields");
  o.drop_fields = false;
  o.any_point_order = true;
  o.max_error = 0.01;
  check_compress(t, o, "scan reordered");
  o.any_point_order = false;
  o.max_error = 0;
  o.lossless = true;
  check_compress(t, o, "scan lossless");
  o.window_frames = 3;  // three windows, the last short
  check_compress(t, o, "scan lossless, 3 windows");
}

TEST(ThreadsSynthetic, ThreadsZeroMeansAllCoresAndNegativeIsRejected) {
  const capz::Take t = synthetic_take(200, 5, 0);
  capz::CompressOptions o;
  o.window_frames = 32;
  o.max_error = 0.1;
  const std::vector<uint8_t> one = capz::compress(t, o);
  o.threads = 0;
  EXPECT_TRUE(capz::compress(t, o) == one);
  o.threads = -1;
  EXPECT_EQ(capz_test::error_of([&] { capz::compress(t, o); }), capz::ErrorCode::kInvalidParameter);
  capz::DecompressOptions d;
  d.threads = -3;
  EXPECT_EQ(capz_test::error_of([&] { capz::decompress(one.data(), one.size(), "x", d); }),
            capz::ErrorCode::kInvalidParameter);
}

// A source that breaks window `bad` on the coding pass (the second read of it): `mode` 0 gives
// rotation arrays one sample short (the worker coding the window throws kInternal), 1 throws
// kIo from read() itself (the reading thread). It also records how far reading ran ahead of
// the windows emitted (progress calls).
class BreakingSource : public capz::FrameSource {
 public:
  BreakingSource(const capz::Take& t, size_t window, size_t bad, int mode)
      : inner_(capz::take_frames(t)), window_(window), bad_(bad), mode_(mode) {
    header_ = inner_->header();
  }
  bool has_sample_words() const override { return inner_->has_sample_words(); }
  void read(size_t first, size_t count, capz::FrameBlock* out) override {
    inner_->read(first, count, out);
    const size_t w = first / window_;
    if (w == 0) ++pass_;
    if (pass_ == 2) max_ahead_ = std::max(max_ahead_, w + 1 - emitted_);
    if (pass_ != 2 || w != bad_) return;
    if (mode_ == 1) capz::fail(capz::ErrorCode::kIo, "breaking", "read fault in window 5");
    out->rotation_matrices.pop_back();
  }
  size_t emitted_ = 0, max_ahead_ = 0;

 private:
  std::unique_ptr<capz::FrameSource> inner_;
  size_t window_, bad_;
  int mode_;
  int pass_ = 0;
};

capz::Take take_with_rotations() {
  capz::Take t = synthetic_take(640, 6, 0);
  t.rotations.segments = 2;
  t.rotations.samples_per_frame = 1;
  t.rotations.matrices.resize(t.frames * 2 * 16);
  for (size_t i = 0; i < t.rotations.matrices.size(); ++i)
    t.rotations.matrices[i] = static_cast<float>(i % 17) * 0.25f;
  t.rotations.reliability.assign(t.frames * 2, 1.0f);
  return t;
}

// What encoding the breaking source throws with `threads` workers: code and message.
capz::ErrorCode encode_breaking(int threads, int mode, std::string* msg, size_t* ahead) {
  const capz::Take t = take_with_rotations();
  BreakingSource src(t, 64, 5, mode);
  capz::CompressOptions o;
  o.window_frames = 64;
  o.max_error = 0.05;
  o.threads = threads;
  o.progress = [&](size_t, size_t) { ++src.emitted_; };
  TempDir dir("capz_threads");
  const std::string out = dir.file("x.capz");
  const capz::ErrorCode code =
      capz_test::error_of([&] { capz::compress_stream(src, o, out, false); }, msg);
  EXPECT_FALSE(std::filesystem::exists(out)) << "partial output left";
  if (ahead) *ahead = src.max_ahead_;
  return code;
}

TEST(ThreadsSynthetic, WorkerErrorReachesTheCallerAsInSerial) {
  for (int mode : {0, 1}) {
    std::string m1;
    const capz::ErrorCode c1 = encode_breaking(1, mode, &m1, nullptr);
    EXPECT_NE(m1.find(mode == 0 ? "rotations do not match" : "read fault"), std::string::npos)
        << m1;
    for (int t : {2, 8}) {
      std::string mt;
      EXPECT_EQ(encode_breaking(t, mode, &mt, nullptr), c1);
      EXPECT_EQ(mt, m1) << t << " threads";
    }
  }
}

TEST(ThreadsSynthetic, WindowsInFlightAreBoundedByThreads) {
  const capz::Take t = take_with_rotations();
  for (int threads : {1, 2, 4}) {
    BreakingSource src(t, 64, 1000, 0);  // never breaks
    capz::CompressOptions o;
    o.window_frames = 64;  // 10 windows
    o.max_error = 0.05;
    o.threads = threads;
    o.progress = [&](size_t, size_t) { ++src.emitted_; };
    TempDir dir("capz_threads");
    capz::compress_stream(src, o, dir.file("x.capz"), false);
    EXPECT_EQ(src.emitted_, 10u);
    // Window w is read when at most threads windows before it are not yet emitted.
    EXPECT_LE(src.max_ahead_, static_cast<size_t>(threads) + 1) << threads << " threads";
    if (threads > 1) {
      EXPECT_GT(src.max_ahead_, 1u) << "no window was read ahead";
    }
  }
}

// synthetic_take(700, 20, 0.05) at a bound of 0.05 in windows of 64 frames: 11 windows.
std::vector<uint8_t> eleven_windows() {
  const capz::Take t = synthetic_take(700, 20, 0.05);
  capz::CompressOptions o;
  o.window_frames = 64;
  o.max_error = 0.05;
  return capz::compress(t, o);
}

// A stream with a corrupt window in the middle: decoding with 2 or 8 threads throws the
// capz::Error a serial decode throws, from the same window.
TEST(ThreadsSynthetic, CorruptWindowDecodedInParallelThrowsTheSerialError) {
  std::vector<uint8_t> bytes = eleven_windows();
  const capz::StreamInfo info = capz::describe(bytes.data(), bytes.size());
  ASSERT_EQ(info.windows, 11u);
  // The POSW chunk of window 6: found by walking the chunks after the file header.
  size_t off = capz::kFileHeaderBytes, posw = 0, n = 0;
  while (off < bytes.size()) {
    const capz::Chunk c = capz::read_chunk(bytes.data(), bytes.size(), off, "x");
    if (c.type == "POSW" && n++ == 6) {
      posw = c.offset;
      break;
    }
    off = c.end;
  }
  ASSERT_GT(posw, 0u);
  // Window 6's POSW claims to be window 7's, its CRC made right again: the window's decoder (on a
  // worker with threads) rejects it.
  const capz::Chunk c = capz::read_chunk(bytes.data(), bytes.size(), posw, "x");
  ASSERT_EQ(c.payload[0], 6);
  const size_t payload = static_cast<size_t>(c.payload - bytes.data());
  bytes[payload] = 7;
  const uint8_t* p = bytes.data() + posw;
  const uint32_t crc = capz::crc32c_update(capz::crc32c(p, 4), p + 8, c.size);
  for (int i = 0; i < 4; ++i) bytes[payload + c.size + i] = static_cast<uint8_t>(crc >> (8 * i));
  {
    std::string m1;
    capz::DecompressOptions d;
    const capz::ErrorCode c1 = capz_test::error_of(
        [&] { capz::decompress(bytes.data(), bytes.size(), "bad.capz", d); }, &m1);
    EXPECT_EQ(c1, capz::ErrorCode::kCorrupt) << m1;
    EXPECT_NE(m1.find("belongs to window 7, expected 6"), std::string::npos) << m1;
    for (int th : {2, 8}) {
      d.threads = th;
      std::string mt;
      EXPECT_EQ(capz_test::error_of(
                    [&] { capz::decompress(bytes.data(), bytes.size(), "bad.capz", d); }, &mt),
                c1);
      EXPECT_EQ(mt, m1);
    }
  }
}

// DecompressOptions::progress: called once a window in the calling thread, with the frames
// decoded so far, for every thread count; an exception it throws at the fourth window leaves
// decompress as it came, with windows decoded ahead on the workers.
TEST(ThreadsSynthetic, DecompressProgressPerWindowAndItsExceptionLeaveDecompress) {
  const std::vector<uint8_t> bytes = eleven_windows();
  for (int th : {1, 2, 8}) {
    capz::DecompressOptions d;
    d.threads = th;
    std::vector<size_t> done;
    d.progress = [&](size_t frames, size_t total) {
      EXPECT_EQ(total, 700u);
      done.push_back(frames);
    };
    EXPECT_EQ(capz::decompress(bytes.data(), bytes.size(), "p.capz", d).frames, 700u);
    ASSERT_EQ(done.size(), 11u) << th;
    EXPECT_EQ(done[0], 64u);
    EXPECT_EQ(done.back(), 700u);
    d.progress = [](size_t frames, size_t) {
      if (frames >= 4 * 64) throw std::runtime_error("stopped");
    };
    EXPECT_THROW(capz::decompress(bytes.data(), bytes.size(), "p.capz", d), std::runtime_error)
        << th;
  }
}

// The repository's samples (data/): C3D with analog and 4th words, TRC, and a scan folder one
// sweep a window (a residue chunk after each window, rebuilt from its self-check's decode),
// lossless and at a bound, streamed (HASH and residue, rebuilt originals) and in memory.
TEST(ThreadsRepo, SamplesStreamAndDecodeTheSameForEveryThreadCount) {
  const std::string d = CAPZ_REPO_DATA;
  const std::pair<const char*, size_t> samples[] = {{"admarche2.c3d", 128},
                                                    {"EB015PI.c3d", 128},
                                                    {"Capture0004.c3d", 128},
                                                    {"std_walking5_markers.trc", 128},
                                                    {"scan_small", 1}};
  for (const auto& [f, window] : samples) {
    const std::string in = d + "/" + f;
    capz::CompressOptions o;
    o.window_frames = window;
    o.lossless = true;
    check_stream(in, o);
    o.lossless = false;
    o.max_error = 0.5;
    check_stream(in, o);
    check_compress(capz::read_take(in), o, in);
  }
}

// A PCD folder with point fields (ATTR chunks, coded on the workers too), one frame a window.
TEST(ThreadsRepo, PcdFieldsTheSameForEveryThreadCount) {
  const capz::Take t = capz::read_take(std::string(CAPZ_REPO_DATA) + "/lidar_small");
  ASSERT_FALSE(t.attributes.empty());
  capz::CompressOptions o;
  o.window_frames = 1;
  o.lossless = true;
  check_compress(t, o, "lidar_small lossless");
  o.lossless = false;
  o.max_error = 0.01;
  check_compress(t, o, "lidar_small bound");
}

TEST(ThreadsShared, C3DTakesAndPcdFolder) {
  const std::string root = capz_test::shared_data_or_skip();
  if (root.empty()) return;
  for (const char* rel :
       {"c3d/btkdata/others/FunctionalLHip.c3d", "c3d/c3dorg/sample_17/128analogchannels.c3d",
        "c3d/c3dorg/sample_00/Cometa Systems/EMG Data Cometa.c3d"}) {
    const std::string in = capz_test::shared_data_or_skip(rel);
    if (in.empty()) return;
    capz::CompressOptions o;
    o.lossless = true;
    check_stream(in, o);  // default windows
    o.lossless = false;
    o.max_error = 0.1;
    o.window_frames = 256;
    check_stream(in, o);
  }
  const std::string pcd = capz_test::shared_data_or_skip("pcd/chickenCrossing");
  if (pcd.empty()) return;
  const capz::Take t = capz::read_take(pcd);
  capz::CompressOptions o;
  o.window_frames = 64;
  o.max_error = 0.002;
  check_compress(t, o, "pcd none");
  o.codec = "ts";
  check_compress(t, o, "pcd ts");
  o.codec = "none";
  o.lossless = true;
  check_stream(pcd, o);
}

}  // namespace
