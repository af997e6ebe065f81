// PLY and .bin takes through compress and decompress in memory (docs/FORMAT.md "Scans (format
// 1.1)", frame-file sources): HEAD's feature bit 4 and frame_format, META's PLY block, and the
// refusal of a damaged or unknown frame-file format code.
#include <gtest/gtest.h>

#include <algorithm>
#include <cmath>
#include <cstring>
#include <string>
#include <vector>

#include "capz/codec.h"
#include "capz/error.h"
#include "capz/io.h"
#include "coding/crc32c.h"
#include "support/float32.h"
#include "support/stream_pieces.h"
#include "test_util.h"

namespace {

using capz::Format;

// Frames of the given point counts on a spiral, point 2 of each frame a gap; the take's frame
// shape fixed when every count is the same, else ragged.
capz::Take spiral_take(Format format, const std::vector<size_t>& counts) {
  capz::Take t;
  t.format = format;
  t.units = "m";
  t.units_assumed = true;
  capz_test::resize_frames(&t, counts);
  for (size_t i = 0; i < t.total_points(); ++i) {
    const double a = 0.01 * static_cast<double>(i);
    t.xyz[3 * i] = capz_test::float32_value(30 * std::cos(a));
    t.xyz[3 * i + 1] = capz_test::float32_value(30 * std::sin(a));
    t.xyz[3 * i + 2] = static_cast<float>(0.5 + 0.002 * static_cast<double>(i % 97));
    t.valid[i] = 1;
  }
  for (size_t f = 0; f < t.frames; ++f)
    if (t.frame_points(f) > 2) t.valid[t.frame_begin(f) + 2] = 0;
  return t;
}

// A PLY take: x y z float32 (spelled "float32"), intensity uchar, time double.
capz::Take ply_take(const std::vector<size_t>& counts, bool fields) {
  capz::Take t = spiral_take(Format::kPLYFolder, counts);
  auto x = std::make_shared<capz::PLYExtra>();
  x->encoding = "binary_big_endian";
  x->version = "1.0";
  x->fields = {{"x", 'F', 4, 1}, {"y", 'F', 4, 1}, {"z", 'F', 4, 1}};
  x->type_names = {"float32", "float32", "float"};
  if (fields) {
    x->fields.push_back({"intensity", 'U', 1, 1});
    x->fields.push_back({"time", 'F', 8, 1});
    x->type_names.push_back("uchar");
    x->type_names.push_back("float64");
    capz::PointAttribute in{"intensity", 'U', 1, 1, {}}, tm{"time", 'F', 8, 1, {}};
    for (size_t i = 0; i < t.total_points(); ++i) {
      in.data.push_back(static_cast<uint8_t>(i * 7));
      const double v = 1.7e9 + 1e-5 * static_cast<double>(i);
      uint8_t b[8];
      std::memcpy(b, &v, 8);
      tm.data.insert(tm.data.end(), b, b + 8);
    }
    t.attributes = {in, tm};
  }
  x->comments = {"made by test_scan_formats", ""};
  x->obj_info = {"synthetic spiral"};
  for (size_t f = 0; f < counts.size(); ++f)
    x->frame_names.push_back("sweep" + std::to_string(f) + ".ply");
  t.ply = x;
  return t;
}

capz::Take bin_take(const std::vector<size_t>& counts) {
  capz::Take t = spiral_take(Format::kBinFolder, counts);
  t.bin = std::make_shared<capz::BinExtra>();
  for (size_t f = 0; f < counts.size(); ++f)
    t.bin->frame_names.push_back(std::to_string(f) + ".bin");
  capz::PointAttribute in{"intensity", 'F', 4, 1, {}};
  for (size_t i = 0; i < t.total_points(); ++i) {
    const float v = 0.01f * static_cast<float>(i % 100);
    uint8_t b[4];
    std::memcpy(b, &v, 4);
    in.data.insert(in.data.end(), b, b + 4);
  }
  t.attributes = {in};
  return t;
}

std::vector<uint8_t> compress_at(const capz::Take& t, double bound, bool drop = false) {
  capz::CompressOptions o;
  o.max_error = bound;
  o.drop_fields = drop;
  return capz::compress(t, o);
}

// Same shape and gaps, every valid coordinate within `bound`, also as the float32 a PLY or .bin
// writer stores.
void expect_within(const capz::Take& a, const capz::Take& b, double bound) {
  ASSERT_EQ(a.frames, b.frames);
  ASSERT_EQ(a.frame_offsets, b.frame_offsets);
  ASSERT_EQ(a.valid, b.valid);
  for (size_t i = 0; i < a.xyz.size(); ++i) {
    if (!a.valid[i / 3]) continue;
    EXPECT_LE(std::fabs(a.xyz[i] - b.xyz[i]), bound) << i;
    EXPECT_LE(std::fabs(a.xyz[i] - static_cast<float>(b.xyz[i])), bound) << i;
  }
}

TEST(ScanFormats, GivenAFixedPLYTakeThenItsHeaderFactsAndFieldsComeBack) {
  const capz::Take t = ply_take({300, 300, 300}, true);
  const std::vector<uint8_t> s = compress_at(t, 0.001);
  EXPECT_EQ(s[10], 1);  // format 1.1: a frame-file source
  const capz::Take d = capz::decompress(s.data(), s.size(), "ply.capz");
  EXPECT_EQ(d.format, Format::kPLYFolder);
  ASSERT_TRUE(d.ply);
  EXPECT_EQ(d.ply->encoding, "binary_big_endian");
  EXPECT_EQ(d.ply->version, "1.0");
  EXPECT_EQ(d.ply->type_names, t.ply->type_names);
  EXPECT_EQ(d.ply->comments, t.ply->comments);
  EXPECT_EQ(d.ply->obj_info, t.ply->obj_info);
  EXPECT_EQ(d.ply->frame_names, t.ply->frame_names);
  ASSERT_EQ(d.ply->fields.size(), t.ply->fields.size());
  for (size_t i = 0; i < t.ply->fields.size(); ++i) {
    EXPECT_EQ(d.ply->fields[i].name, t.ply->fields[i].name);
    EXPECT_EQ(d.ply->fields[i].size, t.ply->fields[i].size);
  }
  ASSERT_EQ(d.attributes.size(), 2u);
  EXPECT_EQ(d.attributes[0].data, t.attributes[0].data);
  EXPECT_EQ(d.attributes[1].data, t.attributes[1].data);
  expect_within(t, d, 0.001);
  const capz::StreamInfo si = capz::describe(s.data(), s.size(), "ply.capz");
  EXPECT_EQ(si.source_format, Format::kPLYFolder);
}

TEST(ScanFormats, GivenARaggedPLYTakeThenItComesBackAsPLYWithItsCounts) {
  const capz::Take t = ply_take({300, 417, 5, 260}, false);
  const std::vector<uint8_t> s = compress_at(t, 0.001);
  const capz::Take d = capz::decompress(s.data(), s.size(), "ragged.capz");
  EXPECT_EQ(d.format, Format::kPLYFolder);
  ASSERT_TRUE(d.ply);
  EXPECT_EQ(d.ply->frame_names, t.ply->frame_names);
  EXPECT_EQ(d.ply->comments, t.ply->comments);
  expect_within(t, d, 0.001);
  // Point fields of ragged windows: kept byte for byte; --drop-fields keeps x y z and the
  // header's other facts.
  {
    const capz::Take tk = ply_take({300, 417, 5, 260}, true);
    const std::vector<uint8_t> sk = compress_at(tk, 0.001);
    const capz::Take dk = capz::decompress(sk.data(), sk.size(), "ragged.capz");
    ASSERT_TRUE(dk.ply);
    EXPECT_EQ(dk.ply->type_names, tk.ply->type_names);
    ASSERT_EQ(dk.attributes.size(), 2u);
    EXPECT_EQ(dk.attributes[0].data, tk.attributes[0].data);
    EXPECT_EQ(dk.attributes[1].data, tk.attributes[1].data);
    expect_within(tk, dk, 0.001);
  }
  const capz::Take tf = ply_take({300, 417, 5, 260}, true);
  const std::vector<uint8_t> sf = compress_at(tf, 0.001, true);
  const capz::Take df = capz::decompress(sf.data(), sf.size(), "ragged.capz");
  ASSERT_TRUE(df.ply);
  EXPECT_EQ(df.ply->fields.size(), 3u);
  EXPECT_EQ(df.ply->type_names, std::vector<std::string>({"float32", "float32", "float"}));
  expect_within(tf, df, 0.001);
}

TEST(ScanFormats, GivenBinTakesThenTheyComeBackAsBinWithTheirIntensity) {
  const capz::Take t = bin_take({500, 500});
  const std::vector<uint8_t> s = compress_at(t, 0.01);
  const capz::Take d = capz::decompress(s.data(), s.size(), "bin.capz");
  EXPECT_EQ(d.format, Format::kBinFolder);
  ASSERT_TRUE(d.bin);
  EXPECT_EQ(d.bin->frame_names, t.bin->frame_names);
  ASSERT_EQ(d.attributes.size(), 1u);
  EXPECT_EQ(d.attributes[0].data, t.attributes[0].data);
  expect_within(t, d, 0.01);
  const capz::Take r = bin_take({500, 200, 333});
  for (bool drop : {false, true}) {
    const std::vector<uint8_t> rs = compress_at(r, 0.01, drop);
    const capz::Take rd = capz::decompress(rs.data(), rs.size(), "bin.capz");
    EXPECT_EQ(rd.format, Format::kBinFolder);
    ASSERT_EQ(rd.attributes.size(), drop ? 0u : 1u);
    if (!drop) {
      EXPECT_EQ(rd.attributes[0].data, r.attributes[0].data);
    }
    expect_within(r, rd, 0.01);
  }
}

// A take of nuScenes' .bin frames (NAME.pcd.bin: x y z intensity ring) keeps its record through
// the archive, with --drop-fields too (its files are then written with zeros); a take whose .bin
// frame names are of both kinds has no one record and is refused by name.
TEST(ScanFormats, GivenNuScenesBinTakesThenTheirRecordComesBack) {
  capz::Take t = bin_take({500, 200, 333});
  for (std::string& n : t.bin->frame_names) n = "sweep" + n.substr(0, n.size() - 4) + ".pcd.bin";
  capz::PointAttribute ring{"ring", 'F', 4, 1, {}};
  for (size_t i = 0; i < t.total_points(); ++i) {
    const float v = static_cast<float>(i % 32);
    uint8_t b[4];
    std::memcpy(b, &v, 4);
    ring.data.insert(ring.data.end(), b, b + 4);
  }
  t.attributes.push_back(ring);
  for (bool drop : {false, true}) {
    const std::vector<uint8_t> s = compress_at(t, 0.01, drop);
    const capz::Take d = capz::decompress(s.data(), s.size(), "nus.capz");
    ASSERT_TRUE(d.bin);
    EXPECT_EQ(d.bin->frame_names, t.bin->frame_names);
    EXPECT_EQ(capz::bin_record_text(capz::bin_record_of(d)), "x y z intensity ring");
    ASSERT_EQ(d.attributes.size(), drop ? 0u : 2u);
    if (!drop) {
      EXPECT_EQ(d.attributes[1].name, "ring");
      EXPECT_EQ(d.attributes[1].data, ring.data);
    }
    expect_within(t, d, 0.01);
  }
  t.bin->frame_names[1] = "sweep1.bin";  // KITTI's name among nuScenes'
  try {
    compress_at(t, 0.01);
    FAIL() << "frame names of both kinds were compressed";
  } catch (const capz::Error& e) {
    EXPECT_EQ(e.code(), capz::ErrorCode::kInvalidParameter) << e.what();
    EXPECT_NE(std::string(e.what()).find("two kinds"), std::string::npos) << e.what();
  }
  // A KITTI take with a ring field cannot write it back: refused unless dropped.
  t.bin->frame_names[1] = "sweep1.pcd.bin";
  for (std::string& n : t.bin->frame_names) n = n.substr(0, n.size() - 8) + ".bin";
  EXPECT_THROW(compress_at(t, 0.01), capz::Error);
  EXPECT_NO_THROW(compress_at(t, 0.01, true));
}

// --lossless on PLY and .bin takes in memory (no frame files to rebuild: no residue): every
// valid coordinate bit for bit, every field exact (FORMAT.md "Lossless frame-file streams").
TEST(ScanFormats, GivenLosslessOnPLYOrBinTakesThenPositionsAndFieldsComeBackExact) {
  capz::CompressOptions o;
  o.lossless = true;
  capz::Take takes[] = {ply_take({10, 10}, true), ply_take({9, 13}, true), bin_take({10, 12})};
  for (capz::Take& t : takes) {
    for (double& v : t.xyz) v = static_cast<float>(v);  // x y z float32, as the layout says
    SCOPED_TRACE(std::to_string(t.frames) + " frames, ragged " + std::to_string(t.ragged()) +
                 ", format " + std::to_string(static_cast<int>(t.format)));
    capz::CompressStats st;
    std::vector<uint8_t> z;
    try {
      z = capz::compress(t, o, &st);
    } catch (const capz::Error& e) {
      FAIL() << e.what();
    }
    EXPECT_TRUE(st.lossless);
    const capz::Take d = capz::decompress(z.data(), z.size());
    ASSERT_EQ(d.total_points(), t.total_points());
    ASSERT_EQ(d.valid, t.valid);
    for (size_t i = 0; i < t.xyz.size(); ++i) {
      if (!t.valid[i / 3]) continue;
      ASSERT_EQ(d.xyz[i], t.xyz[i]) << i;
    }
    ASSERT_EQ(d.attributes.size(), t.attributes.size());
    for (size_t a = 0; a < t.attributes.size(); ++a)
      EXPECT_EQ(d.attributes[a].data, t.attributes[a].data) << t.attributes[a].name;
    EXPECT_TRUE(capz::describe(z.data(), z.size()).lossless);
  }
}

// The file header's minor set to `minor`, its CRC made right again.
std::vector<uint8_t> with_minor(std::vector<uint8_t> b, uint8_t minor) {
  b[10] = minor;
  const uint32_t c = capz::crc32c(b.data(), 11);
  for (int i = 0; i < 4; ++i) b[11 + static_cast<size_t>(i)] = static_cast<uint8_t>(c >> (8 * i));
  return b;
}

// Frames of their own counts with float64 x y z far from the origin (map coordinates: UTM
// eastings and northings), PCD and PLY: at 2.5 cm (about the CLI's default there), 1 cm and 1 mm
// the files written back keep float64, so the grid need not hold under float32's 0.25 m spacing
// there (every bound was refused with "below the float32 resolution of the frame files written
// back").
TEST(ScanFormats, GivenFloat64MapCoordinatesInFramesOfTheirOwnCountsThenABoundHolds) {
  for (const Format format : {Format::kPCDFolder, Format::kPLYFolder}) {
    SCOPED_TRACE(format == Format::kPLYFolder ? "PLY" : "PCD");
    capz::Take t = spiral_take(format, {300, 280, 310});
    for (size_t i = 0; i < t.total_points(); ++i) {
      t.xyz[3 * i] += 500000.123456789;
      t.xyz[3 * i + 1] += 4000000.987654321;
    }
    const std::vector<capz::PCDField> f64 = {{"x", 'F', 8, 1}, {"y", 'F', 8, 1}, {"z", 'F', 8, 1}};
    if (format == Format::kPCDFolder) {
      t.pcd = std::make_shared<capz::PCDExtra>();
      t.pcd->fields = f64;
    } else {
      t.ply = std::make_shared<capz::PLYExtra>();
      t.ply->encoding = "binary_little_endian";
      t.ply->version = "1.0";
      t.ply->fields = f64;
      t.ply->type_names = {"double", "double", "double"};
      for (size_t f = 0; f < t.frames; ++f)
        t.ply->frame_names.push_back(std::to_string(f) + ".ply");
    }
    for (const double bound : {0.025, 0.01, 0.001}) {
      capz::CompressOptions o;
      o.max_error = bound;
      const std::vector<uint8_t> z = capz::compress(t, o);
      const capz::Take d = capz::decompress(z.data(), z.size());
      EXPECT_EQ(capz::describe(z.data(), z.size()).max_error, bound);
      ASSERT_EQ(d.frame_offsets, t.frame_offsets);
      ASSERT_EQ(d.valid, t.valid);
      double worst = 0;  // float64 written back: the decoded values as they are
      for (size_t i = 0; i < t.xyz.size(); ++i)
        if (t.valid[i / 3]) worst = std::max(worst, std::fabs(t.xyz[i] - d.xyz[i]));
      EXPECT_LE(worst, bound);
    }
  }
}

// A fixed take's stream (POSW) of .bin frames: lossless, without gaps and scattered like a mesh's
// vertices (the second frame the first moved a little), which the scan coder codes no smaller,
// so POSW is kept without the rest of the trial; the spiral sweeps code smaller through the scan
// coder (a ragged stream, HEAD bit 3 besides bit 4).
TEST(ScanFormats, GivenADamagedFrameFileCodeInHeadThenTheStreamIsRefusedByName) {
  capz::CompressOptions lossless;
  lossless.lossless = true;
  capz::Take t = bin_take({40, 40});
  std::fill(t.valid.begin(), t.valid.end(), uint8_t{1});
  ASSERT_EQ(t.points, 40u);  // a fixed take
  uint32_t seed = 7;
  const auto next = [&seed] { return (seed = seed * 1664525u + 1013904223u) >> 8; };
  for (size_t i = 0; i < 3 * t.points; ++i) {
    t.xyz[i] = capz_test::float32_value(static_cast<double>(next() % 20000) / 1000.0 - 10);
    t.xyz[3 * t.points + i] =
        capz_test::float32_value(t.xyz[i] + static_cast<double>(next() % 100) / 1000.0);
  }
  const std::vector<uint8_t> good = capz::compress(t, lossless);
  ASSERT_GT(capz::describe(good.data(), good.size()).chunk_bytes.count("POSW"), 0u);
  std::vector<capz_test::Piece> ps = capz_test::pieces(good);
  ASSERT_EQ(ps[0].type, "HEAD");
  EXPECT_EQ(ps[0].payload[16], 0);        // source_format: 0 with feature bit 4
  EXPECT_EQ(ps[0].payload[19] & 16, 16);  // feature bit 4
  EXPECT_EQ(ps[0].payload.back(), 4);     // frame_format: .bin
  ASSERT_EQ(capz_test::decode_error(capz_test::assemble(good, ps)), "");
  std::vector<capz_test::Piece> bad = ps;
  bad[0].payload.back() = 9;
  EXPECT_NE(
      capz_test::decode_error(capz_test::assemble(good, bad)).find("unknown frame-file format 9"),
      std::string::npos);
  bad = ps;
  bad[0].payload.back() = 3;  // a PCD folder is not a frame-file source code
  EXPECT_NE(
      capz_test::decode_error(capz_test::assemble(good, bad)).find("unknown frame-file format 3"),
      std::string::npos);
  bad = ps;
  bad[0].payload[16] = 3;
  EXPECT_NE(capz_test::decode_error(capz_test::assemble(good, bad))
                .find("frame-file source with source format 3"),
            std::string::npos);
  bad = ps;
  bad[0].payload.pop_back();  // frame_format missing
  EXPECT_NE(capz_test::decode_error(capz_test::assemble(good, bad)), "");
  // Bit 4 belongs to format 1.1: in a stream labelled 1.0 it is damage, not a newer feature.
  EXPECT_NE(capz_test::decode_error(with_minor(good, 0))
                .find("feature bit 4 (frame-file source) in a format 1.0 stream"),
            std::string::npos);
}

TEST(ScanFormats, GivenAPLYBlockInAStreamOfAnotherSourceThenItIsCorrupt) {
  // A .bin stream relabelled as a PLY one has no PLY block; a PLY stream relabelled .bin has a
  // PLY block where it may not.
  const std::vector<uint8_t> bin = compress_at(bin_take({40, 40}), 0.01);
  std::vector<capz_test::Piece> ps = capz_test::pieces(bin);
  ps[0].payload.back() = 5;
  EXPECT_NE(capz_test::decode_error(capz_test::assemble(bin, ps)).find("without a PLY block"),
            std::string::npos);
  const std::vector<uint8_t> ply = compress_at(ply_take({40, 40}, false), 0.01);
  ps = capz_test::pieces(ply);
  ps[0].payload.back() = 4;
  EXPECT_NE(capz_test::decode_error(capz_test::assemble(ply, ps)).find("not a PLY folder"),
            std::string::npos);
}

}  // namespace

// PLY has no 64-bit integers: a take with such a field is refused for PLY by name (the writer
// left the field out without a word), kept with --drop-fields, and written to PCD.
TEST(ScanFormats, GivenA64BitIntegerFieldThenPLYRefusesItByName) {
  capz::Take t = spiral_take(Format::kPCDFolder, {30, 30});
  t.pcd = std::make_shared<capz::PCDExtra>();
  capz::PointAttribute ts{"ts", 'U', 8, 1, std::vector<uint8_t>(60 * 8, 7)};
  t.attributes = {ts};
  capz_test::TempDir d;
  capz::WriteOptions ply;
  ply.folder_format = Format::kPLYFolder;
  std::string msg;
  EXPECT_EQ(capz_test::error_of([&] { capz::write_take(t, d.file("out") + "/", ply); }, &msg),
            capz::ErrorCode::kUsage);
  EXPECT_NE(msg.find("cannot hold the point fields ts"), std::string::npos) << msg;
  capz::WriteOptions drop;
  drop.folder_format = Format::kPLYFolder;
  drop.drop_fields = true;
  capz::write_take(t, d.file("dropped") + "/", drop);
  EXPECT_TRUE(capz::read_take(d.file("dropped")).attributes.empty());
}
