// TRC reader/writer on small synthetic files: layout variants, gaps, warnings, errors, round trip.
#include <gtest/gtest.h>

#include <cmath>
#include <filesystem>
#include <fstream>
#include <string>

#include "capz/error.h"
#include "capz/io.h"
#include "io/text_number.h"
#include "test_util.h"

namespace fs = std::filesystem;
using capz::ErrorCode;
using capz_test::expect_same_samples;
using capz_test::TempDir;

namespace {

capz::Take parse(const std::string& text) {
  return capz::read_trc_bytes(reinterpret_cast<const uint8_t*>(text.data()), text.size(), "t.trc");
}

ErrorCode parse_error(const std::string& text, std::string* msg = nullptr) {
  return capz_test::error_of([&] { parse(text); }, msg);
}

bool has_warning(const capz::Take& t, const std::string& needle) {
  for (const auto& w : t.warnings)
    if (w.find(needle) != std::string::npos) return true;
  return false;
}

const char kTabFile[] =
    "PathFileType\t4\t(X/Y/Z)\twalk.trc\n"
    "DataRate\tCameraRate\tNumFrames\tNumMarkers\tUnits\tOrigDataRate\tOrigDataStartFrame\t"
    "OrigNumFrames\n"
    "100.00\t120.00\t3\t2\tmm\t100.00\t7\t3\n"
    "Frame#\tTime\tLASI\t\t\tRASI\t\t\t\n"
    "\t\tX1\tY1\tZ1\tX2\tY2\tZ2\n"
    "\n"
    "7\t0.060\t1.25\t-2.5\t3.125\t\t\t\n"
    "8\t0.070\tNaN\tNaN\tNaN\t4.000\t5.5\t-6.0\n"
    "9\t0.080\t10.5\t11\t12\n";

}  // namespace

TEST(Trc, ReadsTabSeparatedFileWithGapsAndShortRows) {
  capz::Take t = parse(kTabFile);
  EXPECT_EQ(t.format, capz::Format::kTRC);
  ASSERT_EQ(t.frames, 3u);
  ASSERT_EQ(t.points, 2u);
  EXPECT_EQ(t.labels, (std::vector<std::string>{"LASI", "RASI"}));
  EXPECT_DOUBLE_EQ(t.rate, 100.0);
  EXPECT_EQ(t.units, "mm");
  EXPECT_EQ(t.first_frame, 7);
  EXPECT_TRUE(t.is_valid(0, 0));
  EXPECT_FALSE(t.is_valid(0, 1));  // blank fields
  EXPECT_FALSE(t.is_valid(1, 0));  // NaN
  EXPECT_TRUE(t.is_valid(1, 1));
  EXPECT_TRUE(t.is_valid(2, 0));
  EXPECT_FALSE(t.is_valid(2, 1));  // row ends early
  EXPECT_EQ(t.at(0, 0)[0], 1.25);
  EXPECT_EQ(t.at(0, 0)[1], -2.5);
  EXPECT_EQ(t.at(0, 0)[2], 3.125);
  EXPECT_EQ(t.at(1, 1)[2], -6.0);
  ASSERT_TRUE(t.trc);
  EXPECT_EQ(t.trc->decimals, 3);
  EXPECT_EQ(t.trc->time_decimals, 3);
  EXPECT_DOUBLE_EQ(t.trc->camera_rate, 120.0);
  EXPECT_EQ(t.trc->orig_data_start_frame, 7);
  EXPECT_EQ(t.trc->frame_numbers, (std::vector<int64_t>{7, 8, 9}));
  EXPECT_EQ(t.trc->times, (std::vector<double>{0.06, 0.07, 0.08}));
  EXPECT_EQ(t.trc->path_file_type_line, "PathFileType\t4\t(X/Y/Z)\twalk.trc");
  EXPECT_TRUE(has_warning(t, "1 of 3 rows end before the last marker")) << t.warnings.size();
  EXPECT_EQ(t.gap_samples(), 3u);
}

TEST(Trc, ReadsSpaceSeparatedCrlfFileAndWarnsOnCounts) {
  std::string text =
      "PathFileType 4 (X/Y/Z) a.trc\r\n"
      "DataRate CameraRate NumFrames NumMarkers Units OrigDataRate OrigDataStartFrame "
      "OrigNumFrames\r\n"
      "60 60 900 3 m 60 1 900\r\n"
      "Frame# Time A B\r\n"
      "X1 Y1 Z1 X2 Y2 Z2\r\n"
      "1 0 0.1 0.2 0.3 1e-3 nan 2\r\n"
      "2 0.0166 0.4 0.5 0.6 7 8 9\r\n";
  capz::Take t = parse(text);
  ASSERT_EQ(t.frames, 2u);
  ASSERT_EQ(t.points, 2u);
  EXPECT_EQ(t.units, "m");
  EXPECT_EQ(t.labels, (std::vector<std::string>{"A", "B"}));
  EXPECT_FALSE(t.is_valid(0, 1));
  EXPECT_EQ(t.at(1, 1)[0], 7.0);
  EXPECT_EQ(t.trc->decimals, -1);  // an exponent was seen
  EXPECT_TRUE(has_warning(t, "header says 900 frames, file holds 2"));
  EXPECT_TRUE(has_warning(t, "header says 3 markers, file holds 2"));
}

TEST(Trc, SkipsAUtf8ByteOrderMark) {
  capz::Take t = parse(std::string("\xEF\xBB\xBF") + kTabFile);
  EXPECT_EQ(t.points, 2u);
  EXPECT_EQ(t.trc->path_file_type_line, "PathFileType\t4\t(X/Y/Z)\twalk.trc");
}

TEST(Trc, DataWiderThanTheNamesAddsUnnamedPoints) {
  std::string text =
      "PathFileType\t4\t(X/Y/Z)\tx\n"
      "DataRate\tCameraRate\tNumFrames\tNumMarkers\tUnits\n"
      "400\t400\t2\t0\tmm\n"
      "Frame#\tTime\t\n"
      "\t\t\n"
      "\n"
      "1\t0.000\t1\t2\t3\t\n"
      "2\t0.0025\t\t\t\t4\t5\t6\t\n";
  capz::Take t = parse(text);
  ASSERT_EQ(t.points, 2u);
  EXPECT_EQ(t.labels, (std::vector<std::string>{"", ""}));
  EXPECT_TRUE(t.is_valid(0, 0));
  EXPECT_FALSE(t.is_valid(0, 1));
  EXPECT_FALSE(t.is_valid(1, 0));
  EXPECT_TRUE(t.is_valid(1, 1));
  EXPECT_TRUE(has_warning(t, "0 marker names for 2 markers"));
}

TEST(Trc, RejectsEmptyForeignAndTruncatedFiles) {
  std::string msg;
  EXPECT_EQ(parse_error("", &msg), ErrorCode::kNotOurFormat);
  EXPECT_NE(msg.find("t.trc: empty file"), std::string::npos) << msg;
  EXPECT_EQ(parse_error("hello world\n1 2 3\n"), ErrorCode::kNotOurFormat);
  EXPECT_EQ(parse_error("PathFileType\t4\n"), ErrorCode::kCorrupt);
  EXPECT_EQ(parse_error("PathFileType\t4\nDataRate\tNumFrames\n", &msg), ErrorCode::kCorrupt);
  EXPECT_NE(msg.find("file ends after line 2"), std::string::npos) << msg;
  EXPECT_EQ(parse_error("PathFileType\t4\nDataRate\tNumFrames\nabc\t3\n", &msg),
            ErrorCode::kCorrupt);
  EXPECT_NE(msg.find("DataRate 'abc' is not a number"), std::string::npos) << msg;
  EXPECT_EQ(parse_error("PathFileType\t4\nDataRate\n100\nNames\n", &msg), ErrorCode::kCorrupt);
  EXPECT_NE(msg.find("Frame#"), std::string::npos) << msg;
}

TEST(Trc, RejectsNonNumericFieldNamingLineAndColumn) {
  std::string text(kTabFile);
  text.replace(text.find("4.000"), 5, "4.0x0");
  std::string msg;
  EXPECT_EQ(parse_error(text, &msg), ErrorCode::kCorrupt);
  EXPECT_NE(msg.find("line 8, column 6: '4.0x0' is not a number"), std::string::npos) << msg;
}

TEST(Trc, RefusesRowsThatWouldExpandBeyondTheFileSize) {
  // One row 3000 markers wide followed by 100000 rows holding only a frame number: tiny on disk,
  // 300 million samples in memory.
  std::string text =
      "PathFileType\t4\nDataRate\tNumFrames\tNumMarkers\n100\t1\t1\nFrame#\tTime\tA\n\t\tX1\n1\t0";
  for (int i = 0; i < 3000; ++i) text += "\t1\t2\t3";
  text += "\n";
  for (int i = 0; i < 100000; ++i) text += "2\n";
  std::string msg;
  EXPECT_EQ(parse_error(text, &msg), ErrorCode::kCorrupt);
  EXPECT_NE(msg.find("far more than a file of"), std::string::npos) << msg;
}

TEST(Trc, WriteThenReadIsExactAndTextRoundTrips) {
  capz::Take t = parse(kTabFile);
  TempDir tmp;
  std::string out = (tmp.path() / "out.trc").string();
  capz::write_trc(t, out);
  capz::Take u = capz::read_trc(out);
  expect_same_samples(t, u);
  EXPECT_EQ(u.labels, t.labels);
  EXPECT_EQ(u.rate, t.rate);
  EXPECT_EQ(u.units, t.units);
  EXPECT_EQ(u.first_frame, t.first_frame);
  EXPECT_EQ(u.trc->times, t.trc->times);
  EXPECT_EQ(u.trc->frame_numbers, t.trc->frame_numbers);
  EXPECT_EQ(u.trc->camera_rate, t.trc->camera_rate);
  EXPECT_EQ(u.trc->decimals, 3);
  // Writing what was read back gives the same bytes.
  std::string out2 = (tmp.path() / "out2.trc").string();
  capz::write_trc(u, out2);
  std::ifstream a(out), b(out2);
  std::string sa((std::istreambuf_iterator<char>(a)), {}),
      sb((std::istreambuf_iterator<char>(b)), {});
  EXPECT_EQ(sa, sb);
  // Gaps are empty fields, values carry the source's three decimals, rows end with a tab (as
  // OpenSim writes them; its reader drops an empty last field).
  EXPECT_NE(sa.find("\n7\t0.060\t1.250\t-2.500\t3.125\t\t\t\t\n"), std::string::npos) << sa;
  EXPECT_EQ(sa.find("Frame#\tTime\tLASI\t\t\tRASI\t\t\n\t\tX1\tY1\tZ1\tX2\tY2\tZ2\n\n7\t"),
            sa.find("Frame#"));
}

TEST(Trc, WriterRefusesExistingOutputWithoutOverwrite) {
  capz::Take t = parse(kTabFile);
  TempDir tmp;
  std::string out = (tmp.path() / "out.trc").string();
  capz::write_trc(t, out);
  try {
    capz::write_trc(t, out);
    FAIL() << "overwrote without permission";
  } catch (const capz::Error& e) {
    EXPECT_EQ(e.code(), ErrorCode::kUsage);
  }
  capz::WriteOptions o;
  o.overwrite = true;
  EXPECT_NO_THROW(capz::write_trc(t, out, o));
  EXPECT_EQ(std::distance(fs::directory_iterator(tmp.path()), fs::directory_iterator()), 1);
}

TEST(Trc, WriterOfANonTrcTakeUsesShortestExactNumbers) {
  capz::Take t;
  t.resize(2, 1);
  t.rate = 50;
  t.units = "mm";
  t.labels = {""};
  double v[3] = {0.1 * 3, 1234.5678901234567, -7};
  for (int a = 0; a < 3; ++a) t.at(0, 0)[a] = v[a];
  t.valid[0] = 1;
  TempDir tmp;
  std::string out = (tmp.path() / "x.trc").string();
  capz::write_trc(t, out);
  capz::Take u = capz::read_trc(out);
  ASSERT_EQ(u.points, 1u);
  EXPECT_EQ(u.labels[0], "M1");
  for (int a = 0; a < 3; ++a) EXPECT_EQ(u.at(0, 0)[a], v[a]);
  EXPECT_FALSE(u.is_valid(1, 0));
  EXPECT_DOUBLE_EQ(u.trc->times[1], 0.02);
}

TEST(TextNumber, ShortestFixedAndParse) {
  EXPECT_EQ(capz::format_decimal(1.5, 3), "1.500");
  EXPECT_EQ(capz::format_decimal(100, 2), "100.00");
  EXPECT_EQ(capz::format_decimal(0.1, -1), "0.1");
  EXPECT_EQ(capz::format_decimal(-0.30000000000000004, 2), "-0.30000000000000004");
  EXPECT_EQ(capz::format_decimal(7, 0), "7");
  double x;
  EXPECT_TRUE(capz::parse_double("+1.25", &x));
  EXPECT_EQ(x, 1.25);
  EXPECT_TRUE(capz::parse_double("NaN", &x));
  EXPECT_TRUE(std::isnan(x));
  EXPECT_FALSE(capz::parse_double("1.2.3", &x));
  EXPECT_FALSE(capz::parse_double("", &x));
  EXPECT_FALSE(capz::parse_double("12abc", &x));
  for (double v : {1e-9, 123456.789, -0.0001, 5e-300, 3.14159265358979}) {
    double back;
    ASSERT_TRUE(capz::parse_double(capz::format_decimal(v, 2), &back));
    EXPECT_EQ(back, v);
  }
}

namespace {

// pyomeca's shape (tests/data/markers.trc there): commas, every line padded to the widest line's
// field count (2 + 3 x 2 = 8 here, as wide as line 2), a line of only commas after line 5, rows
// without a closing delimiter, gaps as empty fields.
const char kCommaFile[] =
    "PathFileType,4,(X/Y/Z),/home/u/walk.trc,,,,\n"
    "DataRate,CameraRate,NumFrames,NumMarkers,Units,OrigDataRate,OrigDataStartFrame,OrigNumFrames\n"
    "100,100,3,2,mm,100,0,3\n"
    "Frame#,Time,LASI,,,RASI,,\n"
    ",,X1,Y1,Z1,X2,Y2,Z2\n"
    ",,,,,,,\n"
    "1,0,733.7041,80.9832,191.8668,,,\n"
    "2,0.01, 733.4084 ,81.0119,191.8306,651.5213,313.561,179.0034\n"
    "3,0.02,,,,651.3495,313.6268,179.0038\n";

std::string slurp(const std::string& path) {
  std::ifstream f(path, std::ios::binary);
  return std::string((std::istreambuf_iterator<char>(f)), {});
}

}  // namespace

TEST(Trc, ReadsACommaSeparatedFileAsPyomecaWritesIt) {
  capz::Take t = parse(kCommaFile);
  ASSERT_EQ(t.frames, 3u);
  ASSERT_EQ(t.points, 2u);
  EXPECT_EQ(t.labels, (std::vector<std::string>{"LASI", "RASI"}));
  EXPECT_DOUBLE_EQ(t.rate, 100.0);
  EXPECT_EQ(t.units, "mm");
  EXPECT_EQ(t.trc->orig_data_start_frame, 0);
  EXPECT_EQ(t.trc->frame_numbers, (std::vector<int64_t>{1, 2, 3}));
  EXPECT_EQ(t.trc->times[2], 0.02);
  EXPECT_TRUE(t.is_valid(0, 0));
  EXPECT_FALSE(t.is_valid(0, 1));
  EXPECT_FALSE(t.is_valid(2, 0));
  EXPECT_EQ(t.at(1, 0)[0], 733.4084);  // blanks around a field are trimmed
  EXPECT_EQ(t.at(2, 1)[2], 179.0038);
  EXPECT_TRUE(t.warnings.empty()) << t.warnings.front();
  // Line 1's padding is cut (the residue codes it as a width, docs/FORMAT.md 14.5).
  EXPECT_EQ(t.trc->path_file_type_line, "PathFileType,4,(X/Y/Z),/home/u/walk.trc");
}

TEST(Trc, ABlankSeparatedLineOnePaddedWithCommasMakesACommaFile) {
  // OpenSim's constraintTest.trc starts "PathFileType  4\t(X/Y/Z) ..."; a spreadsheet without
  // tabs keeps such a line whole and pads it with commas.
  std::string text = kCommaFile;
  text.replace(0, text.find('\n'), "PathFileType  4 (X/Y/Z) walk.trc,,,,,,,");
  capz::Take t = parse(text);
  EXPECT_EQ(t.points, 2u);
  EXPECT_EQ(t.at(2, 1)[2], 179.0038);
  // Its padding is cut to the one comma that still says so.
  EXPECT_EQ(t.trc->path_file_type_line, "PathFileType  4 (X/Y/Z) walk.trc,");
}

TEST(Trc, ACommaInAFieldOfATabFileIsText) {
  // Only a comma right after PathFileType makes a comma-separated file.
  std::string text = kTabFile;
  text.replace(text.find("walk.trc"), 8, "walk,2.trc");
  capz::Take t = parse(text);
  EXPECT_EQ(t.points, 2u);
  EXPECT_EQ(t.labels[0], "LASI");
}

TEST(Trc, WriterKeepsTheCommaFormOrWritesTheOneAsked) {
  capz::Take t = parse(kCommaFile);
  TempDir tmp;
  const std::string kept = (tmp.path() / "kept.trc").string();
  capz::write_trc(t, kept);
  const std::string s = slurp(kept);
  // Every line padded to the same 8 fields; the PathFileType line as read.
  EXPECT_EQ(s.substr(0, s.find('\n')), "PathFileType,4,(X/Y/Z),/home/u/walk.trc,,,,");
  size_t lines = 0;
  for (size_t at = 0; at < s.size(); at = s.find('\n', at) + 1, ++lines) {
    const std::string line = s.substr(at, s.find('\n', at) - at);
    EXPECT_EQ(std::count(line.begin(), line.end(), ','), 7) << line;
  }
  EXPECT_EQ(lines, 9u);
  EXPECT_NE(s.find("\n,,,,,,,\n1,0.00,733.7041,80.9832,191.8668,,,\n"), std::string::npos) << s;
  capz::Take u = capz::read_trc(kept);
  expect_same_samples(t, u);
  EXPECT_EQ(u.trc->times, t.trc->times);

  // Asked for tabs: OpenSim's form, line 1 re-joined with tabs and its padding dropped.
  capz::WriteOptions o;
  o.trc_delimiter = '\t';
  const std::string tabs = (tmp.path() / "tabs.trc").string();
  capz::write_trc(t, tabs, o);
  const std::string st = slurp(tabs);
  EXPECT_EQ(st.find(','), std::string::npos) << st;
  EXPECT_EQ(st.substr(0, st.find('\n')), "PathFileType\t4\t(X/Y/Z)\t/home/u/walk.trc");
  capz::Take v = capz::read_trc(tabs);
  expect_same_samples(t, v);

  // And back to commas from the tab take: the same bytes as the comma take gave.
  o.trc_delimiter = ',';
  const std::string again = (tmp.path() / "again.trc").string();
  capz::write_trc(v, again, o);
  EXPECT_EQ(slurp(again), s);

  o.trc_delimiter = ';';
  EXPECT_EQ(capz_test::error_of([&] { capz::write_trc(t, (tmp.path() / "x.trc").string(), o); }),
            ErrorCode::kInvalidParameter);
}

TEST(Trc, CommaFormOfATakeWithoutTrcMetadataIsPaddedToItsWidestLine) {
  capz::Take t;
  t.resize(2, 1);
  t.rate = 50;
  t.units = "m";
  t.labels = {"A"};
  t.at(0, 0)[0] = 1.5;
  t.valid[0] = 1;
  TempDir tmp;
  capz::WriteOptions o;
  o.trc_delimiter = ',';
  const std::string out = (tmp.path() / "one.trc").string();
  capz::write_trc(t, out, o);
  const std::string s = slurp(out);
  // One point: line 2's eight keys are the widest line.
  EXPECT_EQ(s.substr(0, s.find('\n')), "PathFileType,4,(X/Y/Z),one.trc,,,,");
  EXPECT_NE(s.find("\n1,0.000,1.5,0,0,,,\n2,0.020,,,,,,\n"), std::string::npos) << s;
  capz::Take u = capz::read_trc(out);
  expect_same_samples(t, u);
}
