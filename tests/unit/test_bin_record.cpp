// .bin frames in a declared record (--bin-fields, capz::ReadOptions::bin_fields; FORMAT.md
// "Frame-file sources"): the record's text, the reader and writer, the archive keeping the record,
// lossless files rebuilt byte for byte, and the warning on a names' record the frames do not fit.
#include <gtest/gtest.h>

#include <cmath>
#include <cstring>
#include <filesystem>
#include <limits>
#include <string>
#include <vector>

#include "capz/codec.h"
#include "capz/error.h"
#include "capz/io.h"
#include "capz/stream.h"
#include "capz/tool/compress_file.h"
#include "capz/tool/file.h"
#include "capz/tool/original.h"
#include "io/bin_folder.h"
#include "support/frame_files.h"
#include "test_util.h"

namespace fs = std::filesystem;
using capz::ErrorCode;
using capz_test::put;
using capz_test::TempDir;

namespace {

// A frame of `n` points in the record "x y z intensity:U1 _:U1 ring:U2 t:F8" (24 bytes a point),
// point 1 a gap (x y z quiet NaNs, as capz writes a gap), the padding byte 0xAB.
std::string mixed_frame(size_t n, int f) {
  std::string s;
  for (size_t i = 0; i < n; ++i) {
    const double a = 0.1 * static_cast<double>(i) + f;
    const float nan = std::numeric_limits<float>::quiet_NaN();  // a gap: x y z 0x7fc00000
    capz_test::append_bytes(&s, i == 1 ? nan : static_cast<float>(20 * std::cos(a)));
    capz_test::append_bytes(&s, i == 1 ? nan : static_cast<float>(20 * std::sin(a)));
    capz_test::append_bytes(
        &s, i == 1 ? nan : static_cast<float>(-1.5 + 0.01 * static_cast<double>(i)));
    capz_test::append_bytes(&s, static_cast<uint8_t>(i * 7));
    capz_test::append_bytes(&s, static_cast<uint8_t>(0xAB));
    capz_test::append_bytes(&s, static_cast<uint16_t>(i % 32));
    capz_test::append_bytes(&s, 1.7e9 + 0.1 * f + 1e-6 * static_cast<double>(i));
  }
  return s;
}

const char kMixed[] = "x y z intensity:U1 _:U1 ring:U2 t:F8";

// Error code of f(), its message in *what (0 when it returns).
template <class F>
ErrorCode code_of(F f, std::string* what) {
  try {
    f();
  } catch (const capz::Error& e) {
    *what = e.what();
    return e.code();
  }
  return static_cast<ErrorCode>(0);
}

}  // namespace

TEST(BinRecord, GivenRecordTextsThenParsedOrRefusedByName) {
  const std::vector<capz::PCDField> r =
      capz::parse_bin_record("x, y, z intensity ring:u2 t:F8", "");
  ASSERT_EQ(r.size(), 3u);
  EXPECT_EQ(r[1].name, "ring");
  EXPECT_EQ(r[1].type, 'U');
  EXPECT_EQ(r[1].size, 2);
  EXPECT_EQ(r[2].type, 'F');
  EXPECT_EQ(r[2].size, 8);
  EXPECT_EQ(capz::bin_record_text(r), "x y z intensity ring:U2 t:F8");
  EXPECT_EQ(capz::parse_bin_record("x y z", "").size(), 0u);
  EXPECT_EQ(capz::parse_bin_record("x y z _ _:U2 i", "").size(), 3u);  // padding twice
  for (const char* bad : {"", "x y", "y x z i", "x:F8 y z", "x y z i i", "x y z i:F2", "x y z i:Q4",
                          "x y z i:U", "x y z :U2", "x y z x"}) {
    std::string what;
    EXPECT_EQ(code_of([&] { capz::parse_bin_record(bad, "f.bin"); }, &what), ErrorCode::kUsage)
        << bad;
    EXPECT_NE(what.find("--bin-fields"), std::string::npos) << what;
  }
}

// Frames of their own counts in a declared record: each field of its type (the padding kept),
// the gap in place, written back byte for byte; a folder of another format is refused.
TEST(BinRecord, GivenADeclaredRecordThenReadInItAndWrittenBackAsTheFilesWere) {
  TempDir dir;
  fs::create_directories(dir.path() / "in");
  const std::string a = mixed_frame(40, 0), b = mixed_frame(26, 1);
  put(dir.path() / "in" / "000000.bin", a);
  put(dir.path() / "in" / "000001.bin", b);
  capz::ReadOptions ro;
  ro.bin_fields = kMixed;
  const capz::Take t = capz::read_take(dir.file("in"), ro);
  ASSERT_EQ(t.frame_offsets, (std::vector<size_t>{0, 40, 66}));
  ASSERT_EQ(t.attributes.size(), 4u);
  EXPECT_EQ(t.attributes[0].type, 'U');
  EXPECT_EQ(t.attributes[0].size, 1);
  EXPECT_EQ(t.attributes[1].name, "_");
  EXPECT_EQ(t.attributes[3].size, 8);
  EXPECT_EQ(t.attributes[1].data[5], 0xAB);
  EXPECT_EQ(t.valid[1], 0);
  EXPECT_EQ(t.valid[41], 0);
  ASSERT_TRUE(t.bin);
  EXPECT_EQ(capz::bin_record_text(capz::bin_record_of(t)), kMixed);
  EXPECT_TRUE(t.warnings.empty());
  capz::write_take(t, dir.file("back/"));
  EXPECT_EQ(capz::read_file(dir.file("back/000000.bin")), std::vector<uint8_t>(a.begin(), a.end()));
  EXPECT_EQ(capz::read_file(dir.file("back/000001.bin")), std::vector<uint8_t>(b.begin(), b.end()));
  // Without the record, 40 x 24 bytes read as 60 KITTI points, and the warning says so.
  const capz::Take k = capz::read_take(dir.file("in"));
  EXPECT_EQ(k.frame_offsets, (std::vector<size_t>{0, 60, 60 + 26 * 24 / 16}));
  ASSERT_EQ(k.warnings.size(), 1u);
  EXPECT_NE(k.warnings[0].find("--bin-fields"), std::string::npos) << k.warnings[0];
  // The record, for a PCD folder: a usage error naming it.
  capz::write_take(t, dir.file("pcd/"), [] {
    capz::WriteOptions w;
    w.folder_format = capz::Format::kPCDFolder;
    return w;
  }());
  std::string what;
  EXPECT_EQ(code_of([&] { capz::read_take(dir.file("pcd"), ro); }, &what), ErrorCode::kUsage);
  EXPECT_NE(what.find("pcd"), std::string::npos) << what;
  // A whole number of points is still checked: 24 bytes a point.
  put(dir.path() / "cut.bin", a.substr(0, 30));
  EXPECT_EQ(code_of([&] { capz::read_take(dir.file("cut.bin"), ro); }, &what), ErrorCode::kCorrupt);
  EXPECT_NE(what.find("multiple of 24"), std::string::npos) << what;
}

// The archive keeps the record: at a bound the fields exact and the files in their record; with
// --drop-fields x y z alone (written in KITTI's record); lossless, the files byte for byte.
TEST(BinRecord, GivenADeclaredRecordThenTheArchiveKeepsItAndLosslessRebuildsTheFiles) {
  TempDir dir;
  fs::create_directories(dir.path() / "in");
  put(dir.path() / "in" / "a.bin", mixed_frame(300, 0));
  put(dir.path() / "in" / "b.pcd.bin",
      mixed_frame(280, 1));  // names of two kinds: no names' record
  capz::ReadOptions ro;
  ro.bin_fields = kMixed;
  const capz::Take t = capz::read_take(dir.file("in"), ro);
  for (bool drop : {false, true}) {
    capz::CompressOptions o;
    o.max_error = 0.001;
    o.drop_fields = drop;
    const std::vector<uint8_t> s = capz::compress(t, o);
    const capz::Take d = capz::decompress(s.data(), s.size(), "r.capz");
    ASSERT_TRUE(d.bin);
    EXPECT_EQ(capz::bin_record_text(capz::bin_record_of(d)),
              drop ? std::string("x y z intensity") : std::string(kMixed));
    ASSERT_EQ(d.attributes.size(), drop ? 0u : 4u);
    for (size_t k = 0; k < d.attributes.size(); ++k)
      EXPECT_EQ(d.attributes[k].data, t.attributes[k].data) << k;
    for (size_t i = 0; i < t.valid.size(); ++i) {
      ASSERT_EQ(d.valid[i], t.valid[i]);
      for (size_t c = 0; c < 3 && t.valid[i]; ++c)
        EXPECT_LE(std::fabs(d.xyz[3 * i + c] - t.xyz[3 * i + c]), 0.001 * (1 + 1e-9));
    }
  }
  capz::CompressTarget lossless;
  lossless.lossless = true;
  capz::compress_file(dir.file("in"), dir.file("l.capz"), lossless, capz::CompressOptions(), "",
                      false, nullptr, ro);
  capz::test_original(dir.file("l.capz"));
  capz::rebuild_original(dir.file("l.capz"), dir.file("back"), false);
  for (const char* f : {"a.bin", "b.pcd.bin"})
    EXPECT_EQ(capz::read_file(dir.file(std::string("back/") + f)),
              capz::read_file(dir.file(std::string("in/") + f)))
        << f;
  // Without the record the folder is refused: its names are of two kinds.
  std::string what;
  EXPECT_EQ(code_of([&] { capz::read_take(dir.file("in")); }, &what), ErrorCode::kNotOurFormat);
  EXPECT_NE(what.find("--bin-fields"), std::string::npos) << what;
}

// A record of x y z alone (12 bytes a point, numpy's tofile of an (N, 3) float32 array): declared,
// it holds no field, and the archive keeps it (HEAD's frame_format 6), so the files come back in
// it, not as KITTI's 16-byte points.
TEST(BinRecord, GivenARecordOfXyzAloneThenTheFilesComeBackTwelveBytesAPoint) {
  TempDir dir;
  fs::create_directories(dir.path() / "in");
  std::string a;
  for (int i = 0; i < 64; ++i)  // 64 x 12 bytes: 48 KITTI points too
    for (float v : {0.5f * static_cast<float>(i), -2.0f, 1.25f + 0.01f * static_cast<float>(i)})
      capz_test::append_bytes(&a, v);
  put(dir.path() / "in" / "0.bin", a);
  capz::ReadOptions ro;
  ro.bin_fields = "x y z";
  const capz::Take t = capz::read_take(dir.file("in"), ro);
  ASSERT_EQ(t.total_points(), 64u);
  EXPECT_TRUE(t.attributes.empty());
  capz::CompressOptions o;
  o.max_error = 0.001;
  const std::vector<uint8_t> s = capz::compress(t, o);
  const capz::Take d = capz::decompress(s.data(), s.size(), "x.capz");
  ASSERT_TRUE(d.bin);
  EXPECT_TRUE(d.bin->declared);
  capz::write_take(d, dir.file("back/"));
  EXPECT_EQ(fs::file_size(dir.file("back/0.bin")), 64u * 12u);
  capz::CompressTarget lossless;
  lossless.lossless = true;
  capz::compress_file(dir.file("in"), dir.file("l.capz"), lossless, capz::CompressOptions(), "",
                      false, nullptr, ro);
  capz::rebuild_original(dir.file("l.capz"), dir.file("lback"), false);
  EXPECT_EQ(capz::read_file(dir.file("lback/0.bin")), std::vector<uint8_t>(a.begin(), a.end()));
}

// KITTI frames of real sweeps do not draw the warning (data/scan_small_bin: pandar64 sweeps), nor
// do gaps whose intensity is NaN too (a driver's no-return: 10 of 100 points here).
TEST(BinRecord, GivenRealKittiFramesThenNoRecordWarning) {
  const capz::Take t = capz::read_take(std::string(CAPZ_REPO_DATA) + "/scan_small_bin");
  ASSERT_GT(t.total_points(), 0u);
  EXPECT_TRUE(t.warnings.empty()) << t.warnings.front();
  TempDir dir;
  std::string a;
  const float nan = std::numeric_limits<float>::quiet_NaN();
  for (int i = 0; i < 100; ++i)
    for (float v : {i % 10 ? 0.1f * static_cast<float>(i) : nan, 2.0f, -1.0f, i % 10 ? 0.5f : nan})
      capz_test::append_bytes(&a, v);
  put(dir.path() / "gaps.bin", a);
  const capz::Take g = capz::read_take(dir.file("gaps.bin"));
  EXPECT_EQ(g.gap_samples(), 10u);
  EXPECT_TRUE(g.warnings.empty()) << g.warnings.front();
}

// A take's field written in a record of another type (a PCD folder's F4 intensity into
// --bin-fields' integers, a U2 ring into F8): integers rounded to the nearest and clamped to their
// type's range, NaN as 0, floats converted; a field of the same type and size bit for bit.
TEST(BinRecord, GivenAFieldOfAnotherTypeThenWrittenRoundedAndClampedInTheRecordsType) {
  capz::Take t;
  capz::PointAttribute f4{"v", 'F', 4, 1, {}}, u2{"ring", 'U', 2, 1, {}};
  t.attributes = {f4, u2};
  const std::vector<float> v = {2.5f,  -2.5f,  1.4f,
                                -0.6f, 300.0f, -300.0f,
                                1e30f, -1e30f, std::numeric_limits<float>::quiet_NaN()};
  const size_t n = v.size();
  std::vector<uint16_t> ring(n);
  for (size_t i = 0; i < n; ++i) ring[i] = static_cast<uint16_t>(i * 7000);
  const std::vector<const uint8_t*> attrs = {reinterpret_cast<const uint8_t*>(v.data()),
                                             reinterpret_cast<const uint8_t*>(ring.data())};
  const std::vector<double> xyz(3 * n, 1.0);
  const std::vector<uint8_t> valid(n, 1);
  // The record: v in each integer type and F8, then ring as F8 and as F4.
  const std::vector<capz::PCDField> record = {
      {"v", 'U', 1, 1}, {"v", 'I', 1, 1}, {"v", 'I', 2, 1},    {"v", 'U', 8, 1},
      {"v", 'I', 8, 1}, {"v", 'F', 8, 1}, {"ring", 'F', 8, 1}, {"ring", 'F', 4, 1}};
  std::vector<capz::BinRecordSource> src = capz::bin_record_sources(t, record);
  ASSERT_EQ(src.size(), record.size());
  // bin_record_sources takes a field once (the first v and ring columns): the others are matched
  // by hand here.
  EXPECT_EQ(src[0].k, 0u);
  EXPECT_EQ(src[1].k, SIZE_MAX);
  EXPECT_EQ(src[6].k, 1u);
  for (size_t c = 0; c < 8; ++c) {
    src[c].k = c < 6 ? 0 : 1;
    src[c].layout = c < 6 ? f4 : u2;
  }
  const std::vector<uint8_t> out = capz::bin_record_frame(src, n, xyz.data(), valid.data(), attrs);
  const size_t point = 12 + 1 + 1 + 2 + 8 + 8 + 8 + 8 + 4;
  ASSERT_EQ(out.size(), n * point);
  const auto at = [&](size_t i, size_t off, void* dst, size_t bytes) {
    std::memcpy(dst, out.data() + i * point + 12 + off, bytes);
  };
  // nearbyint rounds half to even: 2.5 -> 2, -2.5 -> -2.
  const int64_t want_u1[] = {2, 0, 1, 0, 255, 0, 255, 0, 0};
  const int64_t want_i1[] = {2, -2, 1, -1, 127, -128, 127, -128, 0};
  const int64_t want_i2[] = {2, -2, 1, -1, 300, -300, 32767, -32768, 0};
  for (size_t i = 0; i < n; ++i) {
    uint8_t u1;
    int8_t i1;
    int16_t i2;
    uint64_t u8;
    int64_t i8;
    double f8, r8;
    float r4;
    at(i, 0, &u1, 1);
    at(i, 1, &i1, 1);
    at(i, 2, &i2, 2);
    at(i, 4, &u8, 8);
    at(i, 12, &i8, 8);
    at(i, 20, &f8, 8);
    at(i, 28, &r8, 8);
    at(i, 36, &r4, 4);
    EXPECT_EQ(u1, want_u1[i]) << i;
    EXPECT_EQ(i1, want_i1[i]) << i;
    EXPECT_EQ(i2, want_i2[i]) << i;
    if (std::isnan(v[i])) {
      EXPECT_EQ(u8, 0u);
      EXPECT_EQ(i8, 0);
      EXPECT_TRUE(std::isnan(f8));
    } else {
      EXPECT_EQ(u8, v[i] >= 1e30f ? ~uint64_t{0}
                    : v[i] < 0    ? 0
                                  : static_cast<uint64_t>(std::nearbyint(v[i])))
          << i;
      EXPECT_EQ(i8, v[i] >= 1e30f    ? std::numeric_limits<int64_t>::max()
                    : v[i] <= -1e30f ? std::numeric_limits<int64_t>::min()
                                     : static_cast<int64_t>(std::nearbyint(v[i])))
          << i;
      EXPECT_EQ(f8, static_cast<double>(v[i])) << i;
    }
    EXPECT_EQ(r8, static_cast<double>(ring[i])) << i;
    EXPECT_EQ(r4, static_cast<float>(ring[i])) << i;
  }
}
