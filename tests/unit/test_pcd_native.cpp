// The PCD frames capz reads without PCL (io/pcd_native.h): the same cloud as PCL's reader gives
// (fields, offsets, types, counts and point bytes) on binary and binary_compressed files, and a
// refusal, left to PCL, for headers PCL parses otherwise, `_` in a compressed body and bad LZF;
// a folder's frames read for their coordinates alone (FileFrameSource::read_coordinates).
#include <gtest/gtest.h>

#include <cstdio>
#include <cstring>
#include <filesystem>
#include <memory>
#include <string>
#include <utility>
#include <vector>

#include "capz/stream.h"
#include "coding/lzf.h"
#include "io/frame_files.h"
#include "io/pcd_backend.h"
#include "io/pcd_header.h"
#include "io/pcd_native.h"

namespace fs = std::filesystem;

namespace {

struct FieldSpec {
  std::string name;
  int size;
  char type;
  int count;
};

// A PCD file of `points` points with the given fields, values a function of the byte position;
// `compressed` writes the body as PCL does (each field's values of all points, then LZF).
std::vector<uint8_t> make_pcd(const std::vector<FieldSpec>& fields, size_t points, bool compressed,
                              const std::string& line_end = "\n") {
  std::string head = "# .PCD v0.7 - Point Cloud Data file format" + line_end + "VERSION 0.7";
  std::string f = "FIELDS", s = "SIZE", t = "TYPE", c = "COUNT";
  size_t step = 0;
  for (const FieldSpec& x : fields) {
    f += " " + x.name;
    s += " " + std::to_string(x.size);
    t += std::string(" ") + x.type;
    c += " " + std::to_string(x.count);
    step += static_cast<size_t>(x.size * x.count);
  }
  head += line_end + f + line_end + s + line_end + t + line_end + c + line_end + "WIDTH " +
          std::to_string(points) + line_end + "HEIGHT 1" + line_end + "VIEWPOINT 0 0 0 1 0 0 0" +
          line_end + "POINTS " + std::to_string(points) + line_end + "DATA " +
          (compressed ? "binary_compressed" : "binary") + line_end;
  std::vector<uint8_t> body(points * step);
  for (size_t i = 0; i < body.size(); ++i) body[i] = static_cast<uint8_t>((i * 7 + i / 13) & 0xff);
  std::vector<uint8_t> out(head.begin(), head.end());
  if (!compressed) {
    out.insert(out.end(), body.begin(), body.end());
    return out;
  }
  std::vector<uint8_t> planar;
  size_t offset = 0;
  for (const FieldSpec& x : fields) {
    const size_t bytes = static_cast<size_t>(x.size * x.count);
    for (size_t p = 0; p < points; ++p)
      planar.insert(planar.end(), body.begin() + static_cast<long>(p * step + offset),
                    body.begin() + static_cast<long>(p * step + offset + bytes));
    offset += bytes;
  }
  const std::vector<uint8_t> z = capz::lzf_compress(planar.data(), planar.size());
  for (size_t v : {z.size(), planar.size()})
    for (int k = 0; k < 4; ++k) out.push_back(static_cast<uint8_t>(v >> (8 * k)));
  out.insert(out.end(), z.begin(), z.end());
  return out;
}

// What PCL reads of the file.
capz::pcd::Cloud pcl_cloud(const std::vector<uint8_t>& bytes, const capz::PcdHeader& h) {
  capz::pcd::Cloud c;
  std::string msg;
  const capz::pcd::Status st = capz::pcd::backend("test").read(
      bytes.data(), bytes.size(), h.data_idx, h.points, h.point_step, &c, &msg);
  EXPECT_EQ(st, capz::pcd::Status::kOk) << msg;
  return c;
}

void expect_same(const capz::pcd::Cloud& a, const capz::pcd::Cloud& b) {
  EXPECT_EQ(a.width, b.width);
  EXPECT_EQ(a.height, b.height);
  EXPECT_EQ(a.point_step, b.point_step);
  ASSERT_EQ(a.fields.size(), b.fields.size());
  for (size_t i = 0; i < a.fields.size(); ++i) {
    EXPECT_EQ(a.fields[i].name, b.fields[i].name);
    EXPECT_EQ(a.fields[i].offset, b.fields[i].offset);
    EXPECT_EQ(a.fields[i].type, b.fields[i].type);
    EXPECT_EQ(a.fields[i].count, b.fields[i].count);
  }
  EXPECT_TRUE(a.data == b.data);
}

// True when capz reads the file itself; then its cloud is PCL's.
bool native_matches_pcl(const std::vector<uint8_t>& bytes) {
  const capz::PcdHeader h = capz::parse_header(bytes, "test");
  capz::pcd::Cloud mine;
  if (!capz::pcd::read_native(bytes, h, &mine)) return false;
  expect_same(mine, pcl_cloud(bytes, h));
  return true;
}

const std::vector<FieldSpec> kLidar = {
    {"x", 4, 'F', 1},    {"y", 4, 'F', 1},         {"z", 4, 'F', 1},      {"intensity", 4, 'F', 1},
    {"ring", 2, 'U', 1}, {"timestamp", 8, 'F', 1}, {"normal", 4, 'F', 3}, {"i8", 1, 'I', 1},
    {"u64", 8, 'U', 1},  {"i16", 2, 'I', 2}};

}  // namespace

TEST(PcdNative, GivenBinaryAndCompressedBodiesWhenReadThenPclsCloud) {
  for (bool compressed : {false, true}) {
    EXPECT_TRUE(native_matches_pcl(make_pcd(kLidar, 1000, compressed))) << compressed;
    EXPECT_TRUE(native_matches_pcl(make_pcd(kLidar, 1, compressed))) << compressed;
  }
}

TEST(PcdNative, GivenPaddingFieldsThenBinaryReadAndCompressedLeftToPcl) {
  std::vector<FieldSpec> padded = {
      {"x", 4, 'F', 1}, {"y", 4, 'F', 1}, {"z", 4, 'F', 1}, {"_", 1, 'U', 4}, {"rgb", 4, 'F', 1}};
  EXPECT_TRUE(native_matches_pcl(make_pcd(padded, 50, false)));
  EXPECT_FALSE(native_matches_pcl(make_pcd(padded, 50, true)));
}

TEST(PcdNative, GivenHeadersPclParsesOtherwiseThenLeftToPcl) {
  // Carriage returns, a TYPE PCL has no type for, a COUNT of 0 (PCL drops the field).
  EXPECT_FALSE(native_matches_pcl(make_pcd(kLidar, 10, false, "\r\n")));
  EXPECT_FALSE(native_matches_pcl(make_pcd(
      {{"x", 4, 'F', 1}, {"y", 4, 'F', 1}, {"z", 4, 'F', 1}, {"h", 2, 'F', 1}}, 10, false)));
  std::vector<uint8_t> zero = make_pcd(
      {{"x", 4, 'F', 1}, {"y", 4, 'F', 1}, {"z", 4, 'F', 1}, {"none", 4, 'F', 0}}, 10, false);
  capz::pcd::Cloud c;
  EXPECT_FALSE(capz::pcd::read_native(zero, capz::parse_header(zero, "test"), &c));
  // Keys out of PCL's order (POINTS before SIZE: PCL sizes the body with the step it has then).
  std::string moved =
      "FIELDS x y z\nPOINTS 2\nSIZE 4 4 4\nTYPE F F F\nWIDTH 2\nHEIGHT 1\nDATA binary\n";
  std::vector<uint8_t> b(moved.begin(), moved.end());
  b.resize(b.size() + 24, 0);
  EXPECT_FALSE(capz::pcd::read_native(b, capz::parse_header(b, "test"), &c));
  // A whitespace-only line ends PCL's header.
  std::string blank =
      "FIELDS x y z\nSIZE 4 4 4\n \nTYPE F F F\nWIDTH 2\nHEIGHT 1\nPOINTS 2\nDATA binary\n";
  b.assign(blank.begin(), blank.end());
  b.resize(b.size() + 24, 0);
  EXPECT_FALSE(capz::pcd::read_native(b, capz::parse_header(b, "test"), &c));
}

TEST(PcdNative, GivenCorruptCompressedBodyThenLeftToPcl) {
  std::vector<uint8_t> bytes = make_pcd(kLidar, 200, true);
  const capz::PcdHeader h = capz::parse_header(bytes, "test");
  bytes[h.data_idx + 8] = 0xff;  // a copy from before the start
  capz::pcd::Cloud c;
  EXPECT_FALSE(capz::pcd::read_native(bytes, h, &c));
}

TEST(PcdNative, GivenTheSharedScanFilesThenPclsCloud) {
  const fs::path root = fs::path(CAPZ_SHARED_DATA) / "scan";
  if (!fs::exists(root)) GTEST_SKIP() << "no shared data at " << root;
  size_t native = 0;
  for (const auto& e : fs::recursive_directory_iterator(root)) {
    if (e.path().extension() != ".pcd") continue;
    const std::vector<uint8_t> bytes = capz::read_file_head(e.path().string(), size_t{1} << 30);
    const capz::PcdHeader h = capz::parse_header(bytes, e.path().string());
    if (h.data == "ascii") continue;
    EXPECT_TRUE(native_matches_pcl(bytes)) << e.path();
    ++native;
  }
  EXPECT_GT(native, 0u);
}

namespace {

// A folder of three frames of 500, 20 and 7 points with the given fields (make_pcd's bytes).
std::string frame_folder(const std::string& name, const std::vector<FieldSpec>& fields,
                         bool compressed) {
  const fs::path dir = fs::temp_directory_path() / ("capz_pcd_coords_" + name);
  fs::remove_all(dir);
  fs::create_directories(dir);
  const size_t points[3] = {500, 20, 7};
  for (int f = 0; f < 3; ++f) {
    const std::vector<uint8_t> bytes = make_pcd(fields, points[f], compressed);
    FILE* out = std::fopen((dir / ("f" + std::to_string(f) + ".pcd")).string().c_str(), "wb");
    EXPECT_TRUE(out != nullptr);
    if (!out) break;
    std::fwrite(bytes.data(), 1, bytes.size(), out);
    std::fclose(out);
  }
  return dir.string();
}

}  // namespace

// FileFrameSource::read_coordinates (the encoder's first pass over a ragged take): the
// coordinates and gaps read() gives, frame by frame, without the fields; a compressed body's
// planes after x y z's (here a field before them and two after) are not needed for that. Frame
// 0, which opening the folder read, still comes whole to the first read() of it after.
TEST(PcdNative, GivenFolderWhenCoordinatesReadThenReadsCoordinatesAndGaps) {
  const std::vector<FieldSpec> after = {{"intensity", 4, 'F', 1}, {"x", 4, 'F', 1},
                                        {"y", 4, 'F', 1},         {"z", 4, 'F', 1},
                                        {"ring", 2, 'U', 1},      {"t", 8, 'F', 1}};
  const std::vector<FieldSpec> doubles = {
      {"x", 8, 'F', 1}, {"y", 8, 'F', 1}, {"z", 8, 'F', 1}, {"ring", 2, 'U', 1}};
  for (const auto& c : {std::make_pair(after, true), std::make_pair(after, false),
                        std::make_pair(doubles, true), std::make_pair(doubles, false)}) {
    const std::string dir =
        frame_folder(std::to_string(c.first.size()) + (c.second ? "c" : "b"), c.first, c.second);
    std::unique_ptr<capz::FrameSource> src = capz::open_pcd_frames(dir);
    auto* files = dynamic_cast<capz::FileFrameSource*>(src.get());
    ASSERT_TRUE(files != nullptr);
    capz::FrameBlock coords, whole;
    files->read_coordinates(1, 2, &coords);
    src->read(1, 2, &whole);
    EXPECT_TRUE(coords.attributes.empty());
    ASSERT_EQ(whole.attributes.size(), c.first.size() - 3);
    EXPECT_EQ(whole.attributes[0].size(), 27 * static_cast<size_t>(c.first[0].size == 4 ? 4 : 2));
    EXPECT_EQ(coords.frame_offsets, whole.frame_offsets);
    EXPECT_EQ(coords.valid, whole.valid);
    ASSERT_EQ(coords.xyz.size(), whole.xyz.size());
    for (size_t i = 0; i < coords.xyz.size(); ++i)
      ASSERT_TRUE(std::memcmp(&coords.xyz[i], &whole.xyz[i], 8) == 0) << i;
    std::unique_ptr<capz::FrameSource> again = capz::open_pcd_frames(dir);
    capz::FrameBlock first;
    again->read(0, 1, &first);  // the frame opening read, given whole
    dynamic_cast<capz::FileFrameSource*>(again.get())->read_coordinates(0, 1, &coords);
    EXPECT_EQ(first.xyz.size(), 1500u);
    EXPECT_EQ(first.attributes.size(), c.first.size() - 3);
    EXPECT_EQ(coords.valid, first.valid);
    fs::remove_all(dir);
  }
}
