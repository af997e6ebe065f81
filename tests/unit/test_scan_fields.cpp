// Point fields of ragged takes through the container (docs/FORMAT.md "Scans (format 1.1)": point
// fields of a ragged window): every field back byte for byte through decompress, frame ranges
// and the window-by-window decoder; the PCD layout kept for the writer; --attr-error; a damaged
// or missing ATTR of a ragged window refused as corrupt; the shared scan sequences.
#include <gtest/gtest.h>

#include <cmath>
#include <cstdint>
#include <cstring>
#include <filesystem>
#include <limits>
#include <random>
#include <string>

#include "capz/codec.h"
#include "capz/error.h"
#include "capz/io.h"
#include "coding/crc32c.h"
#include "synthetic.h"
#include "test_util.h"

namespace capz {
namespace {

// Appends one value of `size` bytes, little-endian, to a field.
void put(PointAttribute* a, uint64_t v, int size) {
  for (int k = 0; k < size; ++k) a->data.push_back(static_cast<uint8_t>(v >> (8 * k)));
}
void put_f32(PointAttribute* a, float v) {
  uint32_t u;
  std::memcpy(&u, &v, 4);
  put(a, u, 4);
}
void put_f64(PointAttribute* a, double v) {
  uint64_t u;
  std::memcpy(&u, &v, 8);
  put(a, u, 8);
}

// A 16-beam sweep per frame, each frame its own point count, NaN gaps, and the fields a LiDAR
// driver writes: intensity F4 (a NaN with a payload, a -0.0), ring U2, a padding field `_` of
// COUNT 3 (U1), timestamp F8 nearly linear in firing order, an I1 return type and a COUNT 2 F4.
Take scan_with_fields(size_t frames) {
  Take t = capz_test::synthetic_sweeps(frames, 120, 29, 4, 30, 2, 0.2, 11, 19, 4);
  t.pcd->fields = {{"x", 'F', 4, 1},         {"y", 'F', 4, 1},    {"z", 'F', 4, 1},
                   {"intensity", 'F', 4, 1}, {"ring", 'U', 2, 1}, {"_", 'U', 1, 3},
                   {"timestamp", 'F', 8, 1}, {"ret", 'I', 1, 1},  {"pair", 'F', 4, 2}};
  for (size_t i = 3; i < t.pcd->fields.size(); ++i)
    t.attributes.push_back(attribute_of(t.pcd->fields[i]));
  std::mt19937 rng(11);
  std::uniform_int_distribution<int> byte(0, 255);
  double time = 1.69e9;
  for (size_t i = 0; i < t.total_points(); ++i) {
    const int ring = static_cast<int>(i % 16);  // every frame is whole columns of 16
    const double* p = &t.xyz[3 * i];
    const double az = t.valid[i] ? std::atan2(p[1], p[0]) : 0.0;
    const double r = t.valid[i] ? std::sqrt(p[0] * p[0] + p[1] * p[1] + p[2] * p[2]) : 0.0;
    float in = static_cast<float>(std::round(100 * std::fabs(std::cos(az + ring))));
    if (i == 7) in = -0.0f;
    if (i == 9) {
      const uint32_t u = 0x7FC01234u;  // a NaN with a payload
      std::memcpy(&in, &u, 4);
    }
    put_f32(&t.attributes[0], in);
    put(&t.attributes[1], static_cast<uint64_t>(ring), 2);
    for (int b = 0; b < 3; ++b) put(&t.attributes[2], static_cast<uint64_t>(byte(rng)), 1);
    time += 2.3e-6;
    put_f64(&t.attributes[3], time);
    put(&t.attributes[4], static_cast<uint8_t>(static_cast<int8_t>(ring % 3 - 1)), 1);
    put_f32(&t.attributes[5], static_cast<float>(r));
    put_f32(&t.attributes[5], static_cast<float>(az));
  }
  return t;
}

CompressOptions at(double bound) {
  CompressOptions o;
  o.max_error = bound;
  return o;
}

// Frames [first, first + count) of src against d: counts, gaps, every field byte for byte, and
// every valid coordinate within the bound (also as the float32 a PCD writer stores).
void expect_frames(const Take& src, size_t first, const Take& d, double bound) {
  ASSERT_TRUE(d.ragged());
  const size_t p0 = src.frame_begin(first), p1 = src.frame_begin(first + d.frames);
  for (size_t f = 0; f < d.frames; ++f) ASSERT_EQ(d.frame_points(f), src.frame_points(first + f));
  ASSERT_EQ(d.total_points(), p1 - p0);
  ASSERT_EQ(d.attributes.size(), src.attributes.size());
  for (size_t a = 0; a < src.attributes.size(); ++a) {
    const PointAttribute &s = src.attributes[a], &g = d.attributes[a];
    EXPECT_EQ(g.name, s.name);
    EXPECT_EQ(g.type, s.type);
    EXPECT_EQ(g.size, s.size);
    EXPECT_EQ(g.count, s.count);
    const size_t bpp = s.bytes_per_point();
    ASSERT_EQ(g.data.size(), (p1 - p0) * bpp) << s.name;
    EXPECT_TRUE(std::equal(g.data.begin(), g.data.end(),
                           s.data.begin() + static_cast<std::ptrdiff_t>(p0 * bpp)))
        << "field " << s.name << " differs";
  }
  double worst = 0;
  for (size_t i = 0; i < p1 - p0; ++i) {
    ASSERT_EQ(d.valid[i], src.valid[p0 + i]) << i;
    if (!d.valid[i]) continue;
    for (size_t k = 0; k < 3; ++k) {
      const double x = src.xyz[3 * (p0 + i) + k], y = d.xyz[3 * i + k];
      worst = std::max({worst, std::fabs(x - y), std::fabs(x - static_cast<float>(y))});
    }
  }
  EXPECT_LE(worst, bound);
}

TEST(ScanFields, EveryFieldComesBackByteForByte) {
  const Take t = scan_with_fields(5);
  for (double bound : {0.001, 0.01}) {
    CompressOptions o = at(bound);
    o.window_frames = 2;  // three windows, the last short
    CompressStats st;
    const std::vector<uint8_t> z = compress(t, o, &st);
    EXPECT_GT(st.attribute_bytes, 0u);
    const Take d = decompress(z.data(), z.size());
    expect_frames(t, 0, d, bound);
    ASSERT_TRUE(d.pcd);
    ASSERT_EQ(d.pcd->fields.size(), t.pcd->fields.size());
    for (size_t i = 0; i < t.pcd->fields.size(); ++i) {
      EXPECT_EQ(d.pcd->fields[i].name, t.pcd->fields[i].name);
      EXPECT_EQ(d.pcd->fields[i].count, t.pcd->fields[i].count);
    }
    // Random access and the window-by-window decoder on workers give the same fields.
    expect_frames(t, 1, decompress_frames(z.data(), z.size(), 1, 3), bound);
    expect_frames(t, 4, decompress_frames(z.data(), z.size(), 4, 1), bound);
    DecompressOptions threads;
    threads.threads = 3;
    expect_frames(t, 0, decompress(z.data(), z.size(), "", threads), bound);
    expect_frames(t, 2, decompress_frames(z.data(), z.size(), 2, 2, "", threads), bound);
  }
}

// --drop-fields gives the bytes of the same take without fields (the fieldless stream).
TEST(ScanFields, DroppedFieldsGiveTheFieldlessStream) {
  const Take t = scan_with_fields(3);
  Take bare = t;
  bare.attributes.clear();
  bare.pcd = std::make_shared<PCDExtra>(*t.pcd);
  bare.pcd->fields.resize(3);
  CompressOptions drop = at(0.001);
  drop.drop_fields = true;
  const std::vector<uint8_t> a = compress(t, drop), b = compress(bare, at(0.001));
  EXPECT_EQ(a, b);
  EXPECT_TRUE(decompress(a.data(), a.size()).attributes.empty());
  EXPECT_LT(a.size(), compress(t, at(0.001)).size());
}

// --attr-error on a float field: its values within the bound, the others exact, the bound in
// META.
TEST(ScanFields, AttrErrorBoundsAFloatField) {
  const Take t = scan_with_fields(3);
  CompressOptions o = at(0.001);
  o.attr_error["pair"] = 0.01;
  const std::vector<uint8_t> z = compress(t, o);
  const Take d = decompress(z.data(), z.size());
  ASSERT_EQ(d.attributes.size(), t.attributes.size());
  for (size_t a = 0; a + 1 < t.attributes.size(); ++a)
    EXPECT_EQ(d.attributes[a].data, t.attributes[a].data) << t.attributes[a].name;
  const std::vector<uint8_t>&s = t.attributes.back().data, &g = d.attributes.back().data;
  ASSERT_EQ(s.size(), g.size());
  size_t moved = 0;
  for (size_t k = 0; k < s.size(); k += 4) {
    float x, y;
    std::memcpy(&x, &s[k], 4);
    std::memcpy(&y, &g[k], 4);
    EXPECT_LE(std::fabs(static_cast<double>(x) - static_cast<double>(y)), 0.01) << k;
    moved += x != y;
  }
  EXPECT_GT(moved, 0u);
  EXPECT_LT(z.size(), compress(t, at(0.001)).size());
  const StreamInfo si = describe(z.data(), z.size());
  ASSERT_EQ(si.pcd_field_bounds.size(), t.pcd->fields.size());
  EXPECT_EQ(si.pcd_field_bounds.back(), 0.01);
  EXPECT_EQ(si.pcd_field_bounds[3], 0.0);
  o.attr_error = {{"ring", 1.0}};  // integers are always lossless
  EXPECT_THROW(compress(t, o), Error);
}

// The offset of the first chunk of `type` in z (0: none).
size_t find_chunk(const std::vector<uint8_t>& z, const char* type) {
  for (size_t i = 9; i + 8 <= z.size(); ++i)
    if (std::memcmp(&z[i], type, 4) == 0) return i;
  return 0;
}

// The CRC of the chunk at `off` recomputed (type and payload).
void fix_crc(std::vector<uint8_t>* z, size_t off) {
  const uint32_t len = static_cast<uint32_t>((*z)[off + 4]) | (*z)[off + 5] << 8 |
                       (*z)[off + 6] << 16 | static_cast<uint32_t>((*z)[off + 7]) << 24;
  const uint32_t crc = crc32c_update(crc32c(&(*z)[off], 4), &(*z)[off + 8], len);
  for (int k = 0; k < 4; ++k) (*z)[off + 8 + len + k] = static_cast<uint8_t>(crc >> (8 * k));
}

void expect_corrupt(const std::vector<uint8_t>& z, const std::string& names) {
  for (size_t first : {size_t{0}, size_t{1}}) {
    try {
      decompress_frames(z.data(), z.size(), first, 1);
      FAIL() << "damaged stream accepted";
    } catch (const Error& e) {
      EXPECT_EQ(e.code(), ErrorCode::kCorrupt) << e.what();
      EXPECT_NE(std::string(e.what()).find(names), std::string::npos) << e.what();
    }
  }
}

TEST(ScanFields, DamagedOrMissingAttrOfARaggedWindowIsCorrupt) {
  const Take t = scan_with_fields(2);
  const std::vector<uint8_t> good = compress(t, at(0.01));  // one window of both frames
  const size_t off = find_chunk(good, "ATTR");
  ASSERT_GT(off, find_chunk(good, "SCNW"));
  {  // the chunk made ancillary ("attr"): the window has no ATTR
    std::vector<uint8_t> z = good;
    z[off] = 'a';
    z[off + 1] = 't';
    z[off + 2] = 't';
    z[off + 3] = 'r';
    fix_crc(&z, off);
    expect_corrupt(z, "missing chunk ATTR");
  }
  {  // the first field's transform byte (after the window index 0) out of range
    std::vector<uint8_t> z = good;
    z[off + 9] = 9;
    fix_crc(&z, off);
    expect_corrupt(z, "ATTR");
  }
  {  // the chunk says it belongs to window 1
    std::vector<uint8_t> z = good;
    z[off + 8] = 1;
    fix_crc(&z, off);
    expect_corrupt(z, "ATTR");
  }
  {  // a byte of the payload flipped, CRC left: the CRC names the chunk
    std::vector<uint8_t> z = good;
    z[off + 12] ^= 0x40;
    expect_corrupt(z, "ATTR");
  }
}

// The shared scan sequences (their fields: intensity, ring, f64 timestamps; RoboSense's
// azimuth, elevation, distance, ...) at 1 mm: counts, gaps, fields byte for byte, and the PCD
// frames written back hold the same fields.
TEST(ScanFields, SharedScanSequencesKeepEveryField) {
  const std::string root = capz_test::shared_data_or_skip("scan");
  if (root.empty()) return;
  size_t done = 0;
  capz_test::TempDir first("capz_scan_fields_real");
  for (const char* name : {"robosense-helios16p", "robosense-e1", "pandar64-factory20"}) {
    const std::string dir = root + "/" + name;
    if (!std::filesystem::is_directory(dir)) continue;
    const Take t = read_take(capz_test::folder_for_build(dir, first, 4));
    ASSERT_TRUE(t.ragged()) << name;
    ASSERT_FALSE(t.attributes.empty()) << name;
    const std::vector<uint8_t> z = compress(t, at(0.001));
    const Take d = decompress(z.data(), z.size());
    expect_frames(t, 0, d, 0.001);
    capz_test::TempDir tmp("capz_scan_fields");
    WriteOptions wo;
    wo.overwrite = true;
    write_take(d, tmp.file("back"), wo);
    const Take back = read_take(tmp.file("back"));
    ASSERT_EQ(back.pcd->fields.size(), t.pcd->fields.size()) << name;
    for (size_t i = 0; i < t.pcd->fields.size(); ++i) {
      EXPECT_EQ(back.pcd->fields[i].name, t.pcd->fields[i].name);
      EXPECT_EQ(back.pcd->fields[i].type, t.pcd->fields[i].type);
      EXPECT_EQ(back.pcd->fields[i].size, t.pcd->fields[i].size);
    }
    for (size_t a = 0; a < t.attributes.size(); ++a)
      EXPECT_EQ(back.attributes[a].data, t.attributes[a].data) << name << " " << a;
    ++done;
  }
  if (done == 0) GTEST_SKIP() << "no scan sequence in " << root;
}

// The single sweeps of /scan/single, each cut into two frames of their own size (a ragged take):
// fields (where the sweep has them) byte for byte, positions within 1 mm.
TEST(ScanFields, SingleSweepsAsRaggedTakes) {
  const std::string root = capz_test::shared_data_or_skip("scan/single");
  if (root.empty()) return;
  size_t done = 0;
  for (const auto& e : std::filesystem::directory_iterator(root)) {
    if (e.path().extension() != ".pcd") continue;
    Take t = read_take(e.path().string());
    ASSERT_EQ(t.frames, 1u);
    const size_t n = t.total_points();
    t.frames = 2;
    t.frame_offsets = {0, n / 3, n};
    t.points = 0;
    t.labels.clear();  // a ragged take has no per-point labels (take.h)
    t.descriptions.clear();
    t.pcd = std::make_shared<PCDExtra>(*t.pcd);
    t.pcd->frame_names = {"a.pcd", "b.pcd"};
    const std::vector<uint8_t> z = compress(t, at(0.001));
    expect_frames(t, 0, decompress(z.data(), z.size()), 0.001);
    ++done;
  }
  EXPECT_GT(done, 0u);
}

}  // namespace
// data/scan_small (four Helios 16P sweeps): the distance field, in 2.5 mm steps, is predicted from
// the decoded range (ATTR predictor 12) as well in a lossless stream, whose float32 windows are
// split (the positions the decoder has are the source's), as at 1 mm; every field comes back.
TEST(ScanFields, DistanceFromTheRangeAlsoWhenLossless) {
  const Take t = read_take(std::string(CAPZ_REPO_DATA) + "/scan_small");
  ASSERT_TRUE(t.ragged());
  CompressOptions lossless;
  lossless.lossless = true;
  CompressStats sl, sb;
  const std::vector<uint8_t> zl = compress(t, lossless, &sl);
  const std::vector<uint8_t> zb = compress(t, at(0.001), &sb);
  expect_frames(t, 0, decompress(zl.data(), zl.size()), 0);
  expect_frames(t, 0, decompress(zb.data(), zb.size()), 0.001);
  EXPECT_LT(static_cast<double>(sl.attribute_bytes), 1.1 * static_cast<double>(sb.attribute_bytes));
  // Far below the raw field bytes (the distance alone is 4 bytes a point).
  EXPECT_LT(sb.attribute_bytes, t.total_points() * 2);
}

}  // namespace capz
