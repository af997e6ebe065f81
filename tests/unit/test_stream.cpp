// Frame sources on synthetic files with the awkward cases real files rarely show together: a TRC
// with a byte-order mark, CRLF line ends, blank lines, no final line end and rows longer than
// the source's 1 MiB read chunk; read in blocks, it equals read_trc.
#include <gtest/gtest.h>

#include <cstring>
#include <string>

#include "capz/io.h"
#include "capz/stream.h"
#include "core/atomic_file.h"
#include "test_util.h"

using namespace capz;

namespace {

void write_text(const std::string& path, const std::string& s) {
  AtomicFile f(path, true);
  f.write(s.data(), s.size());
  f.commit();
}

Take read_in_blocks(FrameSource& src, size_t block) {
  Take t = src.header();
  FrameBlock b;
  for (size_t f = 0; f < t.frames; f += block) {
    src.read(f, block, &b);
    t.xyz.insert(t.xyz.end(), b.xyz.begin(), b.xyz.end());
    t.valid.insert(t.valid.end(), b.valid.begin(), b.valid.end());
  }
  return t;
}

TEST(StreamTrcSource, GivenBomCrlfBlankLinesAndRowsLongerThanAChunkThenSameAsReadTrc) {
  capz_test::TempDir dir("capz_stream_unit");
  const size_t points = 90000;  // a row of about 1.4 MB
  std::string s = "\xEF\xBB\xBFPathFileType\t4\t(X/Y/Z)\tlong.trc\r\n";
  s += "DataRate\tCameraRate\tNumFrames\tNumMarkers\tUnits\r\n100\t100\t4\t90000\tmm\r\n";
  s += "Frame#\tTime";
  for (size_t p = 0; p < points; ++p) s += "\tM" + std::to_string(p) + "\t\t";
  s += "\r\n\tX1\tY1\tZ1\r\n\r\n";
  for (int r = 0; r < 4; ++r) {
    s += std::to_string(r + 1) + "\t" + std::to_string(r * 0.01);
    for (size_t p = 0; p < points; ++p) {
      if ((p + static_cast<size_t>(r)) % 7 == 0) {
        s += "\t\t\t";  // a gap
        continue;
      }
      s += "\t" + std::to_string(r) + ".25\t-" + std::to_string(p % 100) + ".5\t0.125";
    }
    s += r == 3 ? "" : "\r\n";
    if (r == 1) s += "\r\n   \r\n";  // blank lines between rows
  }
  const std::string path = dir.file("long.trc");
  write_text(path, s);
  const Take whole = read_trc(path);
  ASSERT_EQ(whole.frames, 4u);
  ASSERT_EQ(whole.points, points);
  for (size_t block : {1, 3, 4}) {
    SCOPED_TRACE("block " + std::to_string(block));
    std::unique_ptr<FrameSource> src = open_trc_frames(path);
    Take parts = read_in_blocks(*src, block);
    capz_test::expect_same_samples(whole, parts);
    EXPECT_EQ(whole.labels, parts.labels);
    EXPECT_EQ(whole.warnings, parts.warnings);
    EXPECT_EQ(whole.trc->times, parts.trc->times);
    EXPECT_EQ(whole.trc->decimals, parts.trc->decimals);
  }
}

TEST(StreamTrcSource, GivenABadNumberThenTheSameErrorAsReadTrcAtOpen) {
  capz_test::TempDir dir("capz_stream_unit");
  const std::string path = dir.file("bad.trc");
  write_text(path,
             "PathFileType\t4\t(X/Y/Z)\tbad.trc\nDataRate\tUnits\n100\tmm\nFrame#\tTime\tA\n"
             "\tX1\tY1\tZ1\n1\t0\t1\t2\t3\n2\t0.01\t1\tx\t3\n");
  std::string whole_msg, stream_msg;
  try {
    read_trc(path);
  } catch (const Error& e) {
    whole_msg = e.what();
  }
  try {
    open_trc_frames(path);
  } catch (const Error& e) {
    stream_msg = e.what();
  }
  EXPECT_NE(whole_msg.find("line 7"), std::string::npos) << whole_msg;
  EXPECT_EQ(whole_msg, stream_msg);
}

}  // namespace

// FrameBlock::frame_bytes counts what reset allocates per frame (and the attribute arrays a
// source sizes): the decoder's memory limit relies on it (CapzSource).
TEST(FrameBlockBytes, GivenEveryLayoutWhenResetThenFrameBytesCountsItsArrays) {
  for (const bool words : {false, true})
    for (const size_t rotations : {size_t{0}, size_t{6}}) {
      const size_t frames = 5, points = 7, analog = 12, attribute_bytes = 9;
      FrameBlock b;
      b.reset(0, frames, points, analog, words, rotations);
      b.attributes.assign(1, std::vector<uint8_t>(frames * points * attribute_bytes));
      const size_t held = b.xyz.size() * sizeof(double) + b.valid.size() +
                          b.residual.size() * sizeof(float) + b.camera_mask.size() +
                          b.analog.size() * sizeof(double) +
                          b.rotation_matrices.size() * sizeof(float) +
                          b.rotation_reliability.size() * sizeof(float) + b.attributes[0].size();
      EXPECT_EQ(static_cast<double>(held),
                frames * FrameBlock::frame_bytes(points, analog, words, rotations, attribute_bytes))
          << "words " << words << ", rotations " << rotations;
    }
  // A header's counts whose product overflows size_t still give a large size, not a wrapped one.
  EXPECT_GT(FrameBlock::frame_bytes(0, 4294967296.0 * 4294967296.0, false, 0, 0), 1e19);
}
