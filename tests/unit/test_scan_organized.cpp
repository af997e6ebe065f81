// Frames of one count through the scan coder (docs/FORMAT.md "Ragged frames: HEAD and the window
// chunk": frames of one organized shape): a synthetic organized spinning sweep sequence (as
// Ouster's ROS driver writes one: HEIGHT beams x WIDTH columns, NaN where a beam has no return)
// whose sensor turns codes smaller through the scan coder, and its archive decodes to the folder's
// shape, gaps in place; a still sensor's frames keep POSW; the kind kept is the smaller of the
// two streams measured; streamed and in memory the same bytes.
#include <gtest/gtest.h>

#include <algorithm>
#include <cmath>
#include <cstdint>
#include <cstdio>
#include <cstring>
#include <filesystem>
#include <limits>
#include <memory>
#include <random>
#include <string>
#include <vector>

#include "capz/codec.h"
#include "capz/error.h"
#include "capz/io.h"
#include "capz/stream.h"
#include "capz/tool/file.h"
#include "capz/tool/original.h"
#include "codec/encoder.h"
#include "codec/scan_encoder.h"
#include "codec/stream_reader.h"
#include "coding/container.h"
#include "coding/meta.h"
#include "test_util.h"

namespace capz {
namespace {

constexpr double kPi = 3.14159265358979323846;

// A sequence of `frames` organized sweeps of H beams x W columns written as binary PCD frames
// into `dir` (WIDTH W HEIGHT H, or with `flat` WIDTH W H HEIGHT 1), NaN where a beam has no
// return. The scene is fixed: each beam's range along the azimuth is a rough room (a smooth
// wall, steps and seeded roughness); the sensor turns `turn` columns a frame (column c of frame f
// looks at azimuth (c + turn f) 2 pi / W), and `noise` m of seeded range noise is added a frame.
void write_sweeps(const std::string& dir, size_t frames, size_t H, size_t W, size_t turn,
                  double noise, bool flat) {
  std::mt19937 rng(11);
  std::uniform_real_distribution<double> u01(0, 1);
  std::vector<double> range(H * W);  // by beam and azimuth cell; NaN: no return
  for (size_t b = 0; b < H; ++b)
    for (size_t a = 0; a < W; ++a) {
      const double az = 2 * kPi * static_cast<double>(a) / static_cast<double>(W);
      double r = 6 + 2 * std::sin(3 * az) + (a / 16 % 3 == 0 ? 0.8 : 0) + 0.3 * u01(rng);
      if ((b + 2 >= H && a % 9 < 4) || u01(rng) < 0.08)
        r = std::numeric_limits<double>::quiet_NaN();
      range[b * W + a] = r;
    }
  std::normal_distribution<double> n01(0, 1);
  const std::string header =
      "VERSION 0.7\nFIELDS x y z\nSIZE 4 4 4\nTYPE F F F\nCOUNT 1 1 1\nWIDTH " +
      std::to_string(flat ? W * H : W) + "\nHEIGHT " + std::to_string(flat ? 1 : H) +
      "\nVIEWPOINT 0 0 0 1 0 0 0\nPOINTS " + std::to_string(W * H) + "\nDATA binary\n";
  for (size_t f = 0; f < frames; ++f) {
    std::vector<uint8_t> bytes(header.begin(), header.end());
    for (size_t b = 0; b < H; ++b) {
      const double el =
          (-15 + 30 * static_cast<double>(b) / static_cast<double>(H - 1)) * kPi / 180;
      for (size_t c = 0; c < W; ++c) {
        const size_t a = (c + turn * f) % W;
        const double az = 2 * kPi * static_cast<double>(a) / static_cast<double>(W);
        const double r = range[b * W + a] + noise * n01(rng);
        const float p[3] = {static_cast<float>(r * std::cos(el) * std::cos(az)),
                            static_cast<float>(r * std::cos(el) * std::sin(az)),
                            static_cast<float>(r * std::sin(el))};
        const uint8_t* q = reinterpret_cast<const uint8_t*>(p);
        bytes.insert(bytes.end(), q, q + sizeof p);
      }
    }
    char name[32];
    std::snprintf(name, sizeof name, "%04zu.pcd", f);
    write_file(dir + "/" + name, bytes, true);
  }
}

CompressOptions at_1mm() {
  CompressOptions o;
  o.max_error = 0.001;
  return o;
}

// The two streams the encoder chooses between for t: through POSW, and through the scan coder as
// frames of one organized shape.
std::vector<uint8_t> posw_stream(const Take& t, const CompressOptions& o) {
  std::vector<uint8_t> z;
  std::unique_ptr<FrameSource> s = take_frames(t);
  StreamOut out(&z);
  encode_source(*s, o, EncoderTuning(), &out, nullptr);
  return z;
}
std::vector<uint8_t> scan_stream(Take t, const CompressOptions& o) {
  t.frame_offsets.resize(t.frames + 1);
  for (size_t f = 0; f <= t.frames; ++f) t.frame_offsets[f] = f * t.points;
  t.points = 0;
  return compress_ragged(t, o, nullptr, "", true);
}

bool has_chunk(const std::vector<uint8_t>& z, const char* type) {
  return describe(z.data(), z.size()).chunk_bytes.count(type) > 0;
}

// The archive z of the folder `dir` (read as t) decodes to t's shape (a fixed take of its points,
// its PCD layout), its gaps in place and every coordinate within 1 mm; the folder written back
// has the source's WIDTH and HEIGHT and NaN at the gaps.
void expect_source_shape(const std::vector<uint8_t>& z, const Take& t, const std::string& back) {
  const StreamInfo si = describe(z.data(), z.size());
  EXPECT_FALSE(si.ragged);
  EXPECT_EQ(si.frames, t.frames);
  EXPECT_EQ(si.points, t.points);
  EXPECT_EQ(si.pcd_width, t.pcd->width);
  EXPECT_EQ(si.pcd_height, t.pcd->height);
  const Take d = decompress(z.data(), z.size());
  ASSERT_FALSE(d.ragged());
  ASSERT_EQ(d.points, t.points);
  ASSERT_EQ(d.frames, t.frames);
  ASSERT_TRUE(d.pcd);
  EXPECT_EQ(d.pcd->width, t.pcd->width);
  EXPECT_EQ(d.pcd->height, t.pcd->height);
  ASSERT_EQ(d.valid, t.valid);
  size_t gaps = 0;
  for (size_t i = 0; i < t.valid.size(); ++i) {
    gaps += !t.valid[i];
    for (size_t a = 0; t.valid[i] && a < 3; ++a)
      ASSERT_LE(std::fabs(static_cast<float>(d.xyz[3 * i + a]) - t.xyz[3 * i + a]), 0.001) << i;
  }
  EXPECT_GT(gaps, 0u);
  write_take(d, back + "/");
  const std::string text = capz_test::file_text(back + "/0001.pcd");
  EXPECT_NE(text.find("WIDTH " + std::to_string(t.pcd->width) + "\nHEIGHT " +
                      std::to_string(t.pcd->height) + "\n"),
            std::string::npos);
  const Take r = read_take(back);
  EXPECT_EQ(r.valid, t.valid);  // NaN where the source has NaN
  for (size_t i = 0; i < t.valid.size(); ++i)
    if (!t.valid[i]) {
      float x;
      const size_t p = i % t.points, f = i / t.points;
      if (f != 1) continue;
      std::memcpy(&x, text.data() + text.find("DATA binary\n") + 12 + 12 * p, 4);
      ASSERT_TRUE(std::isnan(x)) << p;
    }
}

// A turning sensor's organized frames (and the same points as unorganized frames of one count):
// through the scan coder, the smaller of the two streams (both measured when the take is at most
// the choice's prefix of 4 frames; a longer one is estimated from its prefix), the source's
// shape back; compress_stream writes the same bytes.
TEST(ScanOrganized, GivenATurningSensorThenTheScanKindIsKeptWithTheSourceShape) {
  for (const bool flat : {false, true}) {
    for (const size_t frames : {4u, 6u}) {
      SCOPED_TRACE(std::string(flat ? "unorganized" : "organized") + ", " + std::to_string(frames) +
                   " frames");
      capz_test::TempDir dir("capz_scan_organized");
      const std::string src = dir.file("src");
      std::filesystem::create_directories(src);
      write_sweeps(src, frames, 16, 256, 3, 0, flat);
      const Take t = read_take(src);
      ASSERT_FALSE(t.ragged());
      ASSERT_EQ(t.points, 16u * 256u);
      const CompressOptions o = at_1mm();
      const std::vector<uint8_t> z = compress(t, o);
      EXPECT_TRUE(has_chunk(z, "SCNW"));
      EXPECT_FALSE(has_chunk(z, "POSW"));
      if (frames <= 4) {
        const std::vector<uint8_t> posw = posw_stream(t, o), scan = scan_stream(t, o);
        EXPECT_LT(scan.size(), posw.size());
        EXPECT_EQ(z, scan.size() < posw.size() ? scan : posw);
      }
      std::unique_ptr<FrameSource> s = open_frames(src);
      compress_stream(*s, o, dir.file("s.capz"), true);
      EXPECT_EQ(read_file(dir.file("s.capz")), z);
      expect_source_shape(z, t, dir.file("back"));
    }
  }
}

// A still sensor's frames (only 0.2 mm of range noise a frame): POSW, which predicts each point
// from the frame before, codes a frame after the first in about 0.5 KB, the scan coder in about
// 1.2 KB, but its first frame in 11.6 KB against 5.3 KB. Over 24 frames POSW is the smaller and is
// kept, its bytes as they were; over 4 the scan coder's stream is; each time the smaller of the
// two measured.
TEST(ScanOrganized, GivenAStillSensorThenTheSmallerOfTheTwoIsKept) {
  for (const size_t frames : {4u, 24u}) {
    SCOPED_TRACE(std::to_string(frames) + " frames");
    capz_test::TempDir dir("capz_scan_still");
    write_sweeps(dir.path().string(), frames, 16, 256, 0, 0.0002, false);
    const Take t = read_take(dir.path().string());
    const CompressOptions o = at_1mm();
    const std::vector<uint8_t> z = compress(t, o), posw = posw_stream(t, o),
                               scan = scan_stream(t, o);
    EXPECT_EQ(z, scan.size() < posw.size() ? scan : posw);
    EXPECT_EQ(frames == 24, posw.size() < scan.size());
  }
}

// One organized frame: the smaller of its two streams (one_frame_choice), the organized layout
// back whichever is kept.
TEST(ScanOrganized, GivenOneOrganizedFrameThenTheSmallerStreamKeepsItsLayout) {
  capz_test::TempDir dir("capz_scan_one_organized");
  write_sweeps(dir.path().string(), 1, 16, 256, 0, 0, false);
  const std::string file = dir.file("0000.pcd");
  const Take t = read_take(file);
  ASSERT_EQ(t.pcd->height, 16u);
  const CompressOptions o = at_1mm();
  const std::vector<uint8_t> z = compress(t, o), posw = posw_stream(t, o), scan = scan_stream(t, o);
  EXPECT_EQ(z, scan.size() < posw.size() ? scan : posw);
  EXPECT_TRUE(has_chunk(z, "SCNW"));  // the sequence is what the test says
  std::unique_ptr<FrameSource> s = open_frames(file);
  compress_stream(*s, o, dir.file("s.capz"), true);
  EXPECT_EQ(read_file(dir.file("s.capz")), z);
  const Take d = decompress(z.data(), z.size());
  EXPECT_FALSE(d.ragged());
  EXPECT_EQ(d.pcd->width, 256u);
  EXPECT_EQ(d.pcd->height, 16u);
  EXPECT_EQ(d.valid, t.valid);
  // Lossless: the scan coder's stream too, as frames of one organized shape whose residue
  // regenerates the frame WIDTH 256 HEIGHT 16; the file back byte for byte, read back as the
  // organized take.
  CompressOptions lossless;
  lossless.lossless = true;
  std::unique_ptr<FrameSource> ls = open_frames(file);
  compress_stream(*ls, lossless, dir.file("l.capz"), true);
  const std::vector<uint8_t> l = read_file(dir.file("l.capz"));
  EXPECT_TRUE(has_chunk(l, "SCNW"));
  EXPECT_TRUE(has_chunk(l, "PCDR"));
  rebuild_original(dir.file("l.capz"), dir.file("back.pcd"), true);
  EXPECT_EQ(read_file(dir.file("back.pcd")), read_file(file));
  const Take ld = decompress(l.data(), l.size());
  EXPECT_FALSE(ld.ragged());
  EXPECT_EQ(ld.pcd->width, 256u);
  EXPECT_EQ(ld.pcd->height, 16u);
  EXPECT_EQ(ld.valid, t.valid);
}

// Lossless frames of one count that are no organized cloud and have no gap (a driver's fixed-size
// sweeps without NaN; the turning sensor's points, each frame's returns cut to the least count):
// frame 0 through the scan coder is well under POSW's, so they are no mesh, and the whole
// choice keeps the scan coder's stream (SCNW, no POSW); its files come back byte for byte, and the
// archive is under the POSW stream alone (which has no residue). They kept POSW without a trial
// before (2.2x larger on five real sweeps cut so: docs/lab/2026-11-30-lossless-fixed-count.md).
// The folder `sub` of dir (frames of one count, no gap) compressed --lossless: its stream is the
// scan coder's (SCNW, no POSW), under `ratio` times POSW's, and rebuilds every file byte for byte.
void expect_scan_coder_lossless(const capz_test::TempDir& dir, const std::string& sub,
                                double ratio) {
  const Take c = read_take(dir.file(sub));
  ASSERT_FALSE(c.ragged());
  ASSERT_EQ(c.gap_samples(), 0u);
  CompressOptions lossless;
  lossless.lossless = true;
  std::unique_ptr<FrameSource> s = open_frames(dir.file(sub));
  compress_stream(*s, lossless, dir.file("l.capz"), true);
  const std::vector<uint8_t> l = read_file(dir.file("l.capz"));
  EXPECT_TRUE(has_chunk(l, "SCNW"));
  EXPECT_FALSE(has_chunk(l, "POSW"));
  EXPECT_LT(static_cast<double>(l.size()),
            ratio * static_cast<double>(posw_stream(c, lossless).size()));
  rebuild_original(dir.file("l.capz"), dir.file("back"), true);
  for (const std::string& name : c.pcd->frame_names)
    EXPECT_EQ(read_file(dir.file("back/" + name)), read_file(dir.file(sub + "/" + name))) << name;
}

TEST(ScanOrganized, GivenLosslessSweepsOfOneCountWithoutGapsThenTheScanCoderIsTried) {
  capz_test::TempDir dir("capz_scan_fixed_nogap");
  std::filesystem::create_directories(dir.file("src"));
  write_sweeps(dir.file("src"), 5, 16, 256, 3, 0, true);
  const Take r = read_take(dir.file("src"));
  size_t least = r.frame_points(0);
  for (size_t f = 0; f < r.frames; ++f) {
    size_t n = 0;
    for (size_t p = 0; p < r.frame_points(f); ++p) n += r.is_valid(f, p);
    least = std::min(least, n);
  }
  Take t = r;
  t.frame_offsets.clear();
  t.resize(r.frames, least);
  for (size_t f = 0; f < r.frames; ++f)
    for (size_t p = 0, k = 0; p < r.frame_points(f) && k < least; ++p)
      if (r.is_valid(f, p)) {
        std::copy(r.at(f, p), r.at(f, p) + 3, t.at(f, k));
        t.valid[f * least + k++] = 1;
      }
  t.pcd->width = least;
  t.pcd->height = 1;
  WriteOptions w;
  w.pcd_encoding = "binary";
  write_pcd_folder(t, dir.file("cut"), w);
  expect_scan_coder_lossless(dir, "cut", 1.0);
}

// A non-repetitive (Livox-like) sensor's frames of one count, its no-returns written as points at
// exactly 0 0 0 (padding, not NaN: no gap in frame 0): a rosette turning from frame to frame over
// a floor and three walls, ranges on a 2 mm quantum. The scan coder's frame 0 is about POSW's,
// which alone kept POSW without a trial; the points at the origin (its gaps: FORMAT.md "Origin
// points") now send it to the trial, where the whole take codes smaller through the scan coder.
TEST(ScanOrganized, GivenLosslessPaddedFramesOfOneCountThenTheScanCoderIsTried) {
  capz_test::TempDir dir("capz_scan_padded");
  std::filesystem::create_directories(dir.file("src"));
  const size_t N = 6000;
  std::mt19937 rng(7);
  std::normal_distribution<double> n01(0, 1);
  std::uniform_real_distribution<double> u01(0, 1);
  const std::string header =
      "VERSION 0.7\nFIELDS x y z\nSIZE 4 4 4\nTYPE F F F\nCOUNT 1 1 1\nWIDTH " + std::to_string(N) +
      "\nHEIGHT 1\nVIEWPOINT 0 0 0 1 0 0 0\nPOINTS " + std::to_string(N) + "\nDATA binary\n";
  for (size_t f = 0; f < 5; ++f) {
    std::vector<uint8_t> bytes(header.begin(), header.end());
    for (size_t i = 0; i < N; ++i) {
      const double th = 2 * kPi * 1.37e-4 * static_cast<double>(i + f * N);
      const double rr = std::fabs(std::sin(7.3 * th)) * 0.6;
      const double az = rr * std::cos(th + 0.3 * f), el = rr * std::sin(th + 0.3 * f);
      const double d[3] = {std::cos(el) * std::cos(az), std::cos(el) * std::sin(az), std::sin(el)};
      double r = d[0] > 1e-3 ? 20 / d[0] : 1e9;
      if (d[2] < -1e-3) r = std::min(r, -1.5 / d[2]);
      if (std::fabs(d[1]) > 1e-3) r = std::min(r, 8 / std::fabs(d[1]));
      r = 0.002 * std::nearbyint((r + 0.01 * n01(rng)) / 0.002);
      const bool miss = r > 60 || u01(rng) < 0.08;
      float p[3];
      for (int a = 0; a < 3; ++a) p[a] = miss ? 0.0f : static_cast<float>(d[a] * r);
      const uint8_t* q = reinterpret_cast<const uint8_t*>(p);
      bytes.insert(bytes.end(), q, q + sizeof p);
    }
    char name[16];
    std::snprintf(name, sizeof name, "%04zu.pcd", f);
    write_file(dir.file("src/") + name, bytes, true);
  }
  expect_scan_coder_lossless(dir, "src", 0.9);
}

// META's layout in a stream of ragged frames (FORMAT.md "Ragged frames: HEAD and the window
// chunk"): 0 x 1 (frames of their own counts) and W x H with W > 0, H >= 1 (frames of one
// organized shape, organized_points W H; lossless too) are read; 0 x 2, 4 x 0, and W x H with
// HEAD's points-reordered bit are corrupt.
TEST(ScanOrganized, GivenARaggedStreamsLayoutThenOnlyTheTwoShapesAreRead) {
  const auto context = [](size_t width, size_t height, bool lossless, bool reordered) {
    Take m;
    m.format = Format::kPCDFolder;
    m.frames = 2;
    m.pcd = std::make_shared<PCDExtra>();
    m.pcd->encoding = "binary";
    m.pcd->fields = {{"x", 'F', 4, 1}, {"y", 'F', 4, 1}, {"z", 'F', 4, 1}};
    m.pcd->version = "0.7";
    m.pcd->width = width;
    m.pcd->height = width ? height : 1;
    // META in coding 0, its layout's width and height (varints after the version) as asked (the
    // encoder writes 0 x 1 for width 0).
    std::vector<uint8_t> meta = encode_meta_raw(m, false);
    const std::string v = "0.7";
    const auto at = std::search(meta.begin(), meta.end(), v.begin(), v.end());
    EXPECT_NE(at, meta.end());
    if (!width && at != meta.end()) at[4] = static_cast<uint8_t>(height);  // "0.7", 0, height
    std::vector<uint8_t> b;
    append_chunk(&b, "META", meta);
    StreamHeader h;
    h.frames = 2;
    h.ragged = true;
    h.lossless = lossless;
    h.points_reordered = reordered;
    StreamFeatures f;
    f.minor = 1;
    return read_context(h, read_chunk(b.data(), b.size(), 0, "meta"), f, "crafted");
  };
  EXPECT_EQ(organized_points(context(0, 1, false, false)), 0u);
  EXPECT_EQ(organized_points(context(0, 1, true, false)), 0u);
  const StreamContext c = context(8, 3, false, false);
  EXPECT_EQ(organized_points(c), 24u);
  EXPECT_EQ(c.take.pcd->width, 8u);
  EXPECT_EQ(c.take.pcd->height, 3u);
  EXPECT_EQ(organized_points(context(24, 1, false, false)), 24u);
  EXPECT_EQ(organized_points(context(8, 3, true, false)), 24u);
  for (const auto& bad : {std::vector<size_t>{0, 2, 0, 0}, std::vector<size_t>{4, 0, 0, 0},
                          std::vector<size_t>{8, 3, 0, 1}}) {
    SCOPED_TRACE(std::to_string(bad[0]) + " x " + std::to_string(bad[1]) +
                 (bad[2] ? " lossless" : "") + (bad[3] ? " reordered" : ""));
    try {
      context(bad[0], bad[1], bad[2] != 0, bad[3] != 0);
      ADD_FAILURE() << "read";
    } catch (const Error& e) {
      EXPECT_EQ(e.code(), ErrorCode::kCorrupt) << e.what();
      const std::string why = bad[2] || bad[3] ? "organized shape in a reordered"
                                               : "PCD layout " + std::to_string(bad[0]) + " x " +
                                                     std::to_string(bad[1]) + " is not";
      EXPECT_NE(std::string(e.what()).find(why), std::string::npos) << e.what();
    }
  }
}

}  // namespace
}  // namespace capz
