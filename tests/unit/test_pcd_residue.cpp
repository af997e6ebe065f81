// Byte-exact PCD archives (docs/FORMAT.md 7.3, 14.3): folders whose frame files capz's writer does
// not reproduce (other header text, ASCII number spellings, NaN payloads, trailing bytes, other LZF
// bytes) come back byte for byte from a --lossless archive, each frame's checksum checked.
#include <gtest/gtest.h>

#include <cmath>
#include <cstring>
#include <filesystem>
#include <limits>
#include <string>
#include <vector>

#include "capz/codec.h"
#include "capz/error.h"
#include "capz/file.h"
#include "capz/original.h"
#include "capz/stream.h"
#include "coding/lzf.h"
#include "corrupt/chunk_util.h"
#include "io/residue/pcd_residue.h"
#include "test_util.h"

namespace fs = std::filesystem;

namespace {

std::vector<uint8_t> bytes_of(const std::string& s) {
  return std::vector<uint8_t>(s.begin(), s.end());
}

void put_f32(std::vector<uint8_t>* b, float v) {
  uint8_t x[4];
  std::memcpy(x, &v, 4);
  b->insert(b->end(), x, x + 4);
}
void put_u32(std::vector<uint8_t>* b, uint32_t v) {
  for (int i = 0; i < 4; ++i) b->push_back(static_cast<uint8_t>(v >> (8 * i)));
}

// The header capz's (and PCL's) writer gives x y z float32 frames of n points.
std::string plain_header(size_t n, const char* data, const std::string& nl = "\n") {
  const std::string N = std::to_string(n);
  return "# .PCD v0.7 - Point Cloud Data file format" + nl + "VERSION 0.7" + nl + "FIELDS x y z" +
         nl + "SIZE 4 4 4" + nl + "TYPE F F F" + nl + "COUNT 1 1 1" + nl + "WIDTH " + N + nl +
         "HEIGHT 1" + nl + "VIEWPOINT 0 0 0 1 0 0 0" + nl + "POINTS " + N + nl + "DATA " + data +
         nl;
}

// Binary point bytes of frame f (4 points, all valid).
std::vector<uint8_t> points(int f) {
  std::vector<uint8_t> b;
  for (int p = 0; p < 4; ++p)
    for (int a = 0; a < 3; ++a)
      put_f32(&b, 0.25f * static_cast<float>(f + p) + static_cast<float>(a));
  return b;
}

struct Archived {
  std::vector<uint8_t> archive;
  size_t pcdp = 0;  // bytes of every PCDP chunk
};

// Writes the frames into a folder, archives it --lossless, rebuilds it and checks every file
// came back byte for byte (through rebuild_original and through test_original).
Archived round_trip(const std::vector<std::vector<uint8_t>>& frames) {
  capz_test::TempDir tmp("capz_pcdres");
  const std::string dir = tmp.file("in"), z = tmp.file("a.capz"), back = tmp.file("back");
  fs::create_directories(dir);
  std::vector<std::string> names;
  for (size_t f = 0; f < frames.size(); ++f) {
    names.push_back("f" + std::to_string(f) + ".pcd");
    capz::write_file(dir + "/" + names.back(), frames[f], true);
  }
  std::unique_ptr<capz::FrameSource> src = capz::open_frames(dir);
  capz::CompressOptions o;
  o.lossless = true;
  capz::compress_stream(*src, o, z, true);
  const capz::OriginalInfo info = capz::original_info(z);
  EXPECT_TRUE(info.exact);
  size_t total = 0;
  for (const auto& f : frames) total += f.size();
  EXPECT_EQ(info.size, total);
  capz::test_original(z);
  capz::rebuild_original(z, back, true);
  for (size_t f = 0; f < frames.size(); ++f)
    EXPECT_EQ(capz::read_file(back + "/" + names[f]), frames[f]) << names[f];
  Archived a;
  a.archive = capz::read_file(z);
  for (size_t at = capz_test::find_chunk(a.archive, "PCDP"); at != std::string::npos;) {
    a.pcdp += 12 + capz_test::chunk_len(a.archive, at);
    std::vector<uint8_t> rest(a.archive.begin() + static_cast<long>(at + 4), a.archive.end());
    const size_t next = capz_test::find_chunk(rest, "PCDP");
    at = next == std::string::npos ? next : at + 4 + next;
  }
  return a;
}

std::vector<uint8_t> frame(const std::string& header, const std::vector<uint8_t>& body) {
  std::vector<uint8_t> b = bytes_of(header);
  b.insert(b.end(), body.begin(), body.end());
  return b;
}

}  // namespace

TEST(PcdResidue, HeaderEndIsAfterTheDataLine) {
  const std::string h = "# c\nVERSION 0.7\n  DATA binary\r\nxyz";
  EXPECT_EQ(capz::residue::pcd_header_end(reinterpret_cast<const uint8_t*>(h.data()), h.size()),
            h.size() - 3);
  const std::string no = "# DATA x\nDATAX binary\n";
  EXPECT_EQ(capz::residue::pcd_header_end(reinterpret_cast<const uint8_t*>(no.data()), no.size()),
            SIZE_MAX);
}

// Frames in the writer's own form cost their size, hash and flags only.
TEST(PcdResidue, WritersFramesCostOnlyTheirChecksum) {
  std::vector<std::vector<uint8_t>> frames;
  for (int f = 0; f < 8; ++f) frames.push_back(frame(plain_header(4, "binary"), points(f)));
  const Archived a = round_trip(frames);
  // One PCDP: 12 bytes of chunk framing, the window index, 8 x (varint size, 16, 1).
  EXPECT_EQ(a.pcdp, 12u + 1u + 8u * 19u);
}

// Comments, CRLF line ends and extra spaces: shared by the frames, stored once (PCDR).
TEST(PcdResidue, HeaderVariantsComeBackAndAreStoredOnce) {
  std::string h = plain_header(4, "binary", "\r\n");
  h.insert(0, "# written by a scanner\r\n");
  h.replace(h.find("FIELDS x y z"), 12, "FIELDS   x  y z ");
  std::vector<std::vector<uint8_t>> frames;
  for (int f = 0; f < 8; ++f) frames.push_back(frame(h, points(f)));
  const Archived a = round_trip(frames);
  EXPECT_EQ(a.pcdp, 12u + 1u + 8u * 19u);
  // A frame with a header of its own (another comment) among them.
  frames[3] = frame("# frame 3\n" + plain_header(4, "binary"), points(3));
  round_trip(frames);
}

TEST(PcdResidue, AsciiNumberSpellingsComeBack) {
  const std::string body = "1.50 1e+00 -0\n0.1 2.0000 3\n-1.25E-3 +4 5.\n7 8 9   \n";
  const std::string body2 = "1.5 1 0\n0.1 2 3\n-0.00125 4 5\n7 8 9\n";  // the writer's form
  round_trip(
      {frame(plain_header(4, "ascii"), bytes_of(body)),
       frame(plain_header(4, "ascii"), bytes_of(body2)),
       frame(plain_header(4, "ascii", "\r\n"), bytes_of("1 2 3\r\n4 5 6\r\n7 8 9\r\n1 1 1\r\n"))});
}

// NaN payloads, a negative NaN, a gap with one finite coordinate, an infinite coordinate.
TEST(PcdResidue, NanPayloadsAndPartialGapsComeBack) {
  std::vector<uint8_t> b = points(0);
  const uint32_t nans[3] = {0x7fc00001u, 0xffc00000u, 0x7f800001u};
  std::memcpy(&b[0], &nans[0], 4);   // point 0: x a NaN with a payload, y z finite
  std::memcpy(&b[12], &nans[1], 4);  // point 1: x -NaN
  std::memcpy(&b[16], &nans[1], 4);
  std::memcpy(&b[20], &nans[2], 4);  // y -NaN, z a signalling NaN
  const float inf = std::numeric_limits<float>::infinity();
  std::memcpy(&b[24], &inf, 4);  // point 2: x infinite
  std::vector<std::vector<uint8_t>> frames = {frame(plain_header(4, "binary"), b),
                                              frame(plain_header(4, "binary"), points(1))};
  const Archived a = round_trip(frames);
  EXPECT_LT(a.pcdp, 12u + 1u + 2u * 19u + 64u);  // a byte patch, not the body
}

TEST(PcdResidue, TrailingBytesComeBack) {
  std::vector<uint8_t> b = points(0);
  const std::string junk = "\n\n-- trailer --\n";
  b.insert(b.end(), junk.begin(), junk.end());
  round_trip({frame(plain_header(4, "binary"), b), frame(plain_header(4, "binary"), points(1))});
}

// binary_compressed: compressed as capz (PCL's liblzf format) compresses, and by hand as
// literal runs only (other compressed bytes for the same points, which PCL reads alike).
TEST(PcdResidue, CompressedFramesComeBack) {
  auto field_major = [](const std::vector<uint8_t>& pts) {
    std::vector<uint8_t> fm;
    for (int a = 0; a < 3; ++a)
      for (int p = 0; p < 4; ++p)
        fm.insert(fm.end(), pts.begin() + (p * 12 + a * 4), pts.begin() + (p * 12 + a * 4 + 4));
    return fm;
  };
  std::vector<std::vector<uint8_t>> frames;
  for (int f = 0; f < 2; ++f) {
    const std::vector<uint8_t> fm = field_major(points(f));
    const std::vector<uint8_t> c = capz::lzf_compress(fm.data(), fm.size());
    std::vector<uint8_t> body;
    put_u32(&body, static_cast<uint32_t>(c.size()));
    put_u32(&body, static_cast<uint32_t>(fm.size()));
    body.insert(body.end(), c.begin(), c.end());
    frames.push_back(frame(plain_header(4, "binary_compressed"), body));
  }
  for (int f = 2; f < 4; ++f) {
    const std::vector<uint8_t> fm = field_major(points(f));
    std::vector<uint8_t> c;  // literal runs of at most 32 bytes
    for (size_t i = 0; i < fm.size(); i += 32) {
      const size_t n = std::min<size_t>(32, fm.size() - i);
      c.push_back(static_cast<uint8_t>(n - 1));
      c.insert(c.end(), fm.begin() + static_cast<long>(i), fm.begin() + static_cast<long>(i + n));
    }
    std::vector<uint8_t> body;
    put_u32(&body, static_cast<uint32_t>(c.size()));
    put_u32(&body, static_cast<uint32_t>(fm.size()));
    body.insert(body.end(), c.begin(), c.end());
    frames.push_back(frame(plain_header(4, "binary_compressed"), body));
  }
  const Archived a = round_trip(frames);
  EXPECT_GT(a.pcdp, 12u + 1u + 4u * 19u);  // the hand-made bodies are stored
}

// A folder mixing encodings: each frame regenerated in its own.
TEST(PcdResidue, MixedEncodingsComeBack) {
  round_trip({frame(plain_header(4, "binary"), points(0)),
              frame(plain_header(4, "ascii"), bytes_of("1 2 3\n4 5 6\n7 8 9\n1 1 1\n")),
              frame(plain_header(4, "binary"), points(2))});
}

// A PCDP whose bytes differ with its CRC fixed: the rebuild fails naming the frame file and
// leaves no output.
TEST(PcdResidue, ChecksumMismatchNamesTheFrameFile) {
  capz_test::TempDir tmp("capz_pcdres_bad");
  const std::string dir = tmp.file("in"), z = tmp.file("a.capz"), back = tmp.file("back");
  fs::create_directories(dir);
  std::vector<uint8_t> b = points(0);
  b.push_back('\n');  // a tail, so the frame carries bytes of its own
  capz::write_file(dir + "/a.pcd", frame(plain_header(4, "binary"), points(1)), true);
  capz::write_file(dir + "/b.pcd", frame(plain_header(4, "binary"), b), true);
  std::unique_ptr<capz::FrameSource> src = capz::open_frames(dir);
  capz::CompressOptions o;
  o.lossless = true;
  capz::compress_stream(*src, o, z, true);
  std::vector<uint8_t> arc = capz::read_file(z);
  const size_t at = capz_test::find_chunk(arc, "PCDP");
  ASSERT_NE(at, std::string::npos);
  const uint32_t len = capz_test::chunk_len(arc, at);
  // The last byte of the payload is frame b's stored tail ("\n", method 0): change it.
  ASSERT_EQ(arc[at + 8 + len - 1], '\n');
  arc[at + 8 + len - 1] = 'X';
  capz_test::fix_crc(&arc, at);
  capz::write_file(z, arc, true);
  try {
    capz::rebuild_original(z, back, true);
    FAIL() << "a damaged frame was rebuilt";
  } catch (const capz::Error& e) {
    EXPECT_EQ(e.code(), capz::ErrorCode::kCorrupt);
    EXPECT_NE(std::string(e.what()).find("b.pcd"), std::string::npos) << e.what();
    EXPECT_NE(std::string(e.what()).find("XXH3-128"), std::string::npos) << e.what();
  }
  EXPECT_FALSE(fs::exists(back));
  EXPECT_THROW(capz::test_original(z), capz::Error);
}

// At a bound nothing of 5.4 is written: the archive is what it was before.
TEST(PcdResidue, BoundedArchivesCarryNoResidue) {
  capz_test::TempDir tmp("capz_pcdres_bound");
  const std::string z = tmp.file("a.capz");
  std::unique_ptr<capz::FrameSource> src =
      capz::open_frames(std::string(CAPZ_REPO_DATA) + "/lidar_small");
  capz::CompressOptions o;
  o.max_error = 0.01;
  capz::compress_stream(*src, o, z, true);
  const std::vector<uint8_t> a = capz::read_file(z);
  for (const char* t : {"HASH", "PCDR", "PCDP"})
    EXPECT_EQ(capz_test::find_chunk(a, t), std::string::npos) << t;
  EXPECT_FALSE(capz::original_info(z).hashed);
}
