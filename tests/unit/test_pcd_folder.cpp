// PCD folder reader/writer on small synthetic folders: natural order, point-count mismatch, NaN
// gaps, the three encodings, lying headers, empty folders, no partial output.
#include <gtest/gtest.h>

#include <algorithm>
#include <array>
#include <cmath>
#include <filesystem>
#include <fstream>
#include <string>

#include "capz/codec.h"
#include "capz/error.h"
#include "capz/io.h"
#include "coding/meta.h"
#include "io/natural_sort.h"
#include "test_util.h"

namespace fs = std::filesystem;
using capz::ErrorCode;
using capz_test::expect_same_samples;
using capz_test::TempDir;

namespace {

// An ASCII PCD frame with the given points (NaN allowed).
void write_ascii_pcd(const fs::path& file, const std::vector<std::array<float, 3>>& pts) {
  std::ofstream o(file);
  o << "# .PCD v0.7\nVERSION 0.7\nFIELDS x y z\nSIZE 4 4 4\nTYPE F F F\nCOUNT 1 1 1\nWIDTH "
    << pts.size() << "\nHEIGHT 1\nVIEWPOINT 0 0 0 1 0 0 0\nPOINTS " << pts.size()
    << "\nDATA ascii\n";
  o.precision(9);
  for (const auto& p : pts) {
    for (int a = 0; a < 3; ++a) {
      if (std::isnan(p[a])) {
        o << "nan";
      } else {
        o << p[a];
      }
      o << (a < 2 ? " " : "\n");
    }
  }
}

capz::Take make_take(size_t frames, size_t points) {
  capz::Take t;
  t.resize(frames, points);
  for (size_t f = 0; f < frames; ++f)
    for (size_t p = 0; p < points; ++p) {
      float v[3] = {static_cast<float>(f) * 0.5f + static_cast<float>(p) / 3.0f,
                    -static_cast<float>(p) * 1.25f, 1000.0f + static_cast<float>(f) / 7.0f};
      for (int a = 0; a < 3; ++a) t.at(f, p)[a] = v[a];
      t.valid[f * points + p] = (f + p) % 5 != 3;
    }
  return t;
}

ErrorCode read_error(const std::string& dir, std::string* msg = nullptr) {
  return capz_test::error_of([&] { capz::read_pcd_folder(dir); }, msg);
}

}  // namespace

TEST(NaturalSort, NumbersCompareByValue) {
  std::vector<std::string> v = {"frame_10.pcd", "frame_2.pcd",   "frame_1.pcd",  "frame_02.pcd",
                                "a.pcd",        "frame_100.pcd", "frame_9b.pcd", "frame_9a.pcd"};
  std::sort(v.begin(), v.end(), capz::natural_less);
  EXPECT_EQ(v, (std::vector<std::string>{"a.pcd", "frame_1.pcd", "frame_02.pcd", "frame_2.pcd",
                                         "frame_9a.pcd", "frame_9b.pcd", "frame_10.pcd",
                                         "frame_100.pcd"}));
  EXPECT_FALSE(capz::natural_less("x", "x"));
}

// Timestamps printed with their trailing zeros dropped: the digits after a point that follows 9
// digits or more are a fraction (they sorted .8, .98, .781, .881 by value); a number after a
// letter or a short number and a '.' is still a number ("frame.9" before "frame.10", "take1.9"
// before "take1.10"); the order stays total.
TEST(NaturalSort, DigitsAfterANumbersPointAreAFraction) {
  std::vector<std::string> v = {"1691031766.98.pcd",  "1691031766.8.pcd",  "1691031766.881.pcd",
                                "1691031766.781.pcd", "1691031767.05.pcd", "1691031766.80.pcd"};
  std::sort(v.begin(), v.end(), capz::natural_less);
  EXPECT_EQ(v, (std::vector<std::string>{"1691031766.781.pcd", "1691031766.8.pcd",
                                         "1691031766.80.pcd", "1691031766.881.pcd",
                                         "1691031766.98.pcd", "1691031767.05.pcd"}));
  std::vector<std::string> w = {"frame.10.pcd", "frame.9.pcd", "take1.10.pcd", "take1.9.pcd"};
  std::sort(w.begin(), w.end(), capz::natural_less);
  EXPECT_EQ(
      w, (std::vector<std::string>{"frame.9.pcd", "frame.10.pcd", "take1.9.pcd", "take1.10.pcd"}));
  EXPECT_NE(capz::natural_less("1.8", "1.80"), capz::natural_less("1.80", "1.8"));
}

TEST(PcdFolder, ReadsFramesInNaturalOrderWithNanGaps) {
  TempDir d;
  const float nan = std::nanf("");
  write_ascii_pcd(d.path() / "frame_10.pcd", {{{10, 0, 0}}, {{1, 2, 3}}});
  write_ascii_pcd(d.path() / "frame_2.pcd", {{{2, 0, 0}}, {{nan, 2, 3}}});
  write_ascii_pcd(d.path() / "frame_1.pcd", {{{1, 0, 0}}, {{0.1f, 0.2f, 0.3f}}});
  std::ofstream(d.path() / "notes.txt") << "not a frame\n";
  capz::Take t = capz::read_pcd_folder(d.path().string());
  EXPECT_EQ(t.format, capz::Format::kPCDFolder);
  ASSERT_EQ(t.frames, 3u);
  ASSERT_EQ(t.points, 2u);
  EXPECT_EQ(t.at(0, 0)[0], 1.0);
  EXPECT_EQ(t.at(1, 0)[0], 2.0);
  EXPECT_EQ(t.at(2, 0)[0], 10.0);
  EXPECT_EQ(t.at(0, 1)[0], static_cast<double>(0.1f));
  EXPECT_FALSE(t.is_valid(1, 1));
  EXPECT_EQ(t.gap_samples(), 1u);
  ASSERT_TRUE(t.pcd);
  EXPECT_EQ(t.pcd->frame_names,
            (std::vector<std::string>{"frame_1.pcd", "frame_2.pcd", "frame_10.pcd"}));
  EXPECT_EQ(t.pcd->encoding, "ascii");
  EXPECT_TRUE(t.labels.empty());  // frame files' points have no labels (take.h)
}

// A fixed PCD folder's points have no labels, read or decoded, and META lists the N empty
// labels every stream since 1.0 has (FORMAT.md 5.2): the same bytes as a take that has them.
TEST(PcdFolder, GivenFramesOfOneCountThenNoLabelsReadOrDecodedAndMetaAsBefore) {
  TempDir d;
  write_ascii_pcd(d.path() / "f1.pcd", {{{1, 0, 0}}, {{1, 2, 3}}, {{0, 0, 1}}});
  write_ascii_pcd(d.path() / "f2.pcd", {{{1, 0, 1}}, {{1, 2, 4}}, {{0, 1, 1}}});
  const capz::Take t = capz::read_pcd_folder(d.path().string());
  ASSERT_FALSE(t.ragged());
  ASSERT_EQ(t.points, 3u);
  EXPECT_TRUE(t.labels.empty());
  capz::Take listed = t;
  listed.labels.assign(t.points, std::string());
  EXPECT_EQ(capz::encode_meta_raw(t, false), capz::encode_meta_raw(listed, false));
  capz::CompressOptions o;
  o.max_error = 0.001;
  const std::vector<uint8_t> z = capz::compress(t, o);
  EXPECT_EQ(z, capz::compress(listed, o));
  const capz::Take back = capz::decompress(z.data(), z.size());
  EXPECT_TRUE(back.labels.empty());
  EXPECT_EQ(back.points, t.points);
  // Another source's empty labels stay as read: a take of the same points without a format.
  capz::Take plain = t;
  plain.format = capz::Format::kUnknown;
  plain.pcd.reset();
  plain.labels.assign(t.points, std::string());
  const std::vector<uint8_t> zp = capz::compress(plain, o);
  EXPECT_EQ(capz::decompress(zp.data(), zp.size()).labels, plain.labels);
}

TEST(PcdFolder, PointCountsThatDifferGiveARaggedTake) {
  TempDir d;
  write_ascii_pcd(d.path() / "f1.pcd", {{{1, 0, 0}}, {{1, 2, 3}}});
  write_ascii_pcd(d.path() / "f2.pcd", {{{1, 0, 0}}, {{1, 2, 3}}});
  write_ascii_pcd(d.path() / "f3.pcd", {{{1, 0, 0}}});
  write_ascii_pcd(d.path() / "f4.pcd", {{{4, 5, 6}}});
  const capz::Take t = capz::read_pcd_folder(d.path().string());
  ASSERT_TRUE(t.ragged());
  EXPECT_EQ(t.frame_offsets, (std::vector<size_t>{0, 2, 4, 5, 6}));
  EXPECT_EQ(t.points, 0u);
  EXPECT_TRUE(t.labels.empty());
  EXPECT_EQ(t.at(3, 0)[2], 6.0);
}

TEST(PcdFolder, EmptyDirectoryAndMissingPathAreClearErrors) {
  TempDir d;
  std::string msg;
  EXPECT_EQ(read_error(d.path().string(), &msg), ErrorCode::kNotOurFormat);
  EXPECT_NE(msg.find("no .pcd files"), std::string::npos) << msg;
  EXPECT_EQ(read_error((d.path() / "nope").string(), &msg), ErrorCode::kUsage);
}

TEST(PcdFolder, LyingHeadersAreRejectedBeforeAllocating) {
  TempDir d;
  // Binary body of 12 bytes, header announcing a billion points.
  {
    std::ofstream o(d.path() / "a.pcd", std::ios::binary);
    o << "VERSION 0.7\nFIELDS x y z\nSIZE 4 4 4\nTYPE F F F\nCOUNT 1 1 1\nWIDTH 1000000000\n"
         "HEIGHT 1\nPOINTS 1000000000\nDATA binary\n";
    o.write("\0\0\0\0\0\0\0\0\0\0\0\0", 12);
  }
  std::string msg;
  EXPECT_EQ(read_error(d.path().string(), &msg), ErrorCode::kCorrupt);
  EXPECT_NE(msg.find("a.pcd: PCD header announces 1000000000 points"), std::string::npos) << msg;
  // Compressed body claiming a huge uncompressed size.
  {
    std::ofstream o(d.path() / "a.pcd", std::ios::binary | std::ios::trunc);
    o << "VERSION 0.7\nFIELDS x y z\nSIZE 4 4 4\nTYPE F F F\nCOUNT 1 1 1\nWIDTH 100000000\n"
         "HEIGHT 1\nPOINTS 100000000\nDATA binary_compressed\n";
    const unsigned char sizes[8] = {4, 0, 0, 0, 0, 0x84, 0xD7, 0x47};  // 4, 1.2e9
    o.write(reinterpret_cast<const char*>(sizes), 8);
    o.write("\0\0\0\0", 4);
  }
  EXPECT_EQ(read_error(d.path().string(), &msg), ErrorCode::kCorrupt);
  // WIDTH x HEIGHT past 2^64 (2^40 x 2^24 wraps to 0 points): refused by capz's own check.
  std::ofstream(d.path() / "a.pcd", std::ios::trunc)
      << "VERSION 0.7\nFIELDS x y z\nSIZE 4 4 4\nTYPE F F F\nWIDTH 1099511627776\n"
         "HEIGHT 16777216\nDATA binary\n";
  EXPECT_EQ(read_error(d.path().string(), &msg), ErrorCode::kCorrupt);
  EXPECT_NE(msg.find("WIDTH x HEIGHT is absurd"), std::string::npos) << msg;
  // A NUL as a TYPE (found by the pcd_header fuzz target: strchr("FIU", 0) matched the
  // terminator), named in full in the message.
  {
    std::ofstream o(d.path() / "a.pcd", std::ios::binary | std::ios::trunc);
    o << "VERSION 0.7\nFIELDS x y z rgb\nSIZE 4 4 4 4\nTYPE F F F ";
    o.put('\0');
    o << "\nWIDTH 1\nHEIGHT 1\nDATA binary\n";
    o.write("\0\0\0\0\0\0\0\0\0\0\0\0\0\0\0\0", 16);
  }
  EXPECT_EQ(read_error(d.path().string(), &msg), ErrorCode::kCorrupt);
  EXPECT_NE(msg.find("bad TYPE '\\0'"), std::string::npos) << msg;
  // Not a PCD at all.
  std::ofstream(d.path() / "a.pcd", std::ios::trunc) << "hello\n";
  EXPECT_EQ(read_error(d.path().string(), &msg), ErrorCode::kNotOurFormat);
  // Truncated binary body.
  {
    std::ofstream o(d.path() / "a.pcd", std::ios::binary | std::ios::trunc);
    o << "VERSION 0.7\nFIELDS x y z\nSIZE 4 4 4\nTYPE F F F\nWIDTH 2\nHEIGHT 1\nPOINTS 2\n"
         "DATA binary\n";
    o.write("\0\0\0\0\0\0\0\0\0\0\0\0\0\0", 14);
  }
  EXPECT_EQ(read_error(d.path().string(), &msg), ErrorCode::kCorrupt);
  // ASCII bodies: a bad token, a short line, missing points (PCL would read zeros).
  const std::string head =
      "VERSION 0.7\nFIELDS x y z\nSIZE 4 4 4\nTYPE F F F\nWIDTH 3\nHEIGHT 1\nPOINTS 3\n"
      "DATA ascii\n";
  std::ofstream(d.path() / "a.pcd", std::ios::trunc) << head << "1 2 3\n4 5 abc\n7 8 9\n";
  EXPECT_EQ(read_error(d.path().string(), &msg), ErrorCode::kCorrupt);
  EXPECT_NE(msg.find("line 2: 'abc' is not a number"), std::string::npos) << msg;
  std::ofstream(d.path() / "a.pcd", std::ios::trunc) << head << "10 20 30\n40 50\n70 80 90\n";
  EXPECT_EQ(read_error(d.path().string(), &msg), ErrorCode::kCorrupt);
  EXPECT_NE(msg.find("line 2 holds 2 values, the header needs 3"), std::string::npos) << msg;
  std::ofstream(d.path() / "a.pcd", std::ios::trunc) << head << "1 2 3\n4 5 6\n\n\n\n\n\n";
  EXPECT_EQ(read_error(d.path().string(), &msg), ErrorCode::kCorrupt);
  EXPECT_NE(msg.find("ASCII body holds 2 points, the header says 3"), std::string::npos) << msg;
  std::ofstream(d.path() / "a.pcd", std::ios::trunc) << head << "1 2 3\r\n4 5 6\r\nnan nan nan\r\n";
  capz::Take t = capz::read_pcd_folder(d.path().string());
  EXPECT_EQ(t.at(0, 1)[2], 6.0);
  EXPECT_FALSE(t.is_valid(0, 2));
}

TEST(PcdFolder, AllThreeEncodingsRoundTripExactly) {
  capz::Take t = make_take(12, 37);
  for (const char* enc : {"ascii", "binary", "binary_compressed"}) {
    TempDir d;
    std::string out = (d.path() / "seq").string();
    capz::WriteOptions o;
    o.pcd_encoding = enc;
    capz::write_pcd_folder(t, out, o);
    capz::Take u = capz::read_pcd_folder(out);
    SCOPED_TRACE(enc);
    expect_same_samples(t, u);
    EXPECT_EQ(u.pcd->encoding, enc);
    EXPECT_EQ(u.pcd->frame_names.front(), "frame_000001.pcd");
    EXPECT_EQ(u.pcd->frame_names.back(), "frame_000012.pcd");
    // Writing a PCD take back keeps its frame names.
    std::string out2 = (d.path() / "seq2").string();
    capz::write_pcd_folder(u, out2, o);
    EXPECT_TRUE(fs::exists(fs::path(out2) / "frame_000012.pcd"));
  }
}

TEST(PcdFolder, DoublesThatAreNotFloatsAreKeptExactly) {
  capz::Take t = make_take(3, 4);
  t.at(0, 0)[0] = 0.1;  // not a float
  TempDir d;
  std::string out = (d.path() / "seq").string();
  capz::write_pcd_folder(t, out);
  capz::Take u = capz::read_pcd_folder(out);
  expect_same_samples(t, u);
}

TEST(PcdFolder, WriterRefusesExistingOutputAndBadEncodingWithoutLeavingFiles) {
  capz::Take t = make_take(2, 3);
  TempDir d;
  std::string out = (d.path() / "seq").string();
  capz::write_pcd_folder(t, out);
  try {
    capz::write_pcd_folder(t, out);
    FAIL() << "overwrote without permission";
  } catch (const capz::Error& e) {
    EXPECT_EQ(e.code(), ErrorCode::kUsage);
  }
  capz::WriteOptions o;
  o.pcd_encoding = "zip";
  try {
    capz::write_pcd_folder(t, (d.path() / "other").string(), o);
    FAIL() << "accepted encoding zip";
  } catch (const capz::Error& e) {
    EXPECT_EQ(e.code(), ErrorCode::kInvalidParameter);
  }
  o.pcd_encoding = "binary";
  o.overwrite = true;
  capz::Take small = make_take(1, 3);
  capz::write_pcd_folder(small, out, o);
  EXPECT_EQ(capz::read_pcd_folder(out).frames, 1u);
  // Only the two outputs' directories ever existed: no temporaries left.
  EXPECT_EQ(std::distance(fs::directory_iterator(d.path()), fs::directory_iterator()), 1);
}

// holds_frame_files (the CLI's batch walk finds take folders with it): regular .pcd, .ply or
// .bin files, any case, count; hidden files, other extensions and folders named like frames do
// not; a path that is no directory holds none.
TEST(PcdFolder, GivenFolderContentsThenHoldsFrameFilesCountsOnlyVisibleFrameFiles) {
  TempDir d;
  EXPECT_FALSE(capz::holds_frame_files(d.file("absent")));
  EXPECT_FALSE(capz::holds_frame_files(d.path().string()));
  std::ofstream(d.file("._0.pcd")) << "Mac OS X";
  std::ofstream(d.file("notes.txt")) << "x";
  fs::create_directories(d.path() / "sub.ply");
  EXPECT_FALSE(capz::holds_frame_files(d.path().string()));
  std::ofstream(d.file("0.pcd.bak")) << "x";
  EXPECT_FALSE(capz::holds_frame_files(d.path().string()));
  std::ofstream(d.file("frame.BIN")) << "";
  EXPECT_TRUE(capz::holds_frame_files(d.path().string()));
  EXPECT_FALSE(capz::holds_frame_files(d.file("frame.BIN")));
}

// Point field names a frame file cannot hold (a field named x, two of one name, a blank in a
// name): refused by name where a take is compressed or written, nothing left behind (a Python
// take with a field named x was written as a PCD folder with two x fields and crashed the
// interpreter; one named "a b" gave files capz could not read back).
TEST(PcdFolder, GivenPointFieldNamesAFileCannotHoldThenCompressAndWriteRefuseThem) {
  for (const std::string bad : {"x", "a b", "tab\there", "dup"}) {
    SCOPED_TRACE(bad);
    capz::Take t = make_take(2, 5);
    capz::PointAttribute a;
    a.name = bad;
    a.type = 'F';
    a.size = 4;
    a.data.assign(2 * 5 * 4, 0);
    t.attributes.push_back(a);
    if (bad == "dup") t.attributes.push_back(a);
    EXPECT_FALSE(capz::point_field_fault(t).empty());
    TempDir d;
    std::string msg;
    EXPECT_EQ(capz_test::error_of([&] { capz::write_pcd_folder(t, d.file("out")); }, &msg),
              ErrorCode::kInvalidParameter);
    EXPECT_NE(msg.find("would not read back"), std::string::npos) << msg;
    EXPECT_FALSE(fs::exists(d.file("out")));
    capz::CompressOptions o;
    o.max_error = 0.001;
    EXPECT_EQ(capz_test::error_of([&] { capz::compress(t, o); }, &msg),
              ErrorCode::kInvalidParameter);
  }
  capz::Take ok = make_take(2, 5);
  EXPECT_TRUE(capz::point_field_fault(ok).empty());
}

// A folder of frames is readable by others, as its files are: 0755 and 0644 (the temporary
// folder it is renamed from was 0700, so restored frames were the owner's alone).
TEST(PcdFolder, AWrittenFolderIsReadableByOthersAsItsFiles) {
  TempDir d;
  capz::write_pcd_folder(make_take(2, 3), d.file("seq"));
  const fs::perms folder = fs::status(d.file("seq")).permissions();
  EXPECT_EQ(folder & fs::perms::all, fs::perms(0755));
  for (const fs::directory_entry& e : fs::directory_iterator(d.file("seq")))
    EXPECT_EQ(e.status().permissions() & fs::perms::all, fs::perms(0644)) << e.path();
}
