// Lossless PLY and KITTI .bin frames (docs/FORMAT.md "Lossless frame-file streams"): folders and
// single files compressed with --lossless from their path give every frame file back byte for
// byte: capz's own PLY in its three encodings and .bin, and files of other forms (a Python
// writer's "%.6f" ascii PLY with a comment and an empty face element, CRLF lines, trailing bytes
// after a binary body, .bin NaN payloads), fixed and ragged takes, with and without fields; the
// shared RoboSense sweeps converted to PLY and .bin too.
#include <gtest/gtest.h>

#include <algorithm>
#include <array>
#include <cmath>
#include <cstdio>
#include <cstring>
#include <filesystem>
#include <string>
#include <vector>

#include "capz/codec.h"
#include "capz/error.h"
#include "capz/io.h"
#include "capz/stream.h"
#include "capz/tool/file.h"
#include "capz/tool/original.h"
#include "test_util.h"

namespace fs = std::filesystem;

namespace {

// The take an archive on disk decodes to.
capz::Take read_archive(const std::string& path) {
  const std::vector<uint8_t> bytes = capz::read_file(path);
  return capz::decompress(bytes.data(), bytes.size());
}

std::vector<std::string> names_in(const std::string& dir) {
  std::vector<std::string> n;
  for (const auto& e : fs::directory_iterator(dir)) n.push_back(e.path().filename().string());
  std::sort(n.begin(), n.end());
  return n;
}

// Compresses `in` (a folder or one file) losslessly, rebuilds it at `out` and expects every
// frame file back byte for byte; returns the archive's path.
std::string expect_rebuilt(const std::string& in, const std::string& out,
                           const capz_test::TempDir& tmp, size_t window = 0) {
  std::unique_ptr<capz::FrameSource> src = capz::open_frames(in);
  capz::CompressOptions o;
  o.lossless = true;
  o.window_frames = window;
  capz::CompressStats st;
  const std::string z = tmp.file(fs::path(in).filename().string() + ".capz");
  capz::compress_stream(*src, o, z, true, &st);
  EXPECT_TRUE(st.lossless) << in;
  EXPECT_TRUE(capz::original_info(z).exact) << in;
  fs::remove_all(out);
  capz::rebuild_original(z, out, true);
  if (fs::is_directory(in)) {
    EXPECT_EQ(names_in(out), names_in(in)) << in;
    for (const std::string& n : names_in(in))
      EXPECT_EQ(capz::read_file(out + "/" + n), capz::read_file(in + "/" + n)) << in << "/" << n;
  } else {
    EXPECT_EQ(capz::read_file(out), capz::read_file(in)) << in;
  }
  EXPECT_EQ(capz::rebuilds_file(z, in), "") << in;
  return z;
}

void put(const std::string& path, const std::string& text) {
  capz::write_file(path, std::vector<uint8_t>(text.begin(), text.end()), true);
}

// Frame f of a sweep: 6 + 3 f points (or `fixed` points), x y z on a spiral rounded to float32,
// an intensity, point 2 a gap.
std::vector<std::array<float, 4>> sweep(size_t f, size_t fixed = 0) {
  const size_t n = fixed ? fixed : 6 + 3 * f;
  std::vector<std::array<float, 4>> p(n);
  for (size_t i = 0; i < n; ++i) {
    const double a = 0.3 * static_cast<double>(i) + 0.01 * static_cast<double>(f);
    p[i] = {static_cast<float>(12.5 * std::cos(a)), static_cast<float>(12.5 * std::sin(a)),
            static_cast<float>(-0.75 + 0.01 * static_cast<double>(i)), static_cast<float>(i % 50)};
  }
  if (n > 2) p[2][0] = p[2][1] = p[2][2] = std::nanf("");
  return p;
}

// A Python script's ascii PLY: "%.6f" numbers, a comment, an empty face element, `eol` lines.
std::string python_ply(const std::vector<std::array<float, 4>>& p, const std::string& eol,
                       const char* type) {
  std::string s = "ply" + eol + "format ascii 1.0" + eol + "comment written by numpy" + eol +
                  "element vertex " + std::to_string(p.size()) + eol;
  for (const char* n : {"x", "y", "z", "intensity"})
    s += std::string("property ") + type + " " + n + eol;
  s += "element face 0" + eol + "property list uchar int vertex_indices" + eol + "end_header" + eol;
  char buf[64];
  for (const auto& v : p) {
    for (int a = 0; a < 4; ++a) {
      std::snprintf(buf, sizeof buf, a ? " %.6f" : "%.6f", static_cast<double>(v[a]));
      s += buf;
    }
    s += eol;
  }
  return s;
}

// A binary PLY (float x y z intensity) of `enc` with `extra` bytes after the body.
std::string binary_ply(const std::vector<std::array<float, 4>>& p, bool big,
                       const std::string& extra) {
  std::string s = std::string("ply\nformat ") +
                  (big ? "binary_big_endian" : "binary_little_endian") +
                  " 1.0\nobj_info scanner 7\nelement vertex " + std::to_string(p.size()) +
                  "\nproperty float x\nproperty float y\nproperty float z\nproperty float "
                  "intensity\nend_header\n";
  for (const auto& v : p)
    for (float x : v) {
      char b[4];
      std::memcpy(b, &x, 4);
      if (big) std::swap(b[0], b[3]), std::swap(b[1], b[2]);
      s.append(b, 4);
    }
  return s + extra;
}

// A .bin of float32 x y z intensity (numpy's tofile); point 1's x a NaN of payload 0x123.
std::string bin_bytes(const std::vector<std::array<float, 4>>& p) {
  std::string s;
  for (const auto& v : p) s.append(reinterpret_cast<const char*>(v.data()), 16);
  if (p.size() > 1) {
    const uint32_t nan = 0x7fc00123;
    std::memcpy(&s[16], &nan, 4);
  }
  return s;
}

// nuScenes' .pcd.bin: float32 x y z intensity ring; point 1's x a NaN of payload 0x123.
std::string nuscenes_bytes(const std::vector<std::array<float, 4>>& p) {
  std::string s;
  for (size_t i = 0; i < p.size(); ++i) {
    const float ring = static_cast<float>(i % 32);
    s.append(reinterpret_cast<const char*>(p[i].data()), 16);
    s.append(reinterpret_cast<const char*>(&ring), 4);
  }
  if (p.size() > 1) {
    const uint32_t nan = 0x7fc00123;
    std::memcpy(&s[20], &nan, 4);
  }
  return s;
}

}  // namespace

// capz's own writer: PLY in each encoding and .bin, ragged, with every field; windows of 2.
TEST(FrameFileLossless, CapzWrittenFoldersRebuildByteForByte) {
  capz_test::TempDir tmp("capz_ffl_own");
  const std::string pcd = tmp.file("pcd");
  fs::create_directories(pcd);
  for (size_t f = 0; f < 5; ++f)
    put(pcd + "/s" + std::to_string(f) + ".ply", binary_ply(sweep(f), false, ""));
  const capz::Take t = capz::read_take(pcd);
  ASSERT_TRUE(t.ragged());
  for (const char* enc : {"ascii", "binary_little_endian", "binary_big_endian"}) {
    capz::WriteOptions w;
    w.ply_encoding = enc;
    const std::string dir = tmp.file(std::string("ply_") + enc);
    capz::write_take(t, dir + "/", w);
    expect_rebuilt(dir, tmp.file("back"), tmp, 2);
  }
  capz::WriteOptions w;
  w.folder_format = capz::Format::kBinFolder;
  capz::write_take(t, tmp.file("bin") + "/", w);
  expect_rebuilt(tmp.file("bin"), tmp.file("back"), tmp, 2);
}

// Other writers' forms: "%.6f" ascii PLY with LF and CRLF lines (float and double properties),
// binary PLY of both byte orders with trailing bytes, .bin (KITTI's and nuScenes') with NaN
// payloads; ragged and fixed.
TEST(FrameFileLossless, OtherWritersFilesRebuildByteForByte) {
  capz_test::TempDir tmp("capz_ffl_other");
  struct Case {
    const char* name;
    const char* ext;
    std::string (*file)(size_t f, size_t fixed);
  };
  const Case cases[] = {
      {"f6", ".ply", [](size_t f, size_t n) { return python_ply(sweep(f, n), "\n", "float"); }},
      {"f6crlf", ".ply",
       [](size_t f, size_t n) { return python_ply(sweep(f, n), "\r\n", "float"); }},
      {"f6d", ".ply", [](size_t f, size_t n) { return python_ply(sweep(f, n), "\n", "double"); }},
      {"le", ".ply",
       [](size_t f, size_t n) { return binary_ply(sweep(f, n), false, f == 1 ? "tail\n" : ""); }},
      {"be", ".ply", [](size_t f, size_t n) { return binary_ply(sweep(f, n), true, "\0\0"); }},
      {"bin", ".bin", [](size_t f, size_t n) { return bin_bytes(sweep(f, n)); }},
      {"nus", ".pcd.bin", [](size_t f, size_t n) { return nuscenes_bytes(sweep(f, n)); }},
  };
  for (const Case& c : cases)
    for (size_t fixed : {size_t{0}, size_t{9}}) {
      const std::string dir = tmp.file(std::string(c.name) + (fixed ? "_fixed" : ""));
      fs::create_directories(dir);
      for (size_t f = 0; f < 4; ++f) put(dir + "/" + std::to_string(f) + c.ext, c.file(f, fixed));
      EXPECT_EQ(capz::read_take(dir).ragged(), fixed == 0) << dir;
      expect_rebuilt(dir, tmp.file("back"), tmp, 3);
    }
}

// One file is a one-frame take, rebuilt as that one file. With --drop-fields the files cannot
// come back (their fields are left out): x y z come back bit for bit, and no HASH claims more.
TEST(FrameFileLossless, SingleFilesRebuildByteForByteAndDroppedFieldsKeepPositions) {
  capz_test::TempDir tmp("capz_ffl_single");
  put(tmp.file("one.ply"), python_ply(sweep(3), "\n", "float"));
  put(tmp.file("one.bin"), bin_bytes(sweep(4)));
  put(tmp.file("one.pcd.bin"), nuscenes_bytes(sweep(5)));
  expect_rebuilt(tmp.file("one.ply"), tmp.file("back.ply"), tmp);
  expect_rebuilt(tmp.file("one.bin"), tmp.file("back.bin"), tmp);
  expect_rebuilt(tmp.file("one.pcd.bin"), tmp.file("back.bin"), tmp);  // its record, any name
  const std::string dir = tmp.file("drop");
  fs::create_directories(dir);
  for (size_t f = 0; f < 3; ++f)
    put(dir + "/" + std::to_string(f) + ".ply", python_ply(sweep(f), "\n", "float"));
  std::unique_ptr<capz::FrameSource> src = capz::open_frames(dir);
  capz::CompressOptions o;
  o.lossless = true;
  o.drop_fields = true;
  capz::CompressStats st;
  capz::compress_stream(*src, o, tmp.file("d.capz"), true, &st);
  EXPECT_TRUE(st.lossless);
  EXPECT_FALSE(capz::original_info(tmp.file("d.capz")).hashed);
  const capz::Take a = capz::read_take(dir), b = read_archive(tmp.file("d.capz"));
  EXPECT_TRUE(b.attributes.empty());
  EXPECT_EQ(b.frame_offsets, a.frame_offsets);
  EXPECT_EQ(b.valid, a.valid);
  ASSERT_EQ(b.xyz.size(), a.xyz.size());
  for (size_t i = 0; i < a.xyz.size(); ++i)
    if (a.valid[i / 3]) {
      EXPECT_EQ(std::memcmp(&a.xyz[i], &b.xyz[i], 8), 0) << i;
    }
}

// A PLY file whose face element is not empty (a mesh) is refused by the reader, naming the file,
// as not our format (exit 3): it is a valid PLY, of a kind capz does not read.
TEST(FrameFileLossless, NonEmptyFaceElementIsRefusedByName) {
  capz_test::TempDir tmp("capz_ffl_face");
  put(tmp.file("mesh.ply"),
      "ply\nformat ascii 1.0\nelement vertex 3\nproperty float x\nproperty float y\nproperty float "
      "z\nelement face 1\nproperty list uchar int vertex_indices\nend_header\n0 0 0\n1 0 0\n0 1 "
      "0\n3 0 1 2\n");
  try {
    capz::open_frames(tmp.file("mesh.ply"));
    FAIL() << "a mesh was read";
  } catch (const capz::Error& e) {
    EXPECT_NE(std::string(e.what()).find("mesh.ply"), std::string::npos) << e.what();
    EXPECT_EQ(e.code(), capz::ErrorCode::kNotOurFormat) << e.what();  // a valid PLY, a mesh
  }
}

// The shared RoboSense sweeps (ascii PCD, every field) as capz's PLY and .bin: two frames each.
TEST(FrameFileLossless, SharedSweepsAsPLYAndBinRebuildByteForByte) {
  const std::string seq = capz_test::shared_data_or_skip("scan/robosense-helios16p");
  if (seq.empty()) return;
  capz_test::TempDir tmp("capz_ffl_shared");
  capz::Take t = capz::read_take(seq);
  ASSERT_GE(t.frames, 2u);
  const std::string two = tmp.file("two");
  fs::create_directories(two);
  std::vector<std::string> names;
  for (const auto& e : fs::directory_iterator(seq)) names.push_back(e.path().filename().string());
  std::sort(names.begin(), names.end());
  for (size_t f = 0; f < 2; ++f) fs::copy_file(seq + "/" + names[f], two + "/" + names[f]);
  t = capz::read_take(two);
  for (const char* enc : {"ascii", "binary_big_endian"}) {
    capz::WriteOptions w;
    w.ply_encoding = enc;
    w.folder_format = capz::Format::kPLYFolder;
    const std::string dir = tmp.file(std::string("ply_") + enc);
    capz::write_take(t, dir + "/", w);
    expect_rebuilt(dir, tmp.file("back"), tmp);
  }
  capz::WriteOptions w;
  w.folder_format = capz::Format::kBinFolder;
  w.drop_fields = true;
  capz::write_take(t, tmp.file("bin") + "/", w);
  expect_rebuilt(tmp.file("bin"), tmp.file("back"), tmp);
}
