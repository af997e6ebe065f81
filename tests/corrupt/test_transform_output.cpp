// Transform-output streams (docs/FORMAT.md 4.3, HEAD flags bit 1: the transform's reconstruction
// is the output, no bound layer): a valid one decodes to the encoder's reconstruction and meets
// its KG target; every inconsistent combination of flags and fields is rejected as corrupt.
#include <gtest/gtest.h>

#include <cmath>
#include <cstring>
#include <string>

#include "capz/codec.h"
#include "capz/error.h"
#include "capz/metrics.h"
#include "coding/bytes.h"
#include "coding/container.h"
#include "coding/crc32c.h"
#include "support/stream_pieces.h"
#include "test_util.h"

namespace capz {
namespace {

using capz_test::assemble;
using capz_test::Piece;
using capz_test::pieces;

Take smooth_take(size_t frames, size_t points) {
  Take t;
  t.format = Format::kPCDFolder;
  t.resize(frames, points);
  for (size_t f = 0; f < frames; ++f)
    for (size_t p = 0; p < points; ++p) {
      const double u = 0.3 * static_cast<double>(p), s = 0.2 * static_cast<double>(f);
      t.at(f, p)[0] = std::cos(u) * (1 + 0.1 * std::sin(s + u));
      t.at(f, p)[1] = std::sin(u) * (1 + 0.1 * std::cos(s));
      t.at(f, p)[2] = 0.05 * static_cast<double>(p) + 0.2 * std::sin(s);
      t.valid[f * points + p] = (f * 7 + p) % 23 != 0;  // a few gaps
    }
  return t;
}

std::vector<uint8_t> tout_stream(const Take& t) {
  CompressOptions o;
  o.codec = "ts";
  o.kg_error = 0.5;
  o.window_frames = 12;
  return compress(t, o);
}

using capz_test::decode_error;

TEST(TransformOutput, GivenKgTargetAndTsThenStreamIsTransformOutputAndMeetsTarget) {
  const Take t = smooth_take(30, 40);
  CompressOptions o;
  o.codec = "ts";
  o.kg_error = 0.5;
  o.window_frames = 12;
  CompressStats st;
  std::vector<uint8_t> b = compress(t, o, &st);
  EXPECT_EQ(st.mode, "transform-output");
  const StreamInfo si = describe(b.data(), b.size());
  EXPECT_TRUE(si.transform_output);
  EXPECT_EQ(si.kg_target, 0.5);
  EXPECT_EQ(si.max_error, 0.0);
  const Take back = decompress(b.data(), b.size());
  const ErrorStats e = compare(t, back);
  EXPECT_EQ(e.mask_mismatches, 0u);
  EXPECT_LE(e.kg_error, 0.5);
  EXPECT_GT(e.kg_error, 0.05);             // the budget is spent, not wasted on an exact copy
  EXPECT_EQ(e.max_abs, st.error.max_abs);  // the encoder reported what the decoder produces
  for (const Piece& p : pieces(b))
    if (p.type == "HEAD") {
      EXPECT_EQ(p.payload[19], 2);
    }
}

TEST(TransformOutput, GivenMaxErrorOrNoTransformThenBoundLayerAsBefore) {
  const Take t = smooth_take(30, 40);
  CompressOptions o;
  o.codec = "none";
  o.kg_error = 0.5;
  CompressStats st;
  std::vector<uint8_t> b = compress(t, o, &st);
  EXPECT_EQ(st.mode, "grid");
  EXPECT_FALSE(describe(b.data(), b.size()).transform_output);
  o.codec = "ts";
  o.kg_error = 0;
  o.max_error = 0.01;
  b = compress(t, o, &st);
  EXPECT_EQ(st.mode, "grid");
  EXPECT_LE(compare(t, decompress(b.data(), b.size())).max_abs, 0.01);
}

// Found by fuzz_simple_round_trip (pdct, one point): with one point per frame KG's denominator
// (distance to the frame centroid) is 0, so any lossy transform output has an infinite KG error;
// the stream claimed 0.9 %. The encoder must not promise a KG target its output misses: it falls
// back to the grid (a bound), and whatever it writes keeps what HEAD promises.
TEST(TransformOutput, GivenKgTargetTheTransformCannotMeetThenNotPromised) {
  Take t = smooth_take(11, 1);
  t.valid.assign(t.valid.size(), 1);
  for (const char* codec : {"pdct", "ts", "auto"}) {
    SCOPED_TRACE(codec);
    CompressOptions o;
    o.codec = codec;
    o.kg_error = 0.9;
    o.window_frames = 4;
    std::vector<uint8_t> b = compress(t, o);
    const StreamInfo si = describe(b.data(), b.size());
    const ErrorStats e = compare(t, decompress(b.data(), b.size()));
    if (si.transform_output) {
      EXPECT_LE(e.kg_error, 0.9);
    } else {
      EXPECT_LE(e.max_abs, si.max_error);
    }
  }
}

TEST(TransformOutput, GivenInconsistentHeadOrPositionsThenCorrupt) {
  const Take t = smooth_take(30, 40);
  const std::vector<uint8_t> good = tout_stream(t);
  ASSERT_EQ(assemble(good, pieces(good)), good);  // the crafting helper itself is faithful
  auto with_head = [&](auto change) {
    std::vector<Piece> ps = pieces(good);
    change(&ps[0].payload);
    return assemble(good, ps);
  };
  auto set_f64 = [](std::vector<uint8_t>* h, size_t at, double v) {
    uint64_t u;
    std::memcpy(&u, &v, 8);
    for (int i = 0; i < 8; ++i) (*h)[at + i] = static_cast<uint8_t>(u >> (8 * i));
  };
  // HEAD: frames u64 @0, points @8, window @12, format @16, mode @17, codec @18, flags @19,
  // step @20, max_error @28, analog @36/@40, kg_target @44.
  EXPECT_NE(decode_error(with_head([](std::vector<uint8_t>* h) { (*h)[19] = 3; })).find("lossless"),
            std::string::npos);
  // A flag bit this decoder does not define names a later minor version's feature (FORMAT.md
  // 17); bits 3, 4, 5 and 6 (1.1's ragged frames, frame-file sources, reordered points and octree
  // frames) in a 1.0 stream are corrupt.
  std::string flag;
  const std::vector<uint8_t> later = with_head([](std::vector<uint8_t>* h) { (*h)[19] = 130; });
  EXPECT_EQ(capz_test::error_of([&] { decompress(later.data(), later.size(), "x"); }, &flag),
            ErrorCode::kUnsupportedVersion);
  EXPECT_NE(flag.find("feature bit 7"), std::string::npos) << flag;
  const std::vector<uint8_t> files = with_head([](std::vector<uint8_t>* h) { (*h)[19] |= 16; });
  EXPECT_EQ(capz_test::error_of([&] { decompress(files.data(), files.size(), "x"); }, &flag),
            ErrorCode::kCorrupt);
  EXPECT_NE(flag.find("feature bit 4 (frame-file source) in a format 1.0 stream"),
            std::string::npos)
      << flag;
  const std::vector<uint8_t> ragged = with_head([](std::vector<uint8_t>* h) { (*h)[19] = 10; });
  EXPECT_EQ(capz_test::error_of([&] { decompress(ragged.data(), ragged.size(), "x"); }, &flag),
            ErrorCode::kCorrupt);
  EXPECT_NE(flag.find("feature bit 3 (ragged frames) in a format 1.0 stream"), std::string::npos)
      << flag;
  EXPECT_NE(decode_error(with_head([](std::vector<uint8_t>* h) { (*h)[18] = 0; })).find("codec"),
            std::string::npos);
  EXPECT_NE(decode_error(with_head([](std::vector<uint8_t>* h) { (*h)[17] = 1; })).find("grid"),
            std::string::npos);
  EXPECT_NE(
      decode_error(with_head([&](std::vector<uint8_t>* h) { set_f64(h, 20, 0.01); })).find("step"),
      std::string::npos);
  EXPECT_NE(
      decode_error(with_head([&](std::vector<uint8_t>* h) { set_f64(h, 28, 0.01); })).find("bound"),
      std::string::npos);
  EXPECT_NE(decode_error(with_head([&](std::vector<uint8_t>* h) {
              set_f64(h, 44, NAN);
            })).find("KG target"),
            std::string::npos);
  EXPECT_NE(decode_error(with_head([&](std::vector<uint8_t>* h) {
              set_f64(h, 44, -1);
            })).find("KG target"),
            std::string::npos);
  EXPECT_FALSE(decode_error(with_head([](std::vector<uint8_t>* h) { h->resize(44); })).empty());
  // The flag cleared (a grid stream with a step): POSW lacks the predictor and residual blocks.
  EXPECT_FALSE(decode_error(with_head([&](std::vector<uint8_t>* h) {
                 (*h)[19] = 0;
                 set_f64(h, 20, 0.01);
                 h->resize(44);
               })).empty());
  // POSW: a byte after the codec block; an empty codec block.
  {
    std::vector<Piece> ps = pieces(good);
    for (Piece& p : ps)
      if (p.type == "POSW") {
        p.payload.push_back(0);
        break;
      }
    EXPECT_NE(decode_error(assemble(good, ps)).find("after the codec block"), std::string::npos);
  }
  {
    std::vector<Piece> ps = pieces(good);
    for (Piece& p : ps)
      if (p.type == "POSW") {  // window 0, has_mask, then codec length 0 and nothing else
        p.payload.resize(3);
        p.payload[2] = 0;
        break;
      }
    EXPECT_NE(decode_error(assemble(good, ps)).find("codec block"), std::string::npos);
  }
  // A grid stream given the flag (and a KG target field) has codec 0 and a step: rejected.
  {
    const std::vector<uint8_t> grid = [&] {
      CompressOptions o;
      o.max_error = 0.01;
      o.window_frames = 12;
      return compress(t, o);
    }();
    std::vector<Piece> ps = pieces(grid);
    ps[0].payload[19] = 2;
    set_f64(&ps[0].payload, 28, 0);
    ps[0].payload.resize(44);
    std::vector<uint8_t> kg(8);
    set_f64(&kg, 0, 0.5);
    ps[0].payload.insert(ps[0].payload.end(), kg.begin(), kg.end());
    EXPECT_FALSE(decode_error(assemble(grid, ps)).empty());
  }
}

}  // namespace
}  // namespace capz
