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
#include "capz/stream.h"
#include "capz/tool/file.h"
#include "capz/tool/original.h"
#include "coding/lzf.h"
#include "corrupt/chunk_util.h"
#include "io/residue/pcd_residue.h"
#include "io/text_number.h"
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

// LZF variant 1 (docs/FORMAT.md 14.3) on "abcdabcdabcdX", worked by hand from the spec: offset
// 0 is never matched (so "abc" at 4 is a literal), the copy at 5 from 1 stops at n - i - 2 = 6
// bytes, and the last two bytes are literals. capz's own LZF gives other bytes.
TEST(Lzf, Variant1FollowsTheSpecification) {
  const std::string in = "abcdabcdabcdX";
  const auto* p = reinterpret_cast<const uint8_t*>(in.data());
  const std::vector<uint8_t> want = {4, 'a', 'b', 'c', 'd', 'a', 0x80, 3, 1, 'd', 'X'};
  EXPECT_EQ(capz::lzf_compress(p, in.size(), capz::LzfVariant::kLiblzf13), want);
  EXPECT_NE(capz::lzf_compress(p, in.size()), want);
  EXPECT_EQ(capz::lzf_decompress(want.data(), want.size(), in.size(), "t"), bytes_of(in));
  // Long inputs: runs of 32 literals, copies of up to 264 bytes; every stream decompresses.
  std::vector<uint8_t> big;
  uint32_t r = 7;
  for (int k = 0; k < 40000; ++k) {
    r = r * 1103515245u + 12345u;
    big.push_back(k % 3000 < 700 ? static_cast<uint8_t>(r >> 24) : static_cast<uint8_t>(k % 97));
  }
  const std::vector<uint8_t> c =
      capz::lzf_compress(big.data(), big.size(), capz::LzfVariant::kLiblzf13);
  EXPECT_LT(c.size(), big.size());
  EXPECT_EQ(capz::lzf_decompress(c.data(), c.size(), big.size(), "t"), big);
  EXPECT_TRUE(capz::lzf_compress(nullptr, 0, capz::LzfVariant::kLiblzf13).empty());
}

// binary_compressed bodies from PCL's LZF (variant 1) are regenerated by it: they cost their
// size, hash and flags, like the writer's own.
TEST(PcdResidue, LiblzfCompressedFramesCostOnlyTheirChecksum) {
  std::vector<std::vector<uint8_t>> frames;
  size_t differ = 0;
  for (int f = 0; f < 6; ++f) {
    std::vector<uint8_t> fm;  // 24 points, field-major: runs that the two LZFs parse apart
    for (int a = 0; a < 3; ++a)
      for (int q = 0; q < 24; ++q) put_f32(&fm, static_cast<float>(a + (q % 5) + f));
    const std::vector<uint8_t> c =
        capz::lzf_compress(fm.data(), fm.size(), capz::LzfVariant::kLiblzf13);
    differ += c != capz::lzf_compress(fm.data(), fm.size());
    std::vector<uint8_t> body;
    put_u32(&body, static_cast<uint32_t>(c.size()));
    put_u32(&body, static_cast<uint32_t>(fm.size()));
    body.insert(body.end(), c.begin(), c.end());
    frames.push_back(frame(plain_header(24, "binary_compressed"), body));
  }
  EXPECT_EQ(differ, 6u);
  const Archived a = round_trip(frames);
  EXPECT_EQ(a.pcdp, 12u + 1u + 6u * 19u);
}

// The shared Pandar64 sweeps (PCL binary_compressed): their first frames come back byte for
// byte with residue records of a few bytes each, not their bodies.
TEST(PcdResidue, PandarBodiesAreRegeneratedByLiblzf) {
  const std::string root = capz_test::shared_data_or_skip("scan/pandar64-factory20");
  if (root.empty()) return;
  std::vector<std::vector<uint8_t>> frames;
  for (const char* n : {"01.pcd", "02.pcd"}) frames.push_back(capz::read_file(root + "/" + n));
  const Archived a = round_trip(frames);
  EXPECT_LT(a.pcdp, 200u);
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

// The spellings other writers give, pinned against Python 3 (repr, "%.8g", "%.18e", "%.6f",
// "%.10g" of each float32 widened to a double; the shortest float32 text in repr's layout as
// data/make_ascii_pcd.py's shortest_f32 finds it).
TEST(TextNumber, StylesSpellNumbersAsTheirWriters) {
  struct Case {
    float v;
    const char *repr, *f32, *g8, *e18, *f6, *g10;
  };
  const Case cases[] = {
      {-0.059286266565322876f, "-0.059286266565322876", "-0.059286267", "-0.059286267",
       "-5.928626656532287598e-02", "-0.059286", "-0.05928626657"},
      {1e-5f, "9.999999747378752e-06", "1e-05", "9.9999997e-06", "9.999999747378751636e-06",
       "0.000010", "9.999999747e-06"},
      {3.0f, "3.0", "3.0", "3", "3.000000000000000000e+00", "3.000000", "3"},
      {1e16f, "1.0000000272564224e+16", "1e+16", "1e+16", "1.000000027256422400e+16",
       "10000000272564224.000000", "1.000000027e+16"},
      {123456.78f, "123456.78125", "123456.78", "123456.78", "1.234567812500000000e+05",
       "123456.781250", "123456.7812"},
      {-0.0f, "-0.0", "-0.0", "-0", "-0.000000000000000000e+00", "-0.000000", "-0"},
      {0.1f, "0.10000000149011612", "0.1", "0.1", "1.000000014901161194e-01", "0.100000",
       "0.1000000015"},
      {2.5e-38f, "2.4999999777439474e-38", "2.5e-38", "2.5e-38", "2.499999977743947414e-38",
       "0.000000", "2.499999978e-38"}};
  auto spelt = [](float v, uint8_t style, uint8_t p) {
    std::string s;
    capz::append_styled(v, true, style, p, &s);
    return s;
  };
  for (const Case& c : cases) {
    EXPECT_EQ(spelt(c.v, capz::kStylePythonDouble, 0), c.repr);
    EXPECT_EQ(spelt(c.v, capz::kStylePythonShortest, 0), c.f32);
    EXPECT_EQ(spelt(c.v, capz::kStyleG, 8), c.g8);
    EXPECT_EQ(spelt(c.v, capz::kStyleE, 18), c.e18);
    EXPECT_EQ(spelt(c.v, capz::kStyleF, 6), c.f6);
    EXPECT_EQ(spelt(c.v, capz::kStyleG, 10), c.g10);
  }
  EXPECT_EQ(spelt(0.5f, capz::kStyleShortest, 0), "0.5");
}

namespace {

// An organized W x H ascii frame in one writer's spelling: x y z F4, rgb U4, intensity F4,
// normals F4, label U2; every 7th pixel a miss (NaN position and normal, zero rgb and label).
std::vector<uint8_t> styled_frame(const std::string& conv, int f, size_t w, size_t h) {
  const std::string nan = conv == "fixed" ? "NaN" : "nan";
  auto fl = [&](float v) -> std::string {
    if (std::isnan(v)) return nan;
    std::string s;
    if (conv == "pcl") capz::append_styled(v, true, capz::kStyleG, 8, &s);
    if (conv == "repr") capz::append_styled(v, true, capz::kStylePythonDouble, 0, &s);
    if (conv == "f32") capz::append_styled(v, true, capz::kStylePythonShortest, 0, &s);
    if (conv == "savetxt") capz::append_styled(v, true, capz::kStyleE, 18, &s);
    if (conv == "fixed") capz::append_styled(v, true, capz::kStyleF, 6, &s);
    return s;
  };
  auto in = [&](uint32_t v) { return std::to_string(v); };
  const std::string N = std::to_string(w * h);
  std::string t =
      "# .PCD v0.7 - Point Cloud Data file format\nVERSION 0.7\nFIELDS x y z rgb intensity "
      "normal_x normal_y normal_z label\nSIZE 4 4 4 4 4 4 4 4 2\nTYPE F F F U F F F F U\nCOUNT 1 "
      "1 1 1 1 1 1 1 1\nWIDTH " +
      std::to_string(w) + "\nHEIGHT " + std::to_string(h) + "\nVIEWPOINT 0 0 0 1 0 0 0\nPOINTS " +
      N + "\nDATA ascii\n";
  const float q = std::numeric_limits<float>::quiet_NaN();
  for (size_t v = 0; v < h; ++v)
    for (size_t u = 0; u < w; ++u) {
      const size_t i = v * w + u;
      const bool miss = (i * 7 + static_cast<size_t>(f)) % 11 == 0;
      const float z = 2.0f + 0.013f * static_cast<float>(u) + 0.007f * static_cast<float>(f);
      const float x = miss ? q : (static_cast<float>(u) - 20.0f) * z / 52.5f;
      const float y = miss ? q : (static_cast<float>(v) - 15.0f) * z / 52.5f;
      const float nx = miss ? q : 0.12f * static_cast<float>(v % 5), ny = miss ? q : -0.3f;
      const float nz = miss ? q : -std::sqrt(1.0f - nx * nx - ny * ny);
      t += fl(x) + " " + fl(y) + " " + fl(miss ? q : z) + " " +
           in(miss ? 0 : 0x102030u + static_cast<uint32_t>(u * 997)) + " " +
           fl(0.25f + 0.001f * static_cast<float>((u * 31 + v) % 97)) + " " + fl(nx) + " " +
           fl(ny) + " " + fl(nz) + " " + in(miss ? 0 : 1 + static_cast<uint32_t>(u > w / 2)) + "\n";
    }
  return bytes_of(t);
}

}  // namespace

// An organized sequence in each writer's spelling comes back byte for byte, and its per-frame
// residue is the column styles and a few exceptions, not the numbers' text.
TEST(PcdResidue, AsciiBodiesOfOtherWritersAreRegeneratedByColumnStyle) {
  for (const std::string conv : {"pcl", "repr", "f32", "savetxt", "fixed"}) {
    std::vector<std::vector<uint8_t>> frames;
    size_t text = 0;
    for (int f = 0; f < 3; ++f) {
      frames.push_back(styled_frame(conv, f, 40, 30));
      text += frames.back().size();
    }
    const Archived a = round_trip(frames);
    EXPECT_LT(a.pcdp, 3u * 200u) << conv << ": " << a.pcdp << " bytes of PCDP for " << text;
  }
}

// Lines the styles do not give (another spelling of one number, aligned columns, a CRLF line,
// a missing last line end, bytes after the last line) are exceptions and come back.
TEST(PcdResidue, AsciiStyleExceptionsComeBack) {
  const std::vector<uint8_t> f = styled_frame("repr", 0, 40, 30);
  std::string s(f.begin(), f.end());
  // The start of point line k.
  auto line = [&](int k) {
    size_t at = s.find("DATA ascii\n") + 11;
    for (int i = 0; i < k; ++i) at = s.find('\n', at) + 1;
    return at;
  };
  s.replace(s.find(' ', line(5)), 1, "  ");      // two blanks: the line's own text
  s.insert(s.find(' ', line(10)), "0");          // x spelt with one more zero
  s.replace(s.find('\n', line(20)), 1, "\r\n");  // one CRLF
  std::string t = s;
  t.pop_back();                       // no line end after the last line
  const std::string u = s + "\n \n";  // blank lines after the last point
  round_trip({bytes_of(s), bytes_of(t), bytes_of(u)});
}

// Writers that put a blank after every value (a line "1 2 3 \n") give the model lines' end " \n":
// their frames cost the column styles, as without the blanks, not every line's text (each line
// was stored whole: its C values split into C + 1 tokens). A line without the blank and one with
// two come back as exceptions.
TEST(PcdResidue, AsciiLinesEndingInABlankAreRegeneratedByColumnStyle) {
  for (const std::string conv : {"pcl", "repr", "savetxt"}) {
    std::vector<std::vector<uint8_t>> frames;
    for (int f = 0; f < 3; ++f) {
      const std::vector<uint8_t> b = styled_frame(conv, f, 40, 30);
      std::string s(b.begin(), b.end());
      const size_t data = s.find("DATA ascii\n") + 11;
      std::string t = s.substr(0, data);
      size_t line = 0;
      for (size_t at = data; at < s.size(); ++line) {
        const size_t nl = s.find('\n', at);
        t += s.substr(at, nl - at) + (line == 7 ? "" : line == 9 ? "  " : " ") + "\n";
        at = nl + 1;
      }
      frames.push_back(bytes_of(t));
    }
    const Archived a = round_trip(frames);
    EXPECT_LT(a.pcdp, 3u * 200u) << conv << ": " << a.pcdp << " bytes of PCDP";
  }
}
