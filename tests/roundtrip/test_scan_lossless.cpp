// Lossless ragged PCD folders (docs/FORMAT.md "Lossless ragged streams"): frames of their own
// point counts compressed with --lossless from their folder give every frame file back byte for
// byte (ascii, binary and binary_compressed, NaN gaps, headers of other forms), and every
// coordinate bit for bit; the shared scan sequences do too (their first frames here; every file
// with the CLI in docs/BENCHMARKS.md).
#include <gtest/gtest.h>

#include <cmath>
#include <cstring>
#include <filesystem>
#include <iterator>
#include <map>
#include <string>
#include <vector>

#include "capz/codec.h"
#include "capz/error.h"
#include "capz/io.h"
#include "capz/stream.h"
#include "capz/tool/file.h"
#include "capz/tool/original.h"
#include "coding/bytes.h"
#include "coding/quantiser.h"
#include "io/pcd_folder.h"
#include "roundtrip/lossless_folder.h"
#include "test_util.h"
#include "unit/synthetic.h"

namespace fs = std::filesystem;

namespace {

using capz_test::expect_rebuilt;

// The take an archive on disk decodes to.
capz::Take read_archive(const std::string& path) {
  const std::vector<uint8_t> bytes = capz::read_file(path);
  return capz::decompress(bytes.data(), bytes.size());
}

// A ragged take of x y z float32 (tests/unit/synthetic.h): frame f holds 16 x (12 + 3 f)
// points of a noisy sweep, every 37th point a NaN gap.
capz::Take sweeps(size_t frames) {
  capz::Take t = capz_test::synthetic_sweeps(frames, 12, 3, 5.0, 3.0, 5.0, 0.02, 11, 37, 3);
  t.pcd->fields = {{"x", 'F', 4, 1}, {"y", 'F', 4, 1}, {"z", 'F', 4, 1}};
  return t;
}

std::vector<std::vector<uint8_t>> folder_bytes(const std::string& dir) {
  std::vector<std::vector<uint8_t>> out;
  for (const std::string& name : capz::list_pcd_frames(dir))
    out.push_back(capz::read_file((fs::path(dir) / name).string()));
  return out;
}

// --lossless --drop-fields on folder `in`: x y z and gaps back bit for bit, no field, no HASH
// (the frame files cannot come back without their fields), and smaller than `with_fields` bytes.
void expect_positions_only(const std::string& in, const capz_test::TempDir& tmp,
                           size_t with_fields) {
  std::unique_ptr<capz::FrameSource> src = capz::open_frames(in);
  capz::CompressOptions o;
  o.lossless = true;
  o.window_frames = 2;
  o.drop_fields = true;
  capz::CompressStats st;
  const std::string z = tmp.file("d.capz");
  capz::compress_stream(*src, o, z, true, &st);
  EXPECT_TRUE(st.lossless) << in;
  EXPECT_FALSE(capz::original_info(z).hashed) << in;
  EXPECT_LT(st.bytes, with_fields) << in;
  const capz::Take a = capz::read_take(in), b = read_archive(z);
  EXPECT_TRUE(b.attributes.empty()) << in;
  EXPECT_EQ(b.frame_offsets, a.frame_offsets) << in;
  ASSERT_EQ(b.xyz.size(), a.xyz.size()) << in;
  EXPECT_EQ(b.valid, a.valid) << in;
  for (size_t i = 0; i < a.xyz.size(); ++i)
    if (a.valid[i / 3]) {
      ASSERT_EQ(std::memcmp(&a.xyz[i], &b.xyz[i], 8), 0) << in << " " << i;
    }
}

TEST(ScanLossless, InMemoryRaggedTakeComesBackBitForBit) {
  const capz::Take t = sweeps(4);
  capz::CompressOptions o;
  o.lossless = true;
  o.window_frames = 3;
  capz::CompressStats st;
  const std::vector<uint8_t> z = capz::compress(t, o, &st);
  EXPECT_TRUE(st.lossless);
  EXPECT_EQ(st.mode, "float32-split");  // "Lossless ragged streams": the float32 split
  const capz::Take d = capz::decompress(z.data(), z.size());
  ASSERT_EQ(d.frame_offsets, t.frame_offsets);
  ASSERT_EQ(d.valid, t.valid);
  for (size_t i = 0; i < t.xyz.size(); ++i) {
    if (!t.valid[i / 3]) continue;
    ASSERT_TRUE(capz::same_bits(d.xyz[i], t.xyz[i])) << i;
  }
  EXPECT_TRUE(capz::describe(z.data(), z.size()).lossless);
}

// The float32 split ("Lossless ragged streams") keeps -0.0, subnormals and values at binade
// edges; a window with a coordinate beyond the split's integers (1e30 in its third frame, after
// the first two chose a split) keeps the float32 bits, the next window splits again.
TEST(ScanLossless, EdgeCoordinatesComeBackBitForBitWithAndWithoutASplit) {
  capz::Take t = sweeps(5);
  const float edge[] = {-0.0f, 0.0f,         1e-45f, -1.17549435e-38f,
                        0.5f,  -0.99999994f, 1.0f,   std::nextafter(2.0f, 0.0f),
                        4.0f,  -1024.0f};
  size_t k = 0;
  for (size_t i = 0; i < t.frame_points(0) && k < 3 * std::size(edge); ++i)
    if (t.valid[i]) t.xyz[3 * i + k % 3] = edge[(k / 3) % std::size(edge)], ++k;
  const size_t p2 = t.frame_begin(2);
  for (size_t i = p2; i < t.frame_begin(3); ++i)
    if (t.valid[i]) {
      t.xyz[3 * i + 1] = 1e30f;
      break;
    }
  capz::CompressOptions o;
  o.lossless = true;
  o.window_frames = 3;
  const std::vector<uint8_t> z = capz::compress(t, o);
  const capz::Take d = capz::decompress(z.data(), z.size());
  ASSERT_EQ(d.valid, t.valid);
  for (size_t i = 0; i < t.xyz.size(); ++i) {
    if (t.valid[i / 3]) {
      ASSERT_TRUE(capz::same_bits(d.xyz[i], t.xyz[i])) << i << " " << t.xyz[i];
    }
  }
  std::vector<int> split;  // each SCNW's E (after the window and total varints and gaps)
  for (size_t at = 15; at + 12 <= z.size(); at += 12 + capz::load_le32(&z[at + 4])) {
    if (std::memcmp(&z[at], "SCNW", 4) != 0) continue;
    capz::ByteReader r(&z[at + 8], capz::load_le32(&z[at + 4]), "SCNW");
    r.varint();
    r.varint();
    r.u8();
    split.push_back(static_cast<int8_t>(r.u8()));
  }
  ASSERT_EQ(split.size(), 2u);
  EXPECT_EQ(split[0], -128);  // 1e30 has no integer below 2^29 at any exponent tried
  EXPECT_GE(split[1], 7);
  // The report counts the first window under the plain float32 windows' key, the second under
  // its exponent.
  const std::map<int, size_t> windows = capz::describe(z.data(), z.size()).float32_split_windows;
  EXPECT_EQ(windows, (std::map<int, size_t>{{capz::kPlainFloat32WindowsKey, 1}, {split[1], 1}}));
}

// The writer's frames in each encoding, then files of other forms: a header comment with CRLF
// line ends, an ascii body in printf spellings, a NaN payload of its own.
TEST(ScanLossless, FoldersOfEveryEncodingRebuildByteForByte) {
  capz_test::TempDir tmp("capz_scan_lossless");
  for (const char* enc : {"ascii", "binary", "binary_compressed"}) {
    const std::string dir = tmp.file(std::string("w_") + enc);
    capz::WriteOptions w;
    w.pcd_encoding = enc;
    capz::write_take(sweeps(5), dir + "/", w);
    expect_rebuilt(dir, tmp, 2);
  }
  const std::string odd = tmp.file("odd");
  fs::create_directories(odd);
  for (size_t f = 0; f < 3; ++f) {
    const size_t n = 4 + f;
    const bool text = f == 1;
    std::string h = "# scan " + std::to_string(f) + "\r\n# .PCD v0.7\r\nVERSION 0.7\r\n" +
                    "FIELDS x y z\r\nSIZE 4 4 4\r\nTYPE F F F\r\nCOUNT 1 1 1\r\nWIDTH " +
                    std::to_string(n) + "\r\nHEIGHT 1\r\nVIEWPOINT 0 0 0 1 0 0 0\r\nPOINTS " +
                    std::to_string(n) + "\r\nDATA " + (text ? "ascii" : "binary") + "\r\n";
    std::vector<uint8_t> b(h.begin(), h.end());
    for (size_t i = 0; i < n; ++i)
      for (int a = 0; a < 3; ++a) {
        const float v = 0.25f * static_cast<float>(i) - 1.5f * static_cast<float>(a) + 0.1f;
        if (text) {
          const std::string s = std::to_string(v) + (a == 2 ? "\n" : " ");
          b.insert(b.end(), s.begin(), s.end());
          continue;
        }
        uint8_t x[4];
        std::memcpy(x, &v, 4);
        if (f == 2 && i == 1) x[0] = 7, x[1] = 0, x[2] = 0xc0, x[3] = 0x7f;  // NaN, own payload
        b.insert(b.end(), x, x + 4);
      }
    capz::write_file(odd + "/o" + std::to_string(f) + ".pcd", b, true);
  }
  expect_rebuilt(odd, tmp);
}

// The first three frames of each shared sequence (their fields in ATTR; once more with the
// fields dropped: x y z alone, bit for bit), and of a binary folder converted from one.
TEST(ScanLossless, SharedSequencesRebuildByteForByte) {
  const std::string root = capz_test::shared_data_or_skip("scan");
  if (root.empty()) return;
  capz_test::TempDir tmp("capz_scan_lossless_real");
  const size_t kFrames = capz_test::kSanitized ? 2 : 3;  // 2: the same paths, two thirds the time
  for (const char* seq : {"robosense-helios16p", "robosense-e1", "pandar64-factory20"}) {
    const std::string dir = tmp.file(seq);
    fs::create_directories(dir);
    const std::vector<std::string> names = capz::list_pcd_frames(root + "/" + seq);
    ASSERT_GE(names.size(), 3u) << seq;
    for (size_t f = 0; f < kFrames; ++f)
      fs::copy_file(root + "/" + seq + "/" + names[f], dir + "/" + names[f]);
    const capz::CompressStats st = expect_rebuilt(dir, tmp, 2);
    EXPECT_GT(st.attribute_bytes, 0u) << seq;
    expect_positions_only(dir, tmp, st.bytes);
  }
  const std::string bin = tmp.file("binary");
  capz::WriteOptions w;
  w.pcd_encoding = "binary";
  capz::write_take(capz::read_take(tmp.file("robosense-helios16p")), bin + "/", w);
  EXPECT_EQ(folder_bytes(bin).size(), kFrames);
  expect_rebuilt(bin, tmp);
}

}  // namespace
