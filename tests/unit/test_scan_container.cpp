// Ragged takes through the container (docs/FORMAT.md "Scans (format 1.1)"): compress and
// decompress round trips at 1 mm and 1 cm, the SCNW chunk's checks, and what is refused.
#include <gtest/gtest.h>
#include <unistd.h>

#include <cmath>
#include <cstdlib>
#include <cstring>
#include <filesystem>
#include <limits>
#include <random>
#include <string>
#include <utility>

#include "capz/codec.h"
#include "capz/error.h"
#include "capz/io.h"
#include "capz/stream.h"
#include "capz/tool/file.h"
#include "capz/tool/verify.h"
#include "coding/bytes.h"
#include "coding/crc32c.h"
#include "synthetic.h"
#include "test_util.h"

namespace capz {
namespace {

// A synthetic 16-beam spinning sweep per frame, each frame its own point count, with NaN gaps.
Take synthetic_scan(size_t frames) {
  return capz_test::synthetic_sweeps(frames, 150, 37, 5, 40, 3, 0.3, 7, 23, 5);
}

// Every coordinate within the bound (also as the float32 a PCD writer stores), gaps in place,
// counts per frame equal.
void expect_within(const Take& src, const Take& d, double bound) {
  ASSERT_TRUE(d.ragged());
  ASSERT_EQ(d.frames, src.frames);
  for (size_t f = 0; f < src.frames; ++f) ASSERT_EQ(d.frame_points(f), src.frame_points(f));
  ASSERT_EQ(d.valid, src.valid);
  ASSERT_EQ(d.xyz.size(), src.xyz.size());
  double worst = 0;
  for (size_t i = 0; i < src.valid.size(); ++i)
    if (src.valid[i])
      for (size_t a = 0; a < 3; ++a) {
        const double x = src.xyz[3 * i + a];
        const double y = static_cast<float>(d.xyz[3 * i + a]);
        worst = std::max(worst, std::fabs(x - y));
      }
  EXPECT_LE(worst, bound);
  EXPECT_GT(worst, 0.0);  // lossy: the grid moved something
}

CompressOptions at(double bound) {
  CompressOptions o;
  o.max_error = bound;
  return o;
}

TEST(ScanContainer, RoundTripsAtOneMillimetreAndOneCentimetre) {
  const Take t = synthetic_scan(5);
  for (double bound : {0.001, 0.01}) {
    CompressOptions o = at(bound);
    o.window_frames = 2;  // three windows, the last short
    CompressStats st;
    const std::vector<uint8_t> z = compress(t, o, &st);
    EXPECT_LT(st.bpvf, 32.0);
    expect_within(t, decompress(z.data(), z.size()), bound);
    const Take mid = decompress_frames(z.data(), z.size(), 1, 3);
    ASSERT_EQ(mid.frames, 3u);
    for (size_t f = 0; f < 3; ++f) EXPECT_EQ(mid.frame_points(f), t.frame_points(f + 1));
    EXPECT_EQ(mid.pcd->frame_names.front(), "f1.pcd");
  }
}

// Ranges across windows read into one block again and again (its arrays sized, not zeroed, for
// each range) give what a fresh block is given: larger, smaller and one-frame ranges, with a
// point field.
TEST(ScanContainer, RangesReadIntoAReusedBlockAreFreshBlocks) {
  Take t = synthetic_scan(7);
  PointAttribute ring{"ring", 'U', 2, 1, {}};
  ring.data.resize(t.total_points() * 2);
  for (size_t i = 0; i < ring.data.size(); ++i) ring.data[i] = static_cast<uint8_t>(i % 16);
  t.attributes.push_back(ring);
  t.pcd->fields = {PCDField{"x", 'F', 4, 1}, PCDField{"y", 'F', 4, 1}, PCDField{"z", 'F', 4, 1},
                   PCDField{"ring", 'U', 2, 1}};
  CompressOptions o = at(0.001);
  o.window_frames = 2;
  const std::vector<uint8_t> z = compress(t, o);
  const std::string path = (std::filesystem::temp_directory_path() /
                            ("capz_ranges_" + std::to_string(::getpid()) + ".capz"))
                               .string();
  write_file(path, z, true);
  std::unique_ptr<FrameSource> src = open_capz_frames(path);
  FrameBlock reused;
  for (const auto& r : {std::make_pair(0, 7), std::make_pair(3, 3), std::make_pair(1, 1),
                        std::make_pair(2, 5), std::make_pair(5, 1), std::make_pair(1, 4)}) {
    src->read(static_cast<size_t>(r.first), static_cast<size_t>(r.second), &reused);
    FrameBlock fresh;
    open_capz_frames(path)->read(static_cast<size_t>(r.first), static_cast<size_t>(r.second),
                                 &fresh);
    EXPECT_EQ(reused.first, fresh.first);
    EXPECT_EQ(reused.frames, fresh.frames);
    EXPECT_EQ(reused.frame_offsets, fresh.frame_offsets);
    EXPECT_EQ(reused.xyz, fresh.xyz);
    EXPECT_EQ(reused.valid, fresh.valid);
    EXPECT_EQ(reused.attributes, fresh.attributes);
    EXPECT_EQ(fresh.frame_offsets.back(), t.frame_offsets[static_cast<size_t>(r.first + r.second)] -
                                              t.frame_offsets[static_cast<size_t>(r.first)]);
  }
  src.reset();
  std::filesystem::remove(path);
}

TEST(ScanContainer, RefusesWhatIsNotCodedYet) {
  Take t = synthetic_scan(2);
  PointAttribute a;
  a.name = "intensity";
  a.data.assign(t.total_points() * 4, 1);
  t.attributes.push_back(a);
  const std::vector<uint8_t> kept = compress(t, at(0.01));  // fields kept (test_scan_fields)
  EXPECT_EQ(decompress(kept.data(), kept.size()).attributes.at(0).data, a.data);
  CompressOptions drop = at(0.01);
  drop.drop_fields = true;
  const std::vector<uint8_t> z = compress(t, drop);
  EXPECT_TRUE(decompress(z.data(), z.size()).attributes.empty());
}

// The SCNW chunk of window 0 re-framed with its total changed (CRC recomputed): corrupt.
TEST(ScanContainer, CountsDisagreeingWithThePayloadAreCorrupt) {
  const Take t = synthetic_scan(2);
  std::vector<uint8_t> z = compress(t, at(0.01));
  size_t off = 0;
  for (size_t i = 0; i + 4 <= z.size(); ++i)
    if (std::memcmp(&z[i], "SCNW", 4) == 0) {
      off = i;
      break;
    }
  ASSERT_GT(off, 0u);
  const uint32_t len = load_le32(&z[off + 4]);
  // payload: window varint (0), total varint; bump the total's first byte
  z[off + 8 + 1] = static_cast<uint8_t>(z[off + 8 + 1] ^ 1);
  const uint32_t crc = crc32c_update(crc32c(&z[off], 4), &z[off + 8], len);  // type and payload
  for (int k = 0; k < 4; ++k) z[off + 8 + len + k] = static_cast<uint8_t>(crc >> (8 * k));
  try {
    decompress(z.data(), z.size());
    FAIL() << "corrupt SCNW accepted";
  } catch (const Error& e) {
    EXPECT_EQ(e.code(), ErrorCode::kCorrupt) << e.what();
    EXPECT_NE(std::string(e.what()).find("SCNW"), std::string::npos) << e.what();
  }
}

// take.h: a ragged take has no per-point labels and no shared point count; a take that says
// otherwise is refused, never written into a META its decoder would call corrupt.
TEST(ScanContainer, RaggedTakeWithLabelsOrPointsIsRefused) {
  Take t = synthetic_scan(2);
  t.labels.assign(t.frame_points(0), "p");
  std::string msg;
  try {
    compress(t, at(0.01));
  } catch (const Error& e) {
    EXPECT_EQ(e.code(), ErrorCode::kInvalidParameter) << e.what();
    msg = e.what();
  }
  EXPECT_NE(msg.find("labels"), std::string::npos) << msg;
  t.labels.clear();
  t.points = t.frame_points(0);
  EXPECT_THROW(compress(t, at(0.01)), Error);
  t.points = 0;
  EXPECT_NO_THROW(compress(t, at(0.01)));
}

// The shared scans (../shared/data/scan): every ragged sequence at 1 mm and 1 cm.
TEST(ScanContainer, SharedScansRoundTrip) {
  const char* env = std::getenv("CAPZ_SCAN_DATA");
  const std::filesystem::path dir = env ? env : std::string(CAPZ_SHARED_DATA) + "/scan";
  if (!std::filesystem::is_directory(dir)) GTEST_SKIP() << dir << " is absent";
  size_t done = 0;
  capz_test::TempDir tmp("capz_scan_container_real");
  for (const auto& e : std::filesystem::directory_iterator(dir)) {
    if (!e.is_directory()) continue;
    Take t;
    try {
      t = read_take(capz_test::folder_for_build(e.path().string(), tmp, 4));
    } catch (const Error&) {
      continue;  // not a frame folder capz reads
    }
    if (!t.ragged() || t.format != Format::kPCDFolder) continue;
    for (double bound : {0.001, 0.01}) {
      CompressOptions o = at(bound);
      o.drop_fields = true;
      const std::vector<uint8_t> z = compress(t, o);
      expect_within(t, decompress(z.data(), z.size()), bound);
    }
    ++done;
  }
  if (done == 0) GTEST_SKIP() << "no ragged PCD folder in " << dir;
}

// One place decides that a stream of one ragged frame (a single sweep the scan coder codes) is
// the fixed one-frame take a reader gives its file (codec/capz_source.h): the archive's frame
// source gives that header and fixed blocks, decompress() the same take, and describe() (what
// `capz info` prints) the same shape: not ragged, the frame's points, an unorganized layout.
TEST(ScanContainer, OneRaggedFrameReadsAsTheFixedFrameOfItsFile) {
  const std::string file = std::string(CAPZ_REPO_DATA) + "/scan_small/1691031766781547066.pcd";
  const Take t = read_take(file);
  ASSERT_FALSE(t.ragged());
  ASSERT_EQ(t.frames, 1u);
  CompressOptions o = at(0.001);
  o.drop_fields = true;
  const std::vector<uint8_t> z = compress(t, o);
  const StreamInfo si = describe(z.data(), z.size());
  ASSERT_TRUE(si.chunk_bytes.count("SCNW")) << "the scan coder no longer wins on it";
  EXPECT_FALSE(si.ragged);
  EXPECT_EQ(si.frames, 1u);
  EXPECT_EQ(si.points, t.points);
  EXPECT_EQ(si.total_points, t.points);
  EXPECT_EQ(si.pcd_width, t.points);
  EXPECT_EQ(si.pcd_height, 1u);
  const std::string path = (std::filesystem::temp_directory_path() /
                            ("capz_one_ragged_frame_" + std::to_string(::getpid()) + ".capz"))
                               .string();
  write_file(path, z, true);
  std::unique_ptr<FrameSource> src = open_capz_frames(path);
  const Take& h = src->header();
  EXPECT_FALSE(h.ragged());
  EXPECT_EQ(h.frames, 1u);
  EXPECT_EQ(h.points, t.points);
  EXPECT_TRUE(h.labels.empty());  // no labels, as the reader's (take.h)
  PromiseCheck check(promise_of(si));
  EXPECT_TRUE(check.header(t, h)) << check.why();  // the same labels as the reader's
  ASSERT_TRUE(h.pcd);
  EXPECT_EQ(h.pcd->width, t.points);
  EXPECT_EQ(h.pcd->height, 1u);
  FrameBlock b;
  src->read(0, 1, &b);
  EXPECT_FALSE(b.ragged());
  EXPECT_EQ(b.points, t.points);
  EXPECT_EQ(b.valid, t.valid);
  const Take d = decompress(z.data(), z.size());
  EXPECT_FALSE(d.ragged());
  EXPECT_EQ(d.points, t.points);
  EXPECT_EQ(d.labels, t.labels);  // none, as the reader gives
  EXPECT_EQ(d.xyz, b.xyz);
  EXPECT_EQ(d.pcd->width, t.points);
  src.reset();
  // A single frame file written from the archive's one block (the frame sink) holds the bytes
  // write_take writes of the decompressed take, in each frame format.
  for (const char* ext : {".pcd", ".ply", ".bin"}) {
    const std::string a = path + ext, w = path + "_take" + ext;
    std::unique_ptr<FrameSource> s = open_capz_frames(path);
    write_frames(*s, a, WriteOptions());
    write_take(d, w);
    EXPECT_EQ(read_file(a), read_file(w)) << ext;
    std::filesystem::remove(a);
    std::filesystem::remove(w);
  }
  std::filesystem::remove(path);
}

// A one-frame source streamed (compress_stream, which bounds the fixed stream from below, first
// without its fields and META coded, and codes it only when the scan stream is not under a
// bound) writes the bytes compress() of its take writes (both codings whole, the smaller kept):
// a sweep with and without its fields (its scan stream under the first bound), and clouds of
// three points without and with a field.
TEST(ScanContainer, OneFrameSourceStreamsWhatCompressChooses) {
  const std::string dir = std::filesystem::temp_directory_path().string();
  const std::string few = dir + "/capz_few_points_" + std::to_string(::getpid()) + ".pcd";
  const std::string header(
      "VERSION 0.7\nFIELDS x y z\nSIZE 4 4 4\nTYPE F F F\nCOUNT 1 1 1\n"
      "WIDTH 3\nHEIGHT 1\nVIEWPOINT 0 0 0 1 0 0 0\nPOINTS 3\nDATA ascii\n"
      "1 2 3\n4 5 6.5\n-1 0.25 2\n");
  write_file(few, std::vector<uint8_t>(header.begin(), header.end()), true);
  const std::string few_field = dir + "/capz_few_field_" + std::to_string(::getpid()) + ".pcd";
  const std::string with_field(
      "VERSION 0.7\nFIELDS x y z intensity\nSIZE 4 4 4 4\nTYPE F F F F\nCOUNT 1 1 1 1\n"
      "WIDTH 3\nHEIGHT 1\nVIEWPOINT 0 0 0 1 0 0 0\nPOINTS 3\nDATA ascii\n"
      "1 2 3 7\n4 5 6.5 9.5\n-1 0.25 2 100\n");
  write_file(few_field, std::vector<uint8_t>(with_field.begin(), with_field.end()), true);
  const std::string sweep = std::string(CAPZ_REPO_DATA) + "/scan_small/1691031766781547066.pcd";
  const std::string out = dir + "/capz_one_frame_" + std::to_string(::getpid()) + ".capz";
  for (const std::string& file : {sweep, few, few_field}) {
    for (bool drop : {true, false}) {
      CompressOptions o = at(0.001);
      o.drop_fields = drop;
      const std::vector<uint8_t> z = compress(read_take(file), o);
      std::unique_ptr<FrameSource> src = open_frames(file);
      compress_stream(*src, o, out, true);
      EXPECT_EQ(read_file(out), z) << file << (drop ? " --drop-fields" : "");
      if (file == sweep) {
        EXPECT_EQ(describe(z.data(), z.size()).chunk_bytes.count("SCNW"), 1u);
      }
    }
  }
  std::filesystem::remove(few);
  std::filesystem::remove(few_field);
  std::filesystem::remove(out);
}

}  // namespace
}  // namespace capz
