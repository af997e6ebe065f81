// The head of a comma-separated TRC in its TRCR payload (src/io/residue/trc_comma_head.h,
// docs/FORMAT.md 14.5): padding cut and given back by a width and exceptions, CRLF as a bit,
// row endings swapped; damaged fields refused as corrupt.
#include <gtest/gtest.h>

#include <string>
#include <vector>

#include "capz/error.h"
#include "capz/take.h"
#include "coding/bytes.h"
#include "io/residue/trc_comma_head.h"

using namespace capz;
using capz::residue::CommaLayout;

namespace {

// A take of 2 points with a comma line 1 (as the TRC reader keeps it: padding cut).
Take comma_take() {
  Take t;
  t.frames = 3;
  t.points = 2;
  t.rate = 100;
  t.units = "mm";
  t.labels = {"LASI", "RASI"};
  t.trc = std::make_shared<TRCExtra>();
  t.trc->path_file_type_line = "PathFileType,4,(X/Y/Z),walk.trc";
  return t;
}

std::vector<uint8_t> bytes_of(const std::string& s) {
  return {s.begin(), s.end()};
}

// Encodes `head`, checks it decodes to the same bytes and returns the payload.
std::vector<uint8_t> round_trip(const std::string& head, CommaLayout* layout) {
  const Take t = comma_take();
  const std::vector<uint8_t> payload =
      residue::encode_comma_head(bytes_of(head), t, "walk.trc", layout);
  ByteReader in(payload.data(), payload.size(), "head");
  CommaLayout back;
  const std::vector<uint8_t> got = residue::decode_comma_head(in, t, "walk.trc", 1 << 20, &back);
  EXPECT_EQ(std::string(got.begin(), got.end()), head);
  EXPECT_TRUE(in.at_end());
  EXPECT_EQ(back.width, layout->width);
  EXPECT_EQ(back.crlf, layout->crlf);
  return payload;
}

const char kPadded[] =
    "PathFileType,4,(X/Y/Z),walk.trc,,,,,\n"
    "DataRate,CameraRate,NumFrames,NumMarkers,Units,OrigDataRate,OrigDataStartFrame,OrigNumFrames,"
    "\n"
    "100,100,3,2,mm,100,0,3,\n"
    "Frame#,Time,LASI,,,RASI,,,\n"
    ",,X1,Y1,Z1,X2,Y2,Z2,\n"
    ",,,,,,,,\n";

std::string crlf(std::string s) {
  for (size_t i = s.find('\n'); i != std::string::npos; i = s.find('\n', i + 2)) s.insert(i, "\r");
  return s;
}

}  // namespace

TEST(TrcCommaHead, GivenLinesPaddedToOneWidthWhenCodedExpectTheWidthAndNoExceptions) {
  CommaLayout l;
  const std::vector<uint8_t> p = round_trip(kPadded, &l);
  EXPECT_EQ(l.width, 9u);  // one wider than the default 2 + 3 x 2 = 8 (a closing tab's field)
  EXPECT_FALSE(l.crlf);
  EXPECT_EQ(p[0] & 2, 0) << "no padding exceptions";
  // The cut text is capz's own header text but for line 3's spelling: a few bytes.
  EXPECT_LT(p.size(), 40u);
}

TEST(TrcCommaHead, GivenCrlfWhenCodedExpectTheBitAndTheSameSize) {
  CommaLayout lf, cr;
  const size_t lf_size = round_trip(kPadded, &lf).size();
  const std::vector<uint8_t> p = round_trip(crlf(kPadded), &cr);
  EXPECT_TRUE(cr.crlf);
  EXPECT_EQ(p[0] & 1, 1);
  EXPECT_LE(p.size(), lf_size + 1);
}

TEST(TrcCommaHead, GivenOddLinesWhenCodedExpectExceptionsAndTheSameBytes) {
  CommaLayout l;
  // A line padded short, one without padding, a carriage return inside the padding, blank lines
  // empty and of commas, and a last part without a line feed.
  std::string head = kPadded;
  head.replace(head.find("100,100,3,2,mm,100,0,3,"), 23, "100,100,3,2,mm,100,0,3,,,,,");
  head += "\n,,\r,\n,,,,,,,,,,,,,";
  const std::vector<uint8_t> p = round_trip(head, &l);
  EXPECT_EQ(p[0] & 2, 2) << "padding exceptions";
  round_trip("PathFileType,4,(X/Y/Z),walk.trc", &l);  // no line at all
  round_trip("", &l);
}

TEST(TrcCommaHead, EndingsSwapBothWays) {
  CommaLayout l;
  l.width = 4;
  l.crlf = true;
  const std::string blank = "\r\n,,,\r\n";
  EXPECT_EQ(residue::swap_ending("\n", l), "\r\n");
  EXPECT_EQ(residue::swap_ending("\r\n", l), "\n");
  EXPECT_EQ(residue::swap_ending("\n\n", l), blank);
  EXPECT_EQ(residue::swap_ending(blank, l), "\n\n");
  for (const std::string s : {"", "\r", "\n,,,\n", "\r\n,,\r\n", ";\r\n", "\n\n\n"})
    EXPECT_EQ(residue::swap_ending(s, l), s) << s;
  l.crlf = false;
  EXPECT_EQ(residue::swap_ending("\n", l), "\n");
  EXPECT_EQ(residue::swap_ending("\n\n", l), "\n,,,\n");
  EXPECT_EQ(residue::swap_ending("\n,,,\n", l), "\n\n");
  l.width = 5000;  // a blank line too long for an ending is not swapped
  EXPECT_EQ(residue::swap_ending("\n\n", l), "\n\n");
}

TEST(TrcCommaHead, GivenDamagedFieldsWhenDecodedExpectCorrupt) {
  const Take t = comma_take();
  CommaLayout l;
  const std::vector<uint8_t> good =
      residue::encode_comma_head(bytes_of(std::string(kPadded) + ",\n"), t, "walk.trc", &l);
  auto decode = [&](const std::vector<uint8_t>& p, uint64_t limit) {
    ByteReader in(p.data(), p.size(), "head");
    CommaLayout back;
    residue::decode_comma_head(in, t, "walk.trc", limit, &back);
  };
  auto code_of = [&](const std::vector<uint8_t>& p, uint64_t limit) {
    try {
      decode(p, limit);
    } catch (const Error& e) {
      return e.code();
    }
    return ErrorCode::kInternal;  // no error
  };
  for (size_t cut = 0; cut < good.size(); ++cut)
    EXPECT_EQ(code_of({good.begin(), good.begin() + static_cast<long>(cut)}, 1 << 20),
              ErrorCode::kCorrupt)
        << cut;
  std::vector<uint8_t> bad = good;
  ByteWriter w;
  w.varint(4 * (2 * 8 - 1));  // width 8 - 8 = 0
  bad.erase(bad.begin());
  bad.insert(bad.begin(), w.buffer().begin(), w.buffer().end());
  EXPECT_EQ(code_of(bad, 1 << 20), ErrorCode::kCorrupt);
  ByteWriter far;
  far.varint(4 * 2 * ((uint64_t{1} << 20) + 1));  // past the default by more than 2^20
  bad = good;
  bad.erase(bad.begin());
  bad.insert(bad.begin(), far.buffer().begin(), far.buffer().end());
  EXPECT_EQ(code_of(bad, 1 << 20), ErrorCode::kCorrupt);
  EXPECT_EQ(code_of(good, 100), ErrorCode::kCorrupt);  // beyond the original's size
}
