// Resource limits: a small hostile file whose counts claim gigabytes is refused (capz::Error) or
// read as what it really holds, without the reader asking for more than a small budget of heap.
// Every case runs inside an AllocScope (alloc_counter.h): a single request above 256 MB is
// refused (bad_alloc) and fails the test; the peak heap use must stay under kBudget.
#include <gtest/gtest.h>

#include <algorithm>
#include <cstdio>
#include <filesystem>
#include <fstream>
#include <functional>
#include <iterator>
#include <memory>
#include <string>
#include <vector>

#include "alloc_counter.h"
#include "capz/codec.h"
#include "capz/error.h"
#include "capz/io.h"
#include "capz/stream.h"
#include "coding/container.h"
#include "test_util.h"

namespace fs = std::filesystem;
using capz_test::AllocReport;
using capz_test::AllocScope;

namespace {

// A 1 KB input may cost a few MB while being read (a Take holds 25 bytes per sample); not more.
constexpr int64_t kBudget = int64_t{64} << 20;

struct Outcome {
  bool threw_error = false;
  capz::ErrorCode code = capz::ErrorCode::kInternal;  // when threw_error
  bool threw_bad_alloc = false;
  std::string message;
  AllocReport alloc;
};

Outcome run_bounded(const std::function<void()>& read) {
  Outcome o;
  {
    AllocScope scope;
    try {
      read();
    } catch (const capz::Error& e) {
      o.threw_error = true;
      o.code = e.code();
      o.message = e.what();
    } catch (const std::bad_alloc&) {
      o.threw_bad_alloc = true;
    }
    o.alloc = scope.report();
  }
  return o;
}

void expect_bounded(const Outcome& o, const std::string& what) {
  EXPECT_FALSE(o.threw_bad_alloc) << what << ": ran out of memory";
  EXPECT_EQ(o.alloc.refused_request, 0u)
      << what << ": asked for " << o.alloc.refused_request << " bytes in one request";
  EXPECT_LT(o.alloc.peak_bytes, kBudget) << what << ": peak heap " << o.alloc.peak_bytes;
}

std::vector<uint8_t> bytes_of(const std::string& s) {
  return std::vector<uint8_t>(s.begin(), s.end());
}

void write_file(const fs::path& p, const std::string& s) {
  std::ofstream o(p, std::ios::binary);
  o << s;
}

// The streaming path `capz compress` and `decompress` use (include/capz/stream.h): open the
// file as a FrameSource and read every frame, a block at a time.
void read_all_frames(const std::string& path) {
  std::unique_ptr<capz::FrameSource> src = capz::open_frames(path);
  const size_t block = std::max<size_t>(1, src->preferred_block());
  capz::FrameBlock b;
  for (size_t f = 0; f < src->header().frames; f += block) src->read(f, block, &b);
}

}  // namespace

// The allocation counter itself: it must see a large request and refuse a huge one, or every
// other test here could pass without measuring anything.
TEST(ResourceLimits, CounterSeesAndRefusesLargeRequests) {
  Outcome o = run_bounded([] {
    std::vector<uint8_t> v(size_t{8} << 20);
    v[123] = 1;
  });
  EXPECT_GE(o.alloc.peak_bytes, int64_t{8} << 20);
  EXPECT_GE(o.alloc.largest_request, size_t{8} << 20);
  EXPECT_EQ(o.alloc.refused_request, 0u);
  Outcome huge = run_bounded([] { std::vector<double> v(size_t{1} << 30); });
  EXPECT_TRUE(huge.threw_bad_alloc);
  EXPECT_EQ(huge.alloc.refused_request, (size_t{1} << 30) * sizeof(double));
}

TEST(ResourceLimits, TrcHeaderCountsClaimingBillionsAreOnlyWarnings) {
  const std::string trc =
      "PathFileType\t4\t(X/Y/Z)\thostile.trc\n"
      "DataRate\tCameraRate\tNumFrames\tNumMarkers\tUnits\tOrigDataRate\tOrigDataStartFrame\t"
      "OrigNumFrames\n"
      "100\t100\t2000000000\t50000000\tmm\t100\t1\t2000000000\n"
      "Frame#\tTime\tA\t\t\tB\t\t\n"
      "\t\tX1\tY1\tZ1\tX2\tY2\tZ2\n"
      "1\t0\t1\t2\t3\t4\t5\t6\n"
      "2\t0.01\t1\t2\t3\t4\t5\t6\n";
  ASSERT_LT(trc.size(), 1024u);
  std::vector<uint8_t> b = bytes_of(trc);
  capz::Take t;
  Outcome o = run_bounded([&] { t = capz::read_trc_bytes(b.data(), b.size(), "hostile.trc"); });
  expect_bounded(o, "TRC header counts");
  ASSERT_FALSE(o.threw_error) << o.message;
  EXPECT_EQ(t.frames, 2u);
  EXPECT_EQ(t.points, 2u);
  capz_test::TempDir dir("capz_limits");
  write_file(dir.path() / "hostile.trc", trc);
  Outcome so = run_bounded([&] { read_all_frames((dir.path() / "hostile.trc").string()); });
  expect_bounded(so, "TRC header counts, streamed");
  EXPECT_FALSE(so.threw_error) << so.message;
}

TEST(ResourceLimits, TrcManyShortRowsTimesAWideRowIsBounded) {
  // One row reaching marker 300 through empty fields, then ~900 one-field rows: rows x markers
  // samples from one kilobyte. The reader must refuse or stay within the budget.
  std::string trc =
      "PathFileType\t4\t(X/Y/"
      "Z)\th.trc\nDataRate\tNumFrames\tNumMarkers\n100\t1\t1\nFrame#\tTime\tA\n\n";
  trc += "1\t0" + std::string(900, '\t') + "1\n";
  while (trc.size() < 4000) trc += "1\n";
  std::vector<uint8_t> b = bytes_of(trc);
  Outcome o = run_bounded([&] { capz::read_trc_bytes(b.data(), b.size(), "wide.trc"); });
  expect_bounded(o, "TRC wide x long");
  capz_test::TempDir dir("capz_limits");
  write_file(dir.path() / "wide.trc", trc);
  Outcome so = run_bounded([&] { read_all_frames((dir.path() / "wide.trc").string()); });
  expect_bounded(so, "TRC wide x long, streamed");
}

// PCD headers: each lie in its own one-file folder.
TEST(ResourceLimits, PcdHeadersClaimingBillionsOfPointsAreRefused) {
  const std::string head = "VERSION 0.7\nFIELDS x y z\nSIZE 4 4 4\nTYPE F F F\n";
  const std::vector<std::pair<std::string, std::string>> cases = {
      {"binary body", head +
                          "COUNT 1 1 1\nWIDTH 1000000000\nHEIGHT 1\nPOINTS 1000000000\n"
                          "DATA binary\n" +
                          std::string(120, '\0')},
      {"zero COUNT", head +
                         "COUNT 0 0 0\nWIDTH 1000000000\nHEIGHT 1\nPOINTS 1000000000\n"
                         "DATA binary\n" +
                         std::string(120, '\0')},
      {"width x height", head +
                             "COUNT 1 1 1\nWIDTH 1000000\nHEIGHT 1000000\n"
                             "DATA binary\n" +
                             std::string(120, '\0')},
      {"ascii body", head + "COUNT 1 1 1\nWIDTH 4000000000\nHEIGHT 1\nDATA ascii\n1 2 3\n"},
      {"compressed body",
       head + "COUNT 1 1 1\nWIDTH 100000000\nHEIGHT 1\nDATA binary_compressed\n" +
           std::string("\x10\x00\x00\x00\x00\x8c\x86\x47", 8) + std::string(16, 'A')},
      {"huge COUNT",
       "VERSION 0.7\nFIELDS x y z n\nSIZE 4 4 4 4\nTYPE F F F F\n"
       "COUNT 1 1 1 1048576\nWIDTH 1\nHEIGHT 1\nDATA ascii\n1 2 3 4\n"},
  };
  for (const auto& c : cases) {
    capz_test::TempDir dir("capz_limits");
    write_file(dir.path() / "frame_0.pcd", c.second);
    Outcome o = run_bounded([&] { capz::read_pcd_folder(dir.path().string()); });
    expect_bounded(o, "PCD " + c.first);
    EXPECT_TRUE(o.threw_error) << "PCD " << c.first << " was accepted";
    std::printf("PCD %s: %s (peak %lld bytes)\n", c.first.c_str(), o.message.c_str(),
                static_cast<long long>(o.alloc.peak_bytes));
  }
}

// Hand-built C3D files (tests/fuzz/corpus/read_c3d/, made by a script from the C3D layout):
// 1424 bytes whose header, POINT:USED/FRAMES and TRIAL:ACTUAL_END_FIELD claim up to 65535 points
// and 4 billion frames.
TEST(ResourceLimits, C3dCountsClaimingBillionsAreClampedToTheData) {
  const std::string dir = std::string(CAPZ_TEST_DIR) + "/fuzz/corpus/read_c3d/";
  for (const char* file :
       {"hostile-65535-points-65535-frames.c3d", "crash-zero-points-4g-frames.c3d"}) {
    std::vector<uint8_t> b;
    {
      std::ifstream in(dir + file, std::ios::binary);
      ASSERT_TRUE(in) << dir + file;
      b.assign(std::istreambuf_iterator<char>(in), std::istreambuf_iterator<char>());
    }
    ASSERT_LT(b.size(), 2048u);
    capz::Take t;
    Outcome o = run_bounded([&] { t = capz::read_c3d_bytes(b.data(), b.size(), file); });
    expect_bounded(o, file);
    if (!o.threw_error) {
      // What the file really holds: 400 bytes of data cannot be one frame of 65535 points, and
      // frames of nothing are not kept (4 billion of them would stall every later stage).
      EXPECT_EQ(t.frames, 0u) << file;
      EXPECT_FALSE(t.warnings.empty()) << file;
    }
    Outcome so = run_bounded([&] { read_all_frames(dir + file); });
    expect_bounded(so, std::string(file) + ", streamed");
  }
}

// The decoder: a valid small stream whose HEAD (CRC made valid again) claims 2^40 frames of
// 2^31 points, or analog channels by the billion, is refused without allocating for the claim.
TEST(ResourceLimits, CapzHeaderCountsClaimingBillionsAreRefused) {
  capz::Take t;
  t.format = capz::Format::kTRC;
  t.resize(4, 2);
  t.units = "mm";
  t.rate = 100;
  for (size_t i = 0; i < 8; ++i) {
    t.valid[i] = 1;
    t.xyz[i * 3] = static_cast<double>(i);
  }
  capz::CompressOptions co;
  co.max_error = 0.01;
  const std::vector<uint8_t> good = capz::compress(t, co);
  // A take without points and analog channels, whose TRC Time and Frame# columns META stores as
  // start + step (sized by HEAD's frame count, not by the file): found by fuzz_parse_container,
  // a 1 KB stream claiming 2^30 frames in one window of 2^30 frames made the decoder allocate
  // 8 GB for the Frame# column.
  capz::Take e;
  e.format = capz::Format::kTRC;
  e.resize(4, 0);
  e.rate = 100;
  e.units = "mm";
  e.trc = std::make_shared<capz::TRCExtra>();
  e.trc->times = {0, 0.01, 0.02, 0.03};
  e.trc->frame_numbers = {1, 2, 3, 4};
  const std::vector<uint8_t> empty = capz::compress(e, co);
  // Rebuilds the stream `good` (or `empty`) with HEAD replaced by `edit(header)`.
  auto with_head = [&](const std::function<void(capz::StreamHeader*)>& edit,
                       const std::vector<uint8_t>& good) {
    std::vector<uint8_t> out;
    capz::write_file_header(&out);
    size_t off = capz::kFileHeaderBytes;
    while (off < good.size()) {
      capz::Chunk c = capz::read_chunk(good.data(), good.size(), off, "good");
      std::vector<uint8_t> payload(c.payload, c.payload + c.size);
      if (c.type == "HEAD") {
        capz::StreamHeader h = capz::decode_header(c, "good");
        edit(&h);
        payload = capz::encode_header(h);
      }
      capz::append_chunk(&out, c.type.c_str(), payload);
      off = c.end;
    }
    return out;
  };
  const std::vector<std::pair<std::string, std::function<void(capz::StreamHeader*)>>> cases = {
      {"2^40 frames", [](capz::StreamHeader* h) { h->frames = uint64_t{1} << 40; }},
      {"2^31 points", [](capz::StreamHeader* h) { h->points = 1u << 31; }},
      {"both",
       [](capz::StreamHeader* h) {
         h->frames = uint64_t{1} << 40;
         h->points = 0xFFFFFFFFu;
       }},
      {"huge window",
       [](capz::StreamHeader* h) {
         h->frames = uint64_t{1} << 40;
         h->window_frames = 0xFFFFFFFFu;
       }},
      {"analog",
       [](capz::StreamHeader* h) {
         h->analog_channels = 1u << 30;
         h->analog_samples_per_frame = 1u << 30;
       }},
      {"no points, 2^30 frames in one window",
       [](capz::StreamHeader* h) {
         h->frames = uint64_t{1} << 30;
         h->window_frames = 1u << 30;
       }},
      {"no points, 2^30 frames in windows of 8192",
       [](capz::StreamHeader* h) {
         h->frames = uint64_t{1} << 30;
         h->window_frames = 8192;
       }},
  };
  for (const auto& c : cases) {
    std::vector<uint8_t> s =
        with_head(c.second, c.first.compare(0, 9, "no points") == 0 ? empty : good);
    ASSERT_LT(s.size(), 2048u);
    Outcome o = run_bounded([&] { capz::decompress(s.data(), s.size(), "hostile.capz"); });
    expect_bounded(o, "capz " + c.first);
    EXPECT_TRUE(o.threw_error) << "capz " << c.first << " was accepted";
    Outcome d = run_bounded([&] { capz::describe(s.data(), s.size(), "hostile.capz"); });
    expect_bounded(d, "describe " + c.first);
    capz_test::TempDir dir("capz_limits");
    const fs::path path = dir.path() / "hostile.capz";
    write_file(path, std::string(s.begin(), s.end()));
    Outcome so = run_bounded([&] { read_all_frames(path.string()); });
    expect_bounded(so, "capz streamed " + c.first);
    EXPECT_TRUE(so.threw_error) << "capz streamed " << c.first << " was accepted";
  }
}

// A valid stream can ask for much more memory than its size: a constant analog channel codes in
// a few bytes a window whatever its length. Here 2048 frames of 64 x 64 constant analog values
// (8 Mi values, 64 MiB of doubles) code into a few KB. The encoder keeps each window within
// kMaxWindowAnalogValues (so 1024 frames, not the 8192 a take without points would get), and the
// decoder refuses, before allocating, to hold more than its memory limit: the whole take in
// memory, a window and those decoded ahead when streaming. A frame range within the limit still
// decodes.
TEST(ResourceLimits, CapzStreamAskingMoreThanTheMemoryLimitIsRefusedBeforeAllocating) {
  capz::Take t;
  t.format = capz::Format::kC3D;
  t.resize(2048, 0);
  t.rate = 100;
  t.units = "mm";
  t.analog.channels = 64;
  t.analog.samples_per_frame = 64;
  t.analog.rate = 6400;
  t.analog.labels.assign(64, "A");
  t.analog.values.assign(size_t{2048} * 64 * 64, 0.25);
  for (size_t i = 0; i < t.analog.values.size(); i += 64) t.analog.values[i] = 1.0;  // channel 0
  capz::CompressOptions co;
  co.lossless = true;
  const std::vector<uint8_t> s = capz::compress(t, co);
  t = capz::Take();
  ASSERT_LT(s.size(), size_t{1} << 16);
  const capz::StreamInfo si = capz::describe(s.data(), s.size(), "constant.capz");
  EXPECT_EQ(si.window_frames, capz::kMaxWindowAnalogValues / (64 * 64));  // 1024
  EXPECT_EQ(si.windows, 2u);

  capz::DecompressOptions small;
  small.memory_limit = uint64_t{24} << 20;  // below one window's 32 MiB
  Outcome o = run_bounded([&] { capz::decompress(s.data(), s.size(), "constant.capz", small); });
  expect_bounded(o, "decompress under 24 MiB");
  ASSERT_TRUE(o.threw_error);
  EXPECT_NE(o.message.find("constant.capz"), std::string::npos) << o.message;
  EXPECT_NE(o.message.find("needs 32 MiB of samples, above the memory limit of 24 MiB"),
            std::string::npos)
      << o.message;
  EXPECT_EQ(o.code, capz::ErrorCode::kMemoryLimit);

  capz_test::TempDir dir("capz_memlimit");
  const fs::path path = dir.path() / "constant.capz";
  write_file(path, std::string(s.begin(), s.end()));
  // Streaming: one window (32 MiB) fits 48 MiB; with 3 threads, 4 windows decoded ahead do not.
  capz::DecompressOptions stream = small;
  stream.memory_limit = uint64_t{48} << 20;
  stream.threads = 3;
  Outcome so = run_bounded([&] { capz::open_capz_frames(path.string(), stream); });
  expect_bounded(so, "streamed with 3 threads under 48 MiB");
  EXPECT_TRUE(so.threw_error);
  stream.threads = 1;
  std::unique_ptr<capz::FrameSource> src = capz::open_capz_frames(path.string(), stream);
  capz::FrameBlock b;
  src->read(1024, 1024, &b);  // exactly a window: handed over
  ASSERT_EQ(b.analog.size(), size_t{1024} * 64 * 64);
  EXPECT_EQ(b.analog[0], 1.0);
  EXPECT_EQ(b.analog[1], 0.25);
  // The whole take (64 MiB) is above 48 MiB; 100 frames of it are not.
  EXPECT_THROW(capz::decompress(s.data(), s.size(), "constant.capz", stream), capz::Error);
  const capz::Take part = capz::decompress_frames(s.data(), s.size(), 1000, 100, "", stream);
  EXPECT_EQ(part.frames, 100u);
  EXPECT_EQ(part.analog.values.size(), size_t{100} * 64 * 64);
  // No limit, and the default (4 GiB): the whole take.
  stream.memory_limit = 0;
  EXPECT_EQ(capz::decompress(s.data(), s.size(), "", stream).analog.values.size(),
            size_t{2048} * 64 * 64);
  EXPECT_EQ(capz::decompress(s.data(), s.size()).analog.values.size(), size_t{2048} * 64 * 64);
}

// The default limit: 4 GiB, or 1024 bytes per archive byte when more (a large archive of big
// point clouds needs big windows; a small file gets 4 GiB at most). An explicit limit, and 0 (no
// limit), are taken as given.
TEST(ResourceLimits, DefaultMemoryLimitGrowsWithTheArchiveOnlyPast4MiB) {
  const uint64_t auto_limit = capz::DecompressOptions().memory_limit;
  EXPECT_EQ(auto_limit, capz::kAutoMemoryLimit);
  EXPECT_EQ(capz::effective_memory_limit(auto_limit, 0), uint64_t{4} << 30);
  EXPECT_EQ(capz::effective_memory_limit(auto_limit, 6000), uint64_t{4} << 30);
  EXPECT_EQ(capz::effective_memory_limit(auto_limit, uint64_t{4} << 20), uint64_t{4} << 30);
  EXPECT_EQ(capz::effective_memory_limit(auto_limit, uint64_t{10} << 20), uint64_t{10} << 30);
  EXPECT_EQ(capz::effective_memory_limit(auto_limit, uint64_t{1} << 62), ~uint64_t{0} - 1);
  EXPECT_EQ(capz::effective_memory_limit(0, uint64_t{10} << 20), 0u);
  EXPECT_EQ(capz::effective_memory_limit(12345, uint64_t{10} << 20), 12345u);
}
