// ts payloads with point segments (version 2, docs/CODEC-TS.md "Payload"): hand-built payloads
// with inconsistent segment fields are rejected as corrupt, a consistent one decodes; a real
// version-2 payload, truncated or with its segment count altered, never crashes.
#include <gtest/gtest.h>

#include <algorithm>
#include <cmath>
#include <string>
#include <vector>

#include "capz/error.h"
#include "codec/ts/ts_encoder.h"
#include "coding/bytes.h"
#include "coding/entropy.h"

using namespace capz;

namespace {

constexpr int kSegmentCtx = 384;  // docs/CODEC-TS.md: segment labels use 384 + previous segment
constexpr int kContexts = 448;

// A version-2 payload of 1 frame x `points`, K = 1, no rigid motion, no basis prediction, S
// segments each with zero PCs: header, S unit headers, then the block holding only the segment
// ranks. With zero PCs the reconstruction is all zeros.
// With `centre` (flags bit 2): per segment steps 1, 1, that centre, LPC order 0, and a rigid
// block of 6 zeros (the identity): segment s then decodes to centre + s.
std::vector<uint8_t> payload(size_t points, int s_field, const std::vector<uint32_t>& ranks,
                             int units = -1, const double* centre = nullptr) {
  ByteWriter w;
  w.u8(2);               // version
  w.u8(centre ? 4 : 0);  // flags
  w.varint(1);           // frames
  w.varint(points);
  w.f64(1.0);  // coef_step
  w.u8(1);     // K
  w.u8(static_cast<uint8_t>(s_field));
  if (centre)
    for (int sg = 0; sg < s_field; ++sg) {
      w.f64(1.0);
      w.f64(1.0);
      for (int a = 0; a < 3; ++a) w.f64(centre[a] + sg);
      w.u8(0);
      w.u8(0);
    }
  for (int u = 0; u < (units < 0 ? s_field : units); ++u) {
    w.varint(0);  // r
    w.u8(0);      // LPC order
    w.u8(0);      // LPC weight bits
    w.u8(4);      // LCPS weight bits
  }
  IntEncoder e(kContexts);
  // The ranks are coded under the context of the previous point's segment, which the MTF list
  // gives: replay it here.
  std::vector<int> mtf;
  for (int i = 0; i < std::max(s_field, 1); ++i) mtf.push_back(i);
  int prev = 0;
  for (uint32_t r : ranks) {
    e.put(r, kSegmentCtx + std::min(prev, 63));
    if (r < mtf.size()) {
      const int seg = mtf[r];
      mtf.erase(mtf.begin() + r);
      mtf.insert(mtf.begin(), seg);
      prev = seg;
    }
  }
  if (centre)
    for (int i = 0; i < 6 * s_field; ++i) e.put_signed(0, 1 * 16);  // group 1 (rigid), context 16
  w.bytes(e.finish());
  return w.buffer();
}

void expect_corrupt(const std::vector<uint8_t>& p, size_t points, const std::string& what) {
  TsCodec codec;
  std::vector<double> out;
  try {
    codec.decode(p.data(), p.size(), 1, points, &out);
    ADD_FAILURE() << what << ": accepted";
  } catch (const Error& e) {
    EXPECT_EQ(e.code(), ErrorCode::kCorrupt) << what << ": " << e.what();
  }
}

}  // namespace

TEST(TsPayloadSegments, GivenConsistentHandBuiltPayloadThenDecodes) {
  TsCodec codec;
  std::vector<double> out;
  const auto p = payload(4, 2, {0, 1, 0, 1});  // segments 0, 1, 1, 0
  codec.decode(p.data(), p.size(), 1, 4, &out);
  EXPECT_EQ(out, std::vector<double>(12, 0.0));
}

// Per-segment rigid motion with zero PCs: every point decodes to its segment's centre (the
// identity motion, then + c_s); a centre that is not finite is corrupt.
TEST(TsPayloadSegments, GivenSegmentMotionThenCentreAppliedAndNonFiniteCentreCorrupt) {
  TsCodec codec;
  std::vector<double> out;
  const double c[3] = {10.5, -2.0, 0.25};
  const auto p = payload(4, 2, {0, 1, 0, 1}, -1, c);  // segments 0, 1, 1, 0
  codec.decode(p.data(), p.size(), 1, 4, &out);
  const int seg[4] = {0, 1, 1, 0};
  ASSERT_EQ(out.size(), 12u);
  for (int i = 0; i < 4; ++i)
    for (int a = 0; a < 3; ++a) EXPECT_EQ(out[3 * i + a], c[a] + seg[i]) << i << " " << a;
  const double bad[3] = {1.0, NAN, 0.0};
  expect_corrupt(payload(4, 2, {0, 1, 0, 1}, -1, bad), 4, "a NaN centre");
  const double inf[3] = {INFINITY, 0.0, 0.0};
  expect_corrupt(payload(4, 2, {0, 1, 0, 1}, -1, inf), 4, "an infinite centre");
}

TEST(TsPayloadSegments, GivenInconsistentSegmentFieldsThenCorrupt) {
  expect_corrupt(payload(4, 1, {0, 0, 0, 0}), 4, "S = 1 in a version-2 payload");
  expect_corrupt(payload(4, 5, {0, 1, 2, 3}), 4, "S larger than the points");
  expect_corrupt(payload(100, 65, std::vector<uint32_t>(100, 0)), 100, "S above 64");
  expect_corrupt(payload(4, 2, {0, 2, 0, 0}), 4, "a segment rank >= S");
  expect_corrupt(payload(4, 3, {0, 1, 0, 1}), 4, "an empty segment");
  expect_corrupt(payload(4, 2, {0, 0, 0, 0}), 4, "an empty segment (all points in one)");
  expect_corrupt(payload(4, 2, {0, 1, 0, 1}, 1), 4, "fewer unit headers than S x K");
  std::vector<uint8_t> p = payload(4, 2, {0, 1, 0, 1});
  p[1] = 16;
  expect_corrupt(p, 4, "unknown flag bit 4");
  p[1] = 4;  // per-segment rigid motion announced, its headers absent
  expect_corrupt(p, 4, "segment motion headers missing");
  p[1] = 0;
  p[0] = 3;
  TsCodec codec;
  std::vector<double> out;
  try {
    codec.decode(p.data(), p.size(), 1, 4, &out);
    ADD_FAILURE() << "version 3 accepted";
  } catch (const Error& e) {
    EXPECT_EQ(e.code(), ErrorCode::kUnsupportedVersion);
  }
}

// A real version-2 payload (planted moving groups, 4 segments): every truncation is rejected;
// the segment count byte set to every other value is rejected or decodes, never crashes.
TEST(TsPayloadSegments, GivenRealSegmentedPayloadTruncatedOrAlteredThenCorruptNotCrash) {
  const size_t frames = 20, points = 200;
  std::vector<double> xyz(frames * points * 3);
  std::vector<uint8_t> valid(frames * points, 1);
  for (size_t f = 0; f < frames; ++f)
    for (size_t p = 0; p < points; ++p)
      for (size_t a = 0; a < 3; ++a)
        xyz[(f * points + p) * 3 + a] =
            std::sin(0.1 * static_cast<double>(p * 3 + a)) +
            0.05 * static_cast<double>((p % 4 + 1) * f) * (a == p % 3 ? 1.0 : 0.2);
  TransformParams tp;
  tp.kg_error = 0.5;
  tp.clusters = 1;
  tp.options["segments"] = "4";
  tp.options["align"] = "0";
  TsCodec codec;
  std::vector<uint8_t> bytes;
  std::vector<double> recon, dec;
  codec.encode({frames, points, xyz.data(), valid.data()}, tp, &bytes, &recon);
  ASSERT_EQ(bytes[0], 2);  // version 2: segments
  codec.decode(bytes.data(), bytes.size(), frames, points, &dec);
  EXPECT_EQ(dec, recon);
  for (size_t cut = 0; cut < bytes.size(); cut += std::max<size_t>(1, bytes.size() / 151)) {
    try {
      codec.decode(bytes.data(), cut, frames, points, &dec);
      ADD_FAILURE() << "truncation at " << cut << " accepted";
    } catch (const Error& e) {
      EXPECT_EQ(e.code(), ErrorCode::kCorrupt) << e.what();
    }
  }
  // Header: version, flags, varint frames (1 byte), varint points (2 bytes), f64, K: S at 14.
  ASSERT_EQ(bytes[14], 4);
  for (int s = 0; s < 256; ++s) {
    if (s == 4) continue;
    std::vector<uint8_t> bad = bytes;
    bad[14] = static_cast<uint8_t>(s);
    try {
      codec.decode(bad.data(), bad.size(), frames, points, &dec);
    } catch (const Error& e) {
      EXPECT_EQ(e.code(), ErrorCode::kCorrupt) << e.what();
    }
  }
}
