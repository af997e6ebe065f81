// The rotation fields of HEAD and META (docs/FORMAT.md 4.4, 5.6), byte by byte as the spec lays
// them out, and the promise rule (capz/verify.h) on rotations: every bit, the layout and the
// labels.
#include <gtest/gtest.h>

#include <cstring>
#include <vector>

#include "capz/error.h"
#include "capz/verify.h"
#include "coding/container.h"
#include "coding/meta.h"
#include "coding/quantiser.h"

namespace capz {
namespace {

Chunk as_chunk(const std::vector<uint8_t>& payload, const char* type) {
  Chunk c;
  c.type = type;
  c.payload = payload.data();
  c.size = payload.size();
  return c;
}

uint32_t le32(const std::vector<uint8_t>& b, size_t at) {
  return static_cast<uint32_t>(b[at]) | static_cast<uint32_t>(b[at + 1]) << 8 |
         static_cast<uint32_t>(b[at + 2]) << 16 | static_cast<uint32_t>(b[at + 3]) << 24;
}

StreamHeader grid_header() {
  StreamHeader h;
  h.frames = 100;
  h.points = 3;
  h.window_frames = 16;
  h.source_format = Format::kC3D;
  h.step = 0.5;
  h.max_error = 0.25;
  return h;
}

TEST(RotationHead, FieldsFollowTheAnalogFieldsBehindFlagBit2) {
  StreamHeader h = grid_header();
  const std::vector<uint8_t> plain = encode_header(h);
  ASSERT_EQ(plain.size(), 44u);  // 3.1's HEAD, unchanged without rotations
  EXPECT_EQ(plain[19], 0);
  h.rotation_segments = 7;
  h.rotation_samples_per_frame = 3;
  const std::vector<uint8_t> rot = encode_header(h);
  ASSERT_EQ(rot.size(), 52u);
  EXPECT_EQ(rot[19], 4);  // flags: bit 2
  EXPECT_TRUE(std::equal(plain.begin(), plain.begin() + 19, rot.begin()));
  EXPECT_TRUE(std::equal(plain.begin() + 20, plain.end(), rot.begin() + 20));
  EXPECT_EQ(le32(rot, 44), 7u);
  EXPECT_EQ(le32(rot, 48), 3u);
  const StreamHeader back = decode_header(as_chunk(rot, "HEAD"), "t");
  EXPECT_EQ(back.rotation_segments, 7u);
  EXPECT_EQ(back.rotation_samples_per_frame, 3u);
  EXPECT_EQ(decode_header(as_chunk(plain, "HEAD"), "t").rotation_segments, 0u);
}

TEST(RotationHead, AfterTheKgTargetWithTransformOutput) {
  StreamHeader h = grid_header();
  h.codec = 1;
  h.step = h.max_error = 0;
  h.transform_output = true;
  h.kg_target = 2.5;
  h.rotation_segments = 2;
  h.rotation_samples_per_frame = 1;
  const std::vector<uint8_t> b = encode_header(h);
  ASSERT_EQ(b.size(), 60u);
  EXPECT_EQ(b[19], 2 | 4);
  double kg;
  std::memcpy(&kg, &b[44], 8);  // the test machine is little-endian, as the format
  EXPECT_EQ(kg, 2.5);
  EXPECT_EQ(le32(b, 52), 2u);
  EXPECT_EQ(le32(b, 56), 1u);
  const StreamHeader back = decode_header(as_chunk(b, "HEAD"), "t");
  EXPECT_EQ(back.kg_target, 2.5);
  EXPECT_EQ(back.rotation_segments, 2u);
}

TEST(RotationHead, FitsCountsTheRotationValues) {
  StreamHeader h = grid_header();
  h.rotation_segments = 100;
  h.rotation_samples_per_frame = 10;  // 100 frames: 1.7e6 values
  EXPECT_NO_THROW(check_header_fits(h, 1000, kCapzMajor, "t"));
  EXPECT_THROW(check_header_fits(h, 500, kCapzMajor, "t"), Error);
}

TEST(RotationMeta, RateAndLabelsAreAppendedWhenTheTakeHasRotations) {
  Take t;
  t.frames = 4;
  t.units = "mm";
  const std::vector<uint8_t> plain = encode_meta(t, false);
  t.rotations.segments = 2;
  t.rotations.samples_per_frame = 1;
  t.rotations.rate = 120;
  t.rotations.labels = {"head", "arm"};
  const std::vector<uint8_t> rot = encode_meta(t, false);
  EXPECT_GT(rot.size(), plain.size());
  Take back;
  back.frames = 4;
  back.rotations.segments = 2;  // from HEAD
  back.rotations.samples_per_frame = 1;
  bool words = true;
  decode_meta(as_chunk(rot, "META"), "t", &back, &words, 8);
  EXPECT_EQ(back.rotations.rate, 120);
  EXPECT_EQ(back.rotations.labels, t.rotations.labels);
  EXPECT_EQ(back.units, "mm");
  // Without HEAD's rotations the appended fields are not read (as fields of a later version).
  Take none;
  none.frames = 4;
  decode_meta(as_chunk(rot, "META"), "t", &none, &words, 8);
  EXPECT_TRUE(none.rotations.labels.empty());
  // HEAD says rotations, META lacks their fields: corrupt.
  try {
    decode_meta(as_chunk(plain, "META"), "t", &back, &words, 8);
    FAIL() << "accepted";
  } catch (const Error& e) {
    EXPECT_EQ(e.code(), ErrorCode::kCorrupt) << e.what();
  }
}

Take rotation_take() {
  Take t;
  t.frames = 2;
  t.rotations.segments = 1;
  t.rotations.samples_per_frame = 2;
  t.rotations.labels = {"seg"};
  t.rotations.matrices.assign(2 * 2 * 16, 0.25f);
  t.rotations.reliability.assign(2 * 2, 1.0f);
  t.rotations.reliability[3] = bits_float(0x7fc00001u);
  return t;
}

TEST(RotationPromise, EveryBitAndTheLayoutCount) {
  const Take a = rotation_take();
  EXPECT_TRUE(check_promise(a, a, Promise()).holds);
  Take b = a;
  b.rotations.reliability[3] = bits_float(0x7fc00002u);  // another NaN payload
  PromiseResult r = check_promise(a, b, Promise());
  EXPECT_FALSE(r.holds);
  EXPECT_NE(r.why.find("rotation samples"), std::string::npos) << r.why;
  b = a;
  b.rotations.matrices[7] = -0.0f;  // 0.25 -> -0.0
  EXPECT_FALSE(check_promise(a, b, Promise()).holds);
  Promise bound;  // a bound on coordinates does not loosen the rotations
  bound.kind = Promise::Kind::kBound;
  bound.max_error = 1;
  EXPECT_FALSE(check_promise(a, b, bound).holds);
  b = a;
  b.rotations.labels = {"other"};
  r = check_promise(a, b, Promise());
  EXPECT_NE(r.why.find("rotation layout"), std::string::npos) << r.why;
}

}  // namespace
}  // namespace capz
