// C3D ROTATION sections (the extension Visual3D, Theia and ezc3d use): read from hand-laid
// bytes, written back with the layout ezc3d reads (per point frame, per sample, per segment 16
// column-major float32s and a reliability float32, from ROTATION:DATA_START), exact round trips.
#include <gtest/gtest.h>

#include <cmath>
#include <cstring>
#include <limits>
#include <memory>

#include "capz/error.h"
#include "capz/io.h"
#include "capz/stream.h"
#include "capz/tool/file.h"
#include "coding/quantiser.h"
#include "io/c3d_internal.h"
#include "test_util.h"

using namespace capz;

namespace {

C3DParameter int16_param(const std::string& name, int v) {
  C3DParameter p;
  p.name = name;
  c3d::set_int16(p, v);
  return p;
}
C3DParameter float_param(const std::string& name, float v) {
  C3DParameter p;
  p.name = name;
  c3d::set_float(p, v);
  return p;
}

// A value of element k of segment g at sample s: a slowly turning transform, with a NaN
// (payload 0x123) in segment 1's reliability at sample 3.
float element(size_t s, size_t g, size_t k) {
  if (k == 16) return s == 3 && g == 1 ? bits_float(0x7fc00123u) : 0.5f + 0.01f * float(s);
  const size_t row = k % 4, col = k / 4;
  if (row == 3) return col == 3 ? 1.0f : 0.0f;
  const float a = 0.02f * float(s) + float(g);
  if (col == 3) return 100.0f * float(row + 1) + float(s);
  return row == col ? std::cos(a) : (row + 1 == col ? std::sin(a) : -0.25f * std::sin(a));
}

struct Hand {
  size_t frames = 5, segments = 2, ratio = 2;
  size_t rot_block = 0;  // block of the rotation data
  std::vector<uint8_t> bytes;
};

// A C3D of no points and no analog whose only data is a ROTATION section, laid out by hand:
// header, parameter section (encoded by the library's parameter codec), then at
// ROTATION:DATA_START the samples, Intel floats. `extra_blocks` empty blocks before it.
Hand hand_made(size_t extra_blocks = 1) {
  Hand h;
  std::vector<C3DGroup> groups(2);
  groups[0].id = 1;
  groups[0].name = "POINT";
  groups[0].params = {int16_param("USED", 0), int16_param("FRAMES", static_cast<int>(h.frames)),
                      int16_param("DATA_START", 0), float_param("SCALE", -1.0f),
                      float_param("RATE", 50.0f)};
  groups[1].id = 2;
  groups[1].name = "ROTATION";
  groups[1].params = {int16_param("USED", static_cast<int>(h.segments)),
                      int16_param("RATIO", static_cast<int>(h.ratio)), float_param("RATE", 100.0f),
                      int16_param("DATA_START", 0)};
  C3DParameter labels;
  labels.name = "LABELS";
  c3d::set_strings(labels, {"pelvis", "thigh"});
  groups[1].params.push_back(labels);
  std::vector<uint8_t> params = c3d::encode_parameter_section(groups);
  const size_t data_start = 2 + params.size() / 512;
  h.rot_block = data_start + extra_blocks;
  c3d::set_int16(groups[0].params[2], static_cast<int>(data_start));
  c3d::set_int16(groups[1].params[3], static_cast<int>(h.rot_block));
  params = c3d::encode_parameter_section(groups);

  h.bytes.assign(512, 0);
  auto word = [&](int w, uint16_t v) { c3d::put_u16le(v, &h.bytes[2 * (w - 1)]); };
  h.bytes[0] = 2;
  h.bytes[1] = 0x50;
  word(2, 0);                                  // points
  word(3, 0);                                  // analog values per frame
  word(4, 1);                                  // first frame
  word(5, static_cast<uint16_t>(h.frames));    // last frame
  c3d::put_f32le(-1.0f, &h.bytes[12]);         // scale (float storage)
  word(9, static_cast<uint16_t>(data_start));  // data start
  c3d::put_f32le(50.0f, &h.bytes[20]);         // rate
  h.bytes.insert(h.bytes.end(), params.begin(), params.end());
  h.bytes.resize((h.rot_block - 1) * 512, 0);
  for (size_t s = 0; s < h.frames * h.ratio; ++s)
    for (size_t g = 0; g < h.segments; ++g)
      for (size_t k = 0; k < 17; ++k) {
        uint8_t b[4];
        c3d::put_f32le(element(s, g, k), b);
        h.bytes.insert(h.bytes.end(), b, b + 4);
      }
  return h;
}

void expect_same_rotations(const Rotations& a, const Rotations& b) {
  EXPECT_EQ(a.segments, b.segments);
  EXPECT_EQ(a.samples_per_frame, b.samples_per_frame);
  EXPECT_EQ(a.rate, b.rate);
  EXPECT_EQ(a.labels, b.labels);
  ASSERT_EQ(a.matrices.size(), b.matrices.size());
  ASSERT_EQ(a.reliability.size(), b.reliability.size());
  for (size_t i = 0; i < a.matrices.size(); ++i)
    ASSERT_EQ(float_bits(a.matrices[i]), float_bits(b.matrices[i])) << i;
  for (size_t i = 0; i < a.reliability.size(); ++i)
    ASSERT_EQ(float_bits(a.reliability[i]), float_bits(b.reliability[i])) << i;
}

bool has_warning(const Take& t, const std::string& part) {
  for (const auto& w : t.warnings)
    if (w.find(part) != std::string::npos) return true;
  return false;
}

// Points and analog too, with rotations at 3 samples per frame: a take not read from a C3D.
Take take_with_everything(size_t frames) {
  Take t;
  t.format = Format::kTRC;
  t.resize(frames, 2);
  t.rate = 60;
  t.units = "mm";
  t.labels = {"A", "B"};
  for (size_t i = 0; i < t.xyz.size(); ++i) t.xyz[i] = static_cast<float>(10.0 + 0.5 * double(i));
  t.valid.assign(frames * 2, 1);
  t.analog.channels = 1;
  t.analog.samples_per_frame = 2;
  t.analog.rate = 120;
  t.analog.labels = {"EMG"};
  for (size_t i = 0; i < frames * 2; ++i) t.analog.values.push_back(float(i) * 0.25f);
  Rotations& r = t.rotations;
  r.segments = 2;
  r.samples_per_frame = 3;
  r.rate = 180;
  r.labels = {"head", "arm"};
  for (size_t s = 0; s < frames * 3; ++s)
    for (size_t g = 0; g < 2; ++g) {
      for (size_t k = 0; k < 16; ++k) r.matrices.push_back(element(s, g, k));
      r.reliability.push_back(element(s, g, 16));
    }
  r.matrices[5] = -0.0f;
  r.matrices[6] = bits_float(0x00000001u);  // the smallest denormal
  r.matrices[7] = bits_float(0xff800001u);  // a signalling NaN, sign set
  return t;
}

}  // namespace

TEST(C3DRotations, HandMadeRotationsOnlyFileReadsEveryFrame) {
  const Hand h = hand_made();
  const Take t = read_c3d_bytes(h.bytes.data(), h.bytes.size(), "rot.c3d");
  EXPECT_TRUE(t.warnings.empty()) << t.warnings[0];
  EXPECT_EQ(t.frames, h.frames);
  EXPECT_EQ(t.points, 0u);
  const Rotations& r = t.rotations;
  ASSERT_EQ(r.segments, 2);
  EXPECT_EQ(r.samples_per_frame, 2);
  EXPECT_EQ(r.rate, 100.0);
  EXPECT_EQ(r.labels, (std::vector<std::string>{"pelvis", "thigh"}));
  ASSERT_EQ(r.samples(t.frames), 10u);
  ASSERT_EQ(r.matrices.size(), 10u * 2 * 16);
  ASSERT_EQ(r.reliability.size(), 10u * 2);
  for (size_t s = 0; s < 10; ++s)
    for (size_t g = 0; g < 2; ++g) {
      for (size_t k = 0; k < 16; ++k)
        ASSERT_EQ(float_bits(r.matrices[(s * 2 + g) * 16 + k]), float_bits(element(s, g, k)))
            << s << g << k;
      ASSERT_EQ(float_bits(r.reliability[s * 2 + g]), float_bits(element(s, g, 16)));
    }
  EXPECT_EQ(float_bits(r.reliability[3 * 2 + 1]), 0x7fc00123u);
}

TEST(C3DRotations, RatioFromRateWhenTheGroupHasNoRatio) {
  Hand h = hand_made();
  Take t = read_c3d_bytes(h.bytes.data(), h.bytes.size(), "rot.c3d");
  // Remove RATIO: RATE 100 / POINT:RATE 50 gives it (what ezc3d does).
  auto& ps = t.c3d->groups[1].params;
  ps.erase(ps.begin() + 1);
  std::vector<uint8_t> bytes = c3d::encode_c3d_file(t, {}, "rot.c3d");
  const Take back = read_c3d_bytes(bytes.data(), bytes.size(), "rot.c3d");
  EXPECT_EQ(back.c3d->param("ROTATION", "RATIO"), nullptr);  // not added: RATE says it
  EXPECT_EQ(back.rotations.samples_per_frame, 2);
  expect_same_rotations(back.rotations, t.rotations);
}

TEST(C3DRotations, TruncatedRotationSectionKeepsTheCompleteFrames) {
  Hand h = hand_made();
  h.bytes.resize(h.bytes.size() - 1);  // the last frame loses one byte
  const Take t = read_c3d_bytes(h.bytes.data(), h.bytes.size(), "cut.c3d");
  EXPECT_EQ(t.frames, h.frames - 1);
  EXPECT_TRUE(has_warning(t, "the rotation section holds 4")) << t.warnings.size();
  EXPECT_EQ(t.rotations.matrices.size(), (h.frames - 1) * 2 * 2 * 16);
}

TEST(C3DRotations, WrittenBackExactlyWithDataStartAfterTheFrames) {
  const Hand h = hand_made(3);
  const Take t = read_c3d_bytes(h.bytes.data(), h.bytes.size(), "rot.c3d");
  const std::vector<uint8_t> out = c3d::encode_c3d_file(t, {}, "out.c3d");
  const Take back = read_c3d_bytes(out.data(), out.size(), "out.c3d");
  EXPECT_TRUE(back.warnings.empty()) << back.warnings[0];
  EXPECT_EQ(back.frames, t.frames);
  expect_same_rotations(back.rotations, t.rotations);
  // No frames of points: the rotations start at the data block, and the writer's bytes there
  // are the hand-made file's rotation bytes.
  const long data_start = static_cast<long>(c3d::number_param(*back.c3d, "POINT", "DATA_START", 0));
  const long rot_start =
      static_cast<long>(c3d::number_param(*back.c3d, "ROTATION", "DATA_START", 0));
  EXPECT_EQ(rot_start, data_start);
  const size_t n = t.frames * 2 * 2 * c3d::kRotationBytes;
  ASSERT_EQ(out.size(), static_cast<size_t>(rot_start - 1) * 512 + n);
  EXPECT_TRUE(std::equal(out.end() - static_cast<long>(n), out.end(),
                         h.bytes.begin() + static_cast<long>((h.rot_block - 1) * 512)));
}

TEST(C3DRotations, TakeWithPointsAnalogAndRotationsRoundTrips) {
  const Take t = take_with_everything(7);
  const std::vector<uint8_t> out = c3d::encode_c3d_file(t, {}, "all.c3d");
  const Take back = read_c3d_bytes(out.data(), out.size(), "all.c3d");
  EXPECT_TRUE(back.warnings.empty()) << back.warnings[0];
  ASSERT_EQ(back.frames, 7u);
  EXPECT_EQ(back.xyz, t.xyz);
  EXPECT_EQ(back.analog.values, t.analog.values);
  expect_same_rotations(back.rotations, t.rotations);
  // The rotation block follows the frames' last block.
  const size_t data_start =
      static_cast<size_t>(c3d::number_param(*back.c3d, "POINT", "DATA_START", 0));
  const size_t rot_start =
      static_cast<size_t>(c3d::number_param(*back.c3d, "ROTATION", "DATA_START", 0));
  const size_t frame_bytes = 7 * (2 * 4 + 2) * 4;
  EXPECT_EQ(rot_start, data_start + (frame_bytes + 511) / 512);
  // Written again from what was read: the same bytes.
  EXPECT_EQ(c3d::encode_c3d_file(back, {}, "all.c3d"), out);
}

TEST(C3DRotations, StreamedReadAndWriteKeepThem) {
  capz_test::TempDir tmp("capz_rot");
  const Take t = take_with_everything(40);
  write_c3d(t, tmp.file("a.c3d"));
  std::unique_ptr<FrameSource> src = open_c3d_frames(tmp.file("a.c3d"));
  // The header has the layout, the blocks the samples (read by ranges of the section).
  Rotations blocks = src->header().rotations;
  EXPECT_TRUE(blocks.matrices.empty() && blocks.reliability.empty());
  FrameBlock b;
  for (size_t f = 0; f < t.frames; f += 7) {
    src->read(f, 7, &b);
    blocks.matrices.insert(blocks.matrices.end(), b.rotation_matrices.begin(),
                           b.rotation_matrices.end());
    blocks.reliability.insert(blocks.reliability.end(), b.rotation_reliability.begin(),
                              b.rotation_reliability.end());
  }
  expect_same_rotations(blocks, t.rotations);
  auto sink = create_frame_sink(src->header(), src->has_sample_words(), tmp.file("b.c3d"));
  copy_frames(*src, *sink, 16);
  const Take a = read_c3d(tmp.file("a.c3d")), back = read_c3d(tmp.file("b.c3d"));
  expect_same_rotations(back.rotations, a.rotations);
  EXPECT_EQ(back.xyz, a.xyz);
  EXPECT_TRUE(read_file(tmp.file("a.c3d")) == read_file(tmp.file("b.c3d")));
}

TEST(C3DRotations, ATakeWithoutRotationsKeepsAReadGroupConsistent) {
  const Hand h = hand_made();
  Take t = read_c3d_bytes(h.bytes.data(), h.bytes.size(), "rot.c3d");
  t.rotations = Rotations();  // dropped since reading
  const std::vector<uint8_t> out = c3d::encode_c3d_file(t, {}, "none.c3d");
  const Take back = read_c3d_bytes(out.data(), out.size(), "none.c3d");
  EXPECT_EQ(back.rotations.segments, 0);
  EXPECT_EQ(c3d::number_param(*back.c3d, "ROTATION", "USED", -1), 0);
  EXPECT_EQ(back.frames, 0u);  // frames of nothing are not kept
}

TEST(C3DRotations, MismatchedArraysAreRefusedByTheWriter) {
  Take t = take_with_everything(3);
  t.rotations.reliability.pop_back();
  try {
    c3d::encode_c3d_file(t, {}, "bad.c3d");
    FAIL() << "no error";
  } catch (const Error& e) {
    EXPECT_EQ(e.code(), ErrorCode::kInternal);
  }
}

TEST(C3DRotations, MissingDataStartIsAWarningNotACrash) {
  Hand h = hand_made();
  Take t = read_c3d_bytes(h.bytes.data(), h.bytes.size(), "rot.c3d");
  t.c3d->groups[1].params.erase(t.c3d->groups[1].params.begin() + 3);  // DATA_START
  std::vector<uint8_t> params = c3d::encode_parameter_section(t.c3d->groups);
  std::vector<uint8_t> bytes(h.bytes.begin(), h.bytes.begin() + 512);
  bytes.insert(bytes.end(), params.begin(), params.end());
  const Take back = read_c3d_bytes(bytes.data(), bytes.size(), "nostart.c3d");
  EXPECT_EQ(back.rotations.segments, 0);
  EXPECT_TRUE(has_warning(back, "ROTATION:DATA_START")) << back.warnings.size();
}

TEST(C3DRotations, CountsBeyondWhatAC3DHoldsAreAWarning) {
  Hand h = hand_made();
  Take t = read_c3d_bytes(h.bytes.data(), h.bytes.size(), "rot.c3d");
  for (const char* name : {"USED", "RATIO"}) {
    std::vector<C3DGroup> groups = t.c3d->groups;
    c3d::set_float(*c3d::find_param(groups[1], name), 3.0e9f);
    const std::vector<uint8_t> params = c3d::encode_parameter_section(groups);
    std::vector<uint8_t> bytes = h.bytes;  // the same file with these parameters
    ASSERT_LE(512 + params.size(), (h.rot_block - 1) * 512);
    std::copy(params.begin(), params.end(), bytes.begin() + 512);
    const Take back = read_c3d_bytes(bytes.data(), bytes.size(), "huge.c3d");
    EXPECT_EQ(back.rotations.segments, 0) << name;
    EXPECT_TRUE(has_warning(back, "beyond what a C3D holds")) << name;
  }
}
