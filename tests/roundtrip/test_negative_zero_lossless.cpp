// Negative zeros under --lossless (docs/FORMAT.md "Lossless ragged streams", "Negative zeros"): a
// coordinate written `-0.000000` or `-0` reads as -0.0, which no decimal grid decodes. Frame files
// whose coordinates are on a decimal grid (ascii PLY and PCD of double coordinates, binary double
// PLY of decimal values) come back byte for byte with such coordinates, as a ragged folder and as
// single files, and the decoded coordinates keep the sign; so do float32 files (mode 2 keeps
// the sign in its bits), a ragged take built in memory, and a damaged list is corrupt.
#include <gtest/gtest.h>

#include <array>
#include <cmath>
#include <cstring>
#include <filesystem>
#include <string>
#include <vector>

#include "../corrupt/chunk_util.h"
#include "capz/codec.h"
#include "capz/error.h"
#include "capz/io.h"
#include "capz/stream.h"
#include "capz/tool/file.h"
#include "capz/tool/original.h"
#include "test_util.h"

namespace fs = std::filesystem;

namespace {

// Frame f's points as text: 3 + f of them, decimals of two digits, with `-0.000000` and `-0`.
std::vector<std::array<std::string, 3>> frame_text(size_t f) {
  std::vector<std::array<std::string, 3>> p = {{"1.100000", "-0.000000", "2.250000"},
                                               {"-0", "0.100000", "-3.500000"},
                                               {"0.000000", "4.010000", "-0.000000"}};
  for (size_t i = 0; i < f; ++i)
    p.push_back({std::to_string(0.25 * static_cast<double>(i + f)), "-0.000000", "7.750000"});
  return p;
}

std::string ascii_ply(size_t f, const char* type) {
  const auto p = frame_text(f);
  std::string s = "ply\nformat ascii 1.0\nelement vertex " + std::to_string(p.size()) + "\n";
  for (const char* a : {"x", "y", "z"}) s += std::string("property ") + type + " " + a + "\n";
  s += "end_header\n";
  for (const auto& v : p) s += v[0] + " " + v[1] + " " + v[2] + "\n";
  return s;
}

// Frame f's values as T (double or float; -0.0 bits included), little-endian, appended to s.
template <typename T>
std::string with_values(std::string s, size_t f) {
  for (const auto& v : frame_text(f))
    for (const std::string& x : v) {
      const T d = static_cast<T>(std::stod(x));
      char b[sizeof(T)];
      std::memcpy(b, &d, sizeof(T));
      s.append(b, sizeof(T));
    }
  return s;
}

// A binary little-endian PLY of double x y z.
std::string double_ply(size_t f) {
  return with_values<double>(
      "ply\nformat binary_little_endian 1.0\nelement vertex " +
          std::to_string(frame_text(f).size()) +
          "\nproperty double x\nproperty double y\nproperty double z\nend_header\n",
      f);
}

std::string pcd_head(size_t n, int size, const char* data) {
  const std::string z = std::to_string(size);
  return "# .PCD v0.7 - Point Cloud Data file format\nVERSION 0.7\nFIELDS x y z\nSIZE " + z + " " +
         z + " " + z + "\nTYPE F F F\nCOUNT 1 1 1\nWIDTH " + std::to_string(n) +
         "\nHEIGHT 1\nVIEWPOINT 0 0 0 1 0 0 0\nPOINTS " + std::to_string(n) + "\nDATA " + data +
         "\n";
}

std::string ascii_pcd(size_t f, int size) {
  const auto p = frame_text(f);
  std::string s = pcd_head(p.size(), size, "ascii");
  for (const auto& v : p) s += v[0] + " " + v[1] + " " + v[2] + "\n";
  return s;
}

// A binary PCD of float32 x y z (the values rounded to float32).
std::string binary_pcd(size_t f) {
  return with_values<float>(pcd_head(frame_text(f).size(), 4, "binary"), f);
}

void put(const std::string& path, const std::string& text) {
  capz::write_file(path, std::vector<uint8_t>(text.begin(), text.end()), true);
}

// Compresses `in` (a folder or one file) losslessly and expects `mode`, every frame file back byte
// for byte, and the decoded coordinates bit for bit the reader's (-0.0 included).
void expect_kept(const std::string& in, const std::string& mode, const capz_test::TempDir& tmp) {
  SCOPED_TRACE(in);
  std::unique_ptr<capz::FrameSource> src = capz::open_frames(in);
  capz::CompressOptions o;
  o.lossless = true;
  capz::CompressStats st;
  const std::string z = tmp.file("nz.capz");
  capz::compress_stream(*src, o, z, true, &st);
  EXPECT_TRUE(st.lossless);
  EXPECT_EQ(st.mode, mode);
  const std::string out =
      tmp.file(fs::is_directory(in) ? "back" : "back" + fs::path(in).extension().string());
  fs::remove_all(out);
  capz::rebuild_original(z, out, true);
  if (fs::is_directory(in)) {
    for (const auto& e : fs::directory_iterator(in)) {
      const std::string n = e.path().filename().string();
      EXPECT_EQ(capz::read_file(out + "/" + n), capz::read_file(in + "/" + n)) << n;
    }
  } else {
    EXPECT_EQ(capz::read_file(out), capz::read_file(in));
  }
  EXPECT_EQ(capz::rebuilds_file(z, in), "");
  const capz::Take a = capz::read_take(in);
  const std::vector<uint8_t> bytes = capz::read_file(z);
  const capz::Take b = capz::decompress(bytes.data(), bytes.size());
  ASSERT_EQ(a.xyz.size(), b.xyz.size());
  size_t negative = 0;
  for (size_t i = 0; i < a.xyz.size(); ++i) {
    negative += a.xyz[i] == 0 && std::signbit(a.xyz[i]);
    EXPECT_EQ(std::memcmp(&a.xyz[i], &b.xyz[i], 8), 0) << "coordinate " << i << ": " << b.xyz[i];
  }
  EXPECT_GT(negative, 0u);  // the reader gives -0.0 to the coder
}

struct Form {
  const char* name;
  const char* ext;
  std::string (*file)(size_t f);
  const char* mode;  // the lossless mode the encoder settles on
};

const Form kForms[] = {
    {"ply_ascii_double", ".ply", [](size_t f) { return ascii_ply(f, "double"); }, "decimal-grid"},
    {"ply_le_double", ".ply", double_ply, "decimal-grid"},
    {"pcd_ascii_f8", ".pcd", [](size_t f) { return ascii_pcd(f, 8); }, "decimal-grid"},
    {"pcd_ascii_f4", ".pcd", [](size_t f) { return ascii_pcd(f, 4); }, "float32-bits"},
    {"pcd_binary_f4", ".pcd", binary_pcd, "float32-bits"},
};

}  // namespace

TEST(NegativeZeroLossless, RaggedFoldersComeBackByteForByte) {
  for (const Form& form : kForms) {
    capz_test::TempDir tmp("capz_nz_folder");
    const std::string dir = tmp.file(form.name);
    fs::create_directories(dir);
    for (size_t f = 0; f < 3; ++f) put(dir + "/" + std::to_string(f) + form.ext, form.file(f));
    ASSERT_TRUE(capz::read_take(dir).ragged()) << dir;
    expect_kept(dir, form.mode, tmp);
  }
}

TEST(NegativeZeroLossless, SingleFilesComeBackByteForByte) {
  for (const Form& form : kForms) {
    capz_test::TempDir tmp("capz_nz_single");
    const std::string one = tmp.file(std::string(form.name) + form.ext);
    put(one, form.file(2));
    expect_kept(one, form.mode, tmp);
  }
}

// A ragged take built in memory: float64 coordinates on a decimal grid, with -0.0.
capz::Take memory_take() {
  capz::Take t;
  t.format = capz::Format::kPCDFolder;
  t.frames = 2;
  t.frame_offsets = {0, 2, 5};
  t.xyz = {-0.0, 0.5, 1.25, 2.5, -0.0, -0.0, 3.75, 0.0, -1.5, -0.0, 4.0, 0.25, 1.0, 2.0, 3.0};
  t.valid = {1, 1, 0, 1, 1};
  t.xyz[6] = t.xyz[7] = t.xyz[8] = 0;  // the gap's
  return t;
}

TEST(NegativeZeroLossless, TakeInMemoryKeepsItsSigns) {
  const capz::Take t = memory_take();
  capz::CompressOptions o;
  o.lossless = true;
  capz::CompressStats st;
  const std::vector<uint8_t> z = capz::compress(t, o, &st);
  EXPECT_EQ(st.mode, "decimal-grid");
  const capz::Take b = capz::decompress(z.data(), z.size());
  ASSERT_EQ(b.xyz.size(), t.xyz.size());
  for (size_t i = 0; i < t.xyz.size(); ++i) {
    if (!t.valid[i / 3]) continue;
    EXPECT_EQ(std::memcmp(&t.xyz[i], &b.xyz[i], 8), 0) << "coordinate " << i << ": " << b.xyz[i];
  }
}

// The list's entries changed under a recomputed CRC: a listed coordinate that is no zero, one of a
// gap, one beyond the window and a count above 3 total are corrupt, naming SCNW.
TEST(NegativeZeroLossless, DamagedListIsCorruptNamingScnw) {
  capz::CompressOptions o;
  o.lossless = true;
  const std::vector<uint8_t> z = capz::compress(memory_take(), o);
  const size_t at = capz_test::find_chunk(z, "SCNW");
  ASSERT_NE(at, std::string::npos);
  // The payload: window 0, total 5, gaps byte 0, count 4, then the gaps 0 (j 0), 3 (j 4), 0 (j 5)
  // and 3 (j 9); each change below is one byte: a count of 16, a first j of 1 (0.5), 6 (the gap),
  // 14 and 15.
  const size_t p = at + 8;
  ASSERT_EQ(z[p], 0);
  ASSERT_EQ(z[p + 1], 5);
  ASSERT_EQ(z[p + 2], 0);
  ASSERT_EQ(z[p + 3], 4);
  ASSERT_EQ(z[p + 4], 0);
  const struct {
    size_t offset;
    uint8_t value;
  } damage[] = {{p + 3, 16}, {p + 4, 1}, {p + 4, 6}, {p + 4, 14}, {p + 4, 15}};
  for (const auto& d : damage) {
    std::vector<uint8_t> b = z;
    b[d.offset] = d.value;
    capz_test::fix_crc(&b, at);
    try {
      capz::decompress(b.data(), b.size());
      ADD_FAILURE() << "byte " << d.offset - p << " = " << int{d.value} << " decoded";
    } catch (const capz::Error& e) {
      EXPECT_EQ(e.code(), capz::ErrorCode::kCorrupt) << e.what();
      EXPECT_NE(std::string(e.what()).find("SCNW"), std::string::npos) << e.what();
    }
  }
}
