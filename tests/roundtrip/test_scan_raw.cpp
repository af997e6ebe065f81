// Raw windows (docs/FORMAT.md "Raw windows"): a lossless ragged take whose coordinates are
// float64 on no decimal grid is kept as float64 bits (mode 3, every window raw; refused before);
// a depth camera's frames without their invalid pixels whose depth is off any quantum, which the
// scan coder codes larger than LZMA2 of their bits, are kept raw (on a quantum they are raster
// frames); LiDAR sweeps keep the scan coder. Each gives every
// coordinate back bit for bit, its fields byte for byte and, from a folder, its files.
#include <gtest/gtest.h>

#include <cmath>
#include <cstring>
#include <filesystem>
#include <map>
#include <string>
#include <vector>

#include "capz/codec.h"
#include "capz/io.h"
#include "capz/stream.h"
#include "capz/tool/file.h"
#include "io/pcd_folder.h"
#include "roundtrip/lossless_folder.h"
#include "test_util.h"
#include "unit/synthetic.h"

namespace {

const std::string kData = CAPZ_REPO_DATA;

bool same_bits(double a, double b) {
  return std::memcmp(&a, &b, 8) == 0;
}

// d has t's frames, gaps, coordinates bit for bit and fields byte for byte.
void expect_exact(const capz::Take& t, const capz::Take& d) {
  ASSERT_EQ(d.frame_offsets, t.frame_offsets);
  ASSERT_EQ(d.valid, t.valid);
  ASSERT_EQ(d.xyz.size(), t.xyz.size());
  for (size_t i = 0; i < t.xyz.size(); ++i)
    if (t.valid[i / 3]) {
      ASSERT_TRUE(same_bits(d.xyz[i], t.xyz[i])) << "value " << i;
    }
  ASSERT_EQ(d.attributes.size(), t.attributes.size());
  for (size_t a = 0; a < t.attributes.size(); ++a)
    EXPECT_EQ(d.attributes[a].data, t.attributes[a].data) << t.attributes[a].name;
}

// Folder `in` compressed losslessly in windows of `window` frames, every frame file rebuilt
// byte for byte (capz_test::expect_rebuilt), and the decoded take exact against the folder's.
capz::CompressStats lossless_folder(const std::string& in, size_t window) {
  capz_test::TempDir tmp("capz_scan_raw");
  const capz::CompressStats st = capz_test::expect_rebuilt(in, tmp, window);
  const std::vector<uint8_t> bytes = capz::read_file(tmp.file("l.capz"));
  expect_exact(capz::read_take(in), capz::decompress(bytes.data(), bytes.size()));
  return st;
}

// lidar_small's sweeps without NaN in float64 map coordinates (data/make_raw_small.py), frames
// of their own counts: every window raw (refused at 841c43da).
TEST(ScanRaw, Float64FramesOnNoDecimalGridAreKeptAsTheirBits) {
  const capz::CompressStats st = lossless_folder(kData + "/utm_small", 2);
  EXPECT_EQ(st.mode, "float64-bits");
  EXPECT_EQ(st.float32_split_windows, (std::map<int, size_t>{{capz::kRawWindowsKey, 2}}));
  EXPECT_GT(st.attribute_bytes, 0u);  // intensity, in ATTR after the raw window
}

// A depth camera's frames without their invalid pixels (data/make_raw_small.py, 8,952 points):
// raster frames along the depth axis (its depth on a millimetre quantum), 18,470 B (16.5 bits a
// point), where a raw window took 46,084 B (41.2 bits a point; `xz -9e` of the files 48,956 B) and
// the scan coder's other frames 68,554 B (at 841c43da).
TEST(ScanRaw, DepthCameraFramesWithoutInvalidPixelsAreRasterFrames) {
  const capz::CompressStats st = lossless_folder(kData + "/depth_drop_small", 0);
  EXPECT_EQ(st.float32_split_windows.count(capz::kRawWindowsKey), 0u);
  EXPECT_EQ(st.mode, "float32-split");
  EXPECT_LT(st.bytes * 8, 20 * 8952u);
}

// The same frames with their depth moved off any quantum (each z times 1 + 3e-4 sin(i), rounded
// to float32): no raster, and the scan coder's other frames code larger than LZMA2 of the bits,
// so the window is kept raw.
TEST(ScanRaw, DepthFramesOffAnyQuantumAreKeptRaw) {
  capz::Take t = capz::read_take(kData + "/depth_drop_small");
  for (size_t i = 0; i < t.total_points(); ++i)
    if (t.valid[i])
      t.xyz[3 * i + 2] =
          static_cast<float>(t.xyz[3 * i + 2] * (1 + 3e-4 * std::sin(static_cast<double>(i))));
  capz::CompressOptions o;
  o.lossless = true;
  capz::CompressStats st;
  const std::vector<uint8_t> z = capz::compress(t, o, &st);
  ASSERT_EQ(st.float32_split_windows.count(capz::kRawWindowsKey), 1u);
  EXPECT_EQ(st.mode, "float32-bits");
  expect_exact(t, capz::decompress(z.data(), z.size()));
}

// An in-memory float64 take with a field, NaN gaps and a point at +0.0 0 0 (kept a point, bit
// for bit: a raw window has no origin points), and -0.0 coordinates.
TEST(ScanRaw, Float64TakeWithFieldsGapsAndZerosComesBackBitForBit) {
  capz::Take t = capz_test::synthetic_sweeps(3, 40, 5, 5.0, 30.0, 3.0, 0.02, 9, 11, 4);
  t.pcd->fields = {{"x", 'F', 8, 1}, {"y", 'F', 8, 1}, {"z", 'F', 8, 1}, {"intensity", 'U', 2, 1}};
  for (size_t i = 0; i < t.xyz.size(); ++i) t.xyz[i] += i % 3 == 0 ? 412345.6789012 : 1e-7;
  ASSERT_TRUE(t.valid[1] && t.valid[2]);
  for (size_t a = 0; a < 3; ++a) t.xyz[3 + a] = 0.0;
  t.xyz[7] = -0.0;
  capz::PointAttribute in{"intensity", 'U', 2, 1, {}};
  in.data.resize(t.total_points() * 2);
  for (size_t i = 0; i < in.data.size(); ++i) in.data[i] = static_cast<uint8_t>(i * 13 % 29);
  t.attributes.push_back(in);
  capz::CompressOptions o;
  o.lossless = true;
  o.window_frames = 2;
  capz::CompressStats st;
  const std::vector<uint8_t> z = capz::compress(t, o, &st);
  EXPECT_EQ(st.float32_split_windows, (std::map<int, size_t>{{capz::kRawWindowsKey, 2}}));
  expect_exact(t, capz::decompress(z.data(), z.size()));
  const capz::StreamInfo si = capz::describe(z.data(), z.size());
  EXPECT_EQ(si.mode, "float64-bits");
  EXPECT_EQ(si.float32_split_windows, st.float32_split_windows);
}

// LiDAR sweeps (float32): the scan coder's windows are far below a raw window's estimate.
TEST(ScanRaw, SweepsKeepTheScanCoder) {
  capz::Take t = capz_test::synthetic_sweeps(4, 60, 3, 5.0, 30.0, 3.0, 0.02, 5, 17, 2);
  t.pcd->fields = {{"x", 'F', 4, 1}, {"y", 'F', 4, 1}, {"z", 'F', 4, 1}};
  for (double& v : t.xyz) v = static_cast<double>(static_cast<float>(v));
  capz::CompressOptions o;
  o.lossless = true;
  capz::CompressStats st;
  const std::vector<uint8_t> z = capz::compress(t, o, &st);
  EXPECT_EQ(st.float32_split_windows.count(capz::kRawWindowsKey), 0u);
  expect_exact(t, capz::decompress(z.data(), z.size()));
}

}  // namespace

namespace {

// The decoder's memory limit counts a raw window's bits (24 bytes a point in mode 3) besides the
// 25 bytes of a decoded point and its fields' (FORMAT.md "Ragged frames: HEAD and the window
// chunk"): utm_small's golden stream (857 points, an F4 field) is refused under 40 bytes a point,
// which would hold it without the bits (29), and decodes under 53.
TEST(ScanRaw, MemoryLimitCountsARawWindowsBits) {
  const std::vector<uint8_t> z = capz::read_file(std::string(CAPZ_TEST_DIR) +
                                                 "/golden/streams/utm_small.lossless-w2.v1.1.capz");
  capz::DecompressOptions o;
  o.memory_limit = 857 * 40;
  try {
    capz::decompress(z.data(), z.size(), "utm.capz", o);
    ADD_FAILURE() << "decoded under " << o.memory_limit << " bytes";
  } catch (const capz::Error& e) {
    EXPECT_EQ(e.code(), capz::ErrorCode::kMemoryLimit) << e.what();
  }
  o.memory_limit = 857 * 53;
  EXPECT_EQ(capz::decompress(z.data(), z.size(), "utm.capz", o).total_points(), 857u);
}

}  // namespace
