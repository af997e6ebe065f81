// Rotations in a .capz (docs/FORMAT.md 12): a C3D with a ROTATION section, built here, comes
// back with every rotation bit (NaN payloads, -0.0, denormals) through compress / decompress,
// through the streamed paths (C3D source -> .capz file -> C3D sink), lossless and at a bound,
// with and without points, over several windows; damaged ROTW chunks are corrupt.
#include <gtest/gtest.h>

#include <cmath>
#include <cstring>
#include <memory>
#include <string>
#include <vector>

#include "capz/codec.h"
#include "capz/error.h"
#include "capz/file.h"
#include "capz/io.h"
#include "capz/stream.h"
#include "capz/verify.h"
#include "coding/quantiser.h"
#include "support/stream_pieces.h"
#include "support/without_original.h"
#include "test_util.h"

namespace capz {
namespace {

// Element k of segment g at rotation sample s: a turning transform, with special values in
// places (a NaN with a payload, -0.0, a denormal, a signalling NaN, an infinity).
float element(size_t s, size_t g, size_t k) {
  if (k == 16) return s % 11 == 3 && g == 1 ? bits_float(0x7fc00123u) : 0.5f + 0.01f * float(s);
  if (s == 5 && g == 0) return k == 2 ? -0.0f : k == 6 ? bits_float(1u) : bits_float(0xff800001u);
  if (s == 9 && k == 13) return -std::numeric_limits<float>::infinity();
  const size_t row = k % 4, col = k / 4;
  if (row == 3) return col == 3 ? 1.0f : 0.0f;
  const float a = 0.02f * float(s) + float(g);
  if (col == 3) return 100.0f * float(row + 1) + std::sin(0.1f * float(s));
  return row == col ? std::cos(a) : -0.25f * std::sin(a);
}

// A take of `frames` frames, `points` points (0: rotations only) and 3 rotation segments at 2
// samples per frame, written as a float C3D at `path` and read back (so it has the C3D extras
// and the ROTATION group a reader finds).
Take c3d_with_rotations(const std::string& path, size_t frames, size_t points) {
  Take t;
  t.format = Format::kC3D;
  t.resize(frames, points);
  t.rate = 50;
  t.units = "mm";
  for (size_t p = 0; p < points; ++p) t.labels.push_back("M" + std::to_string(p));
  for (size_t f = 0; f < frames; ++f)
    for (size_t p = 0; p < points; ++p) {
      t.valid[f * points + p] = (f + p) % 13 != 4;
      for (int a = 0; a < 3; ++a)
        t.at(f, p)[a] = t.valid[f * points + p]
                            ? static_cast<float>(100.0 * (p + 1) + 10 * std::sin(0.05 * f + a))
                            : 0.0;
    }
  Rotations& r = t.rotations;
  r.segments = 3;
  r.samples_per_frame = 2;
  r.rate = 100;
  r.labels = {"pelvis", "thigh", ""};
  for (size_t s = 0; s < frames * 2; ++s)
    for (size_t g = 0; g < 3; ++g) {
      for (size_t k = 0; k < 16; ++k) r.matrices.push_back(element(s, g, k));
      r.reliability.push_back(element(s, g, 16));
    }
  WriteOptions wo;
  wo.c3d_float = true;
  wo.overwrite = true;
  write_c3d(t, path, wo);
  return read_c3d(path);
}

bool same_bits(const std::vector<float>& a, const std::vector<float>& b) {
  return a.size() == b.size() &&
         (a.empty() || std::memcmp(a.data(), b.data(), a.size() * sizeof(float)) == 0);
}

void expect_same_rotations(const Rotations& a, const Rotations& b) {
  EXPECT_EQ(a.segments, b.segments);
  EXPECT_EQ(a.samples_per_frame, b.samples_per_frame);
  EXPECT_EQ(a.rate, b.rate);
  EXPECT_EQ(a.labels, b.labels);
  EXPECT_TRUE(same_bits(a.matrices, b.matrices));
  EXPECT_TRUE(same_bits(a.reliability, b.reliability));
}

CompressOptions options(bool lossless) {
  CompressOptions o;
  o.lossless = lossless;
  o.max_error = lossless ? 0 : 0.5;
  o.window_frames = 16;
  return o;
}

class RotationsRoundTrip : public ::testing::TestWithParam<size_t> {};  // points

TEST_P(RotationsRoundTrip, CompressDecompressKeepsEveryBitLosslessAndAtABound) {
  capz_test::TempDir tmp("capz_rot_rt");
  const Take t = c3d_with_rotations(tmp.file("a.c3d"), 45, GetParam());
  ASSERT_EQ(t.rotations.segments, 3);
  ASSERT_EQ(t.frames, 45u);  // with no points the frames come from the rotations
  for (bool lossless : {true, false}) {
    SCOPED_TRACE(lossless ? "lossless" : "0.5 mm");
    const std::vector<uint8_t> bytes = compress(t, options(lossless));
    const StreamInfo si = describe(bytes.data(), bytes.size());
    EXPECT_EQ(si.rotation_segments, 3);
    EXPECT_EQ(si.rotation_samples_per_frame, 2);
    EXPECT_EQ(si.rotation_rate, 100);
    EXPECT_EQ(si.rotation_labels, t.rotations.labels);
    EXPECT_GT(si.chunk_bytes.count("ROTW"), 0u);
    const Take b = decompress(bytes.data(), bytes.size());
    expect_same_rotations(b.rotations, t.rotations);
    const PromiseResult pr = check_promise(t, b, promise_of(si));
    EXPECT_TRUE(pr.holds) << pr.why;
    // A range: the rotations of its frames only.
    const Take part = decompress_frames(bytes.data(), bytes.size(), 10, 20);
    const size_t per_frame = 2 * 3;
    ASSERT_EQ(part.rotations.reliability.size(), 20 * per_frame);
    EXPECT_EQ(0, std::memcmp(part.rotations.matrices.data(),
                             t.rotations.matrices.data() + 10 * per_frame * 16,
                             20 * per_frame * 16 * sizeof(float)));
    if (lossless) {  // written back: the same C3D file
      WriteOptions wo;
      wo.overwrite = true;
      write_take(b, tmp.file("b.c3d"), wo);
      EXPECT_TRUE(read_file(tmp.file("a.c3d")) == read_file(tmp.file("b.c3d")));
    }
  }
}

TEST_P(RotationsRoundTrip, StreamedBothWaysGivesTheSameStreamAndTheSameFile) {
  capz_test::TempDir tmp("capz_rot_stream");
  const Take t = c3d_with_rotations(tmp.file("a.c3d"), 45, GetParam());
  const CompressOptions o = options(true);
  // Without the original file (whose HASH and residue chunks compress() of a take cannot
  // write), the streamed bytes are compress()'s.
  capz_test::WithoutOriginal src(open_c3d_frames(tmp.file("a.c3d")));
  compress_stream(src, o, tmp.file("a.capz"), true);
  const std::vector<uint8_t> streamed = read_file(tmp.file("a.capz"));
  EXPECT_TRUE(streamed == compress(t, o));
  // Decoded a window at a time, and in blocks that straddle windows (the C3D sink writes each
  // block's rotations at their place in the rotation section).
  for (size_t block : {size_t{16}, size_t{7}}) {
    std::unique_ptr<FrameSource> dec = open_capz_frames(tmp.file("a.capz"));
    expect_same_rotations(dec->header().rotations, [&] {
      Rotations r = t.rotations;
      r.matrices.clear();
      r.reliability.clear();
      return r;
    }());
    WriteOptions wo;
    wo.overwrite = true;
    std::unique_ptr<FrameSink> sink =
        create_frame_sink(dec->header(), dec->has_sample_words(), tmp.file("b.c3d"), wo);
    copy_frames(*dec, *sink, block);
    EXPECT_TRUE(read_file(tmp.file("a.c3d")) == read_file(tmp.file("b.c3d"))) << block;
  }
}

// An int16 C3D whose scale comes from the data is written whole at commit (the sink collects
// the blocks): its rotations are collected with them.
TEST_P(RotationsRoundTrip, TheWholeTakeSinkCollectsTheBlocksRotations) {
  capz_test::TempDir tmp("capz_rot_whole");
  Take t = c3d_with_rotations(tmp.file("a.c3d"), 45, GetParam());
  auto x = std::make_shared<C3DExtra>(*t.c3d);
  x->float_storage = false;
  x->point_scale = 0;  // no usable scale: the int16 scale comes from the data
  t.c3d = x;
  WriteOptions wo;
  wo.overwrite = true;
  write_take(t, tmp.file("whole.c3d"), wo);
  std::unique_ptr<FrameSource> src = take_frames(t);
  std::unique_ptr<FrameSink> sink =
      create_frame_sink(src->header(), src->has_sample_words(), tmp.file("blocks.c3d"), wo);
  copy_frames(*src, *sink, 7);
  EXPECT_TRUE(read_file(tmp.file("whole.c3d")) == read_file(tmp.file("blocks.c3d")));
  expect_same_rotations(read_c3d(tmp.file("blocks.c3d")).rotations, t.rotations);
}

INSTANTIATE_TEST_SUITE_P(Points, RotationsRoundTrip, ::testing::Values(size_t{0}, size_t{4}));

using capz_test::decode_error;

TEST(RotationsRoundTrip, ATakeWithoutRotationsHasNoRotationChunks) {
  Take t;
  t.resize(20, 2);
  t.valid.assign(40, 1);
  t.units = "mm";
  const std::vector<uint8_t> bytes = compress(t, options(true));
  const StreamInfo si = describe(bytes.data(), bytes.size());
  EXPECT_EQ(si.rotation_segments, 0);
  EXPECT_EQ(si.chunk_bytes.count("ROTW"), 0u);
  EXPECT_EQ(si.chunk_bytes.at("HEAD"), 12u + 44u);  // HEAD as before 4.3: no rotation fields
}

TEST(RotationsRoundTrip, MismatchedRotationArraysAreRefused) {
  capz_test::TempDir tmp("capz_rot_bad");
  Take t = c3d_with_rotations(tmp.file("a.c3d"), 10, 2);
  t.rotations.reliability.pop_back();
  try {
    compress(t, options(true));
    FAIL() << "accepted";
  } catch (const Error& e) {
    EXPECT_EQ(e.code(), ErrorCode::kInvalidParameter) << e.what();
  }
}

// ---- damaged ROTW chunks (CRCs and INDX made valid again, so only the change is wrong) -------

TEST(RotationsCorrupt, DamagedRotwChunksAreCorrupt) {
  capz_test::TempDir tmp("capz_rot_corrupt");
  const Take t = c3d_with_rotations(tmp.file("a.c3d"), 40, 2);
  const std::vector<uint8_t> good = compress(t, options(false));
  using capz_test::Piece;
  ASSERT_EQ(capz_test::assemble(good, capz_test::pieces(good)), good);
  // Applies `change` to window 1's ROTW (or removes it) and returns the reassembled stream.
  auto with_rotw = [&](auto change) {
    std::vector<Piece> ps = capz_test::pieces(good);
    size_t seen = 0;
    for (size_t i = 0; i < ps.size(); ++i)
      if (ps[i].type == "ROTW" && seen++ == 1) {
        if (!change(&ps[i].payload)) ps.erase(ps.begin() + static_cast<long>(i));
        break;
      }
    return capz_test::assemble(good, ps);
  };
  // Payload: window varint (1), 4 predictor bytes, then the block.
  EXPECT_NE(decode_error(with_rotw([](std::vector<uint8_t>*) {
              return false;
            })).find("missing chunk ROTW"),
            std::string::npos);
  EXPECT_NE(decode_error(with_rotw([](std::vector<uint8_t>* p) {
              (*p)[0] = 2;
              return true;
            })).find("window"),
            std::string::npos);
  EXPECT_NE(decode_error(with_rotw([](std::vector<uint8_t>* p) {
              (*p)[2] = 3;
              return true;
            })).find("predictor"),
            std::string::npos);
  EXPECT_FALSE(decode_error(with_rotw([](std::vector<uint8_t>* p) {
                 p->resize(p->size() - 3);
                 return true;
               })).empty());
  EXPECT_FALSE(decode_error(with_rotw([](std::vector<uint8_t>* p) {
                 p->resize(5);
                 return true;
               })).empty());
  EXPECT_FALSE(decode_error(with_rotw([](std::vector<uint8_t>* p) {
                 p->push_back(0);
                 return true;
               })).empty());
  // Every byte of the block changed in turn (CRC fixed up): corrupt, or harmless (a block's
  // last bytes may not change what it decodes to; a range coder has no redundancy to catch
  // most changes: the CRC does that).
  std::vector<Piece> ps = capz_test::pieces(good);
  size_t at = 0;
  while (ps[at].type != "ROTW") ++at;
  size_t caught = 0, tried = 0;
  for (size_t i = 5; i < ps[at].payload.size(); ++i, ++tried) {
    std::vector<Piece> q = ps;
    q[at].payload[i] ^= 0x5a;
    const std::vector<uint8_t> b = capz_test::assemble(good, q);
    try {
      const Take back = decompress(b.data(), b.size());
      EXPECT_EQ(back.rotations.matrices.size(), t.rotations.matrices.size());
    } catch (const Error& e) {
      EXPECT_EQ(e.code(), ErrorCode::kCorrupt) << e.what();
      ++caught;
    }
  }
  EXPECT_GT(caught, 0u);
  EXPECT_GT(tried, 0u);
}

TEST(RotationsCorrupt, HeadRotationFieldsAreChecked) {
  capz_test::TempDir tmp("capz_rot_head");
  const Take t = c3d_with_rotations(tmp.file("a.c3d"), 20, 2);
  const std::vector<uint8_t> good = compress(t, options(true));
  auto with_head = [&](auto change) {
    std::vector<capz_test::Piece> ps = capz_test::pieces(good);
    change(&ps[0].payload);
    return capz_test::assemble(good, ps);
  };
  // HEAD: flags @19, rotation_segments @44, rotation_samples_per_frame @48 (no kg_target).
  ASSERT_EQ(capz_test::pieces(good)[0].payload.size(), 52u);
  EXPECT_NE(decode_error(with_head([](std::vector<uint8_t>* h) { (*h)[44] = 0; })).find("0 segm"),
            std::string::npos);
  EXPECT_NE(decode_error(with_head([](std::vector<uint8_t>* h) { (*h)[48] = 0; })).find("0 segm"),
            std::string::npos);
  EXPECT_FALSE(decode_error(with_head([](std::vector<uint8_t>* h) { h->resize(48); })).empty());
  EXPECT_FALSE(decode_error(with_head([](std::vector<uint8_t>* h) { (*h)[47] = 0x40; })).empty());
  // More segments than the file can hold, caught before anything is allocated.
  EXPECT_NE(decode_error(with_head([](std::vector<uint8_t>* h) {
              (*h)[46] = 0xff;
            })).find("more samples than the file"),
            std::string::npos);
}

}  // namespace
}  // namespace capz
