// --codec auto: the smallest of the plain coder and every transform, decoded within the bound.
#include <gtest/gtest.h>

#include <algorithm>
#include <string>

#include "capz/codec.h"
#include "capz/error.h"
#include "capz/io.h"
#include "capz/metrics.h"
#include "codec/registry.h"

using namespace capz;

namespace {

// A small take of smooth, distinct trajectories (mm).
Take small_moving_take(size_t frames, size_t points) {
  Take t;
  t.resize(frames, points);
  t.rate = 100;
  t.units = "mm";
  for (size_t f = 0; f < t.frames; ++f)
    for (size_t p = 0; p < t.points; ++p) {
      t.valid[f * t.points + p] = 1;
      t.at(f, p)[0] = 10.0 * p + 0.25 * f;
      t.at(f, p)[1] = 3.0 * f + (p % 3);
      t.at(f, p)[2] = -1.0 * p + 0.1 * f * (p % 2);
    }
  return t;
}

size_t size_with(const Take& t, CompressOptions o, const std::string& codec) {
  o.codec = codec;
  return compress(t, o).size();
}

}  // namespace

TEST(AutoCodec, GivenRealGaitTrialWhenAutoThenSmallestCandidateAndWithinBound) {
  Take t = read_take(std::string(CAPZ_REPO_DATA) + "/EB015PI.c3d");
  CompressOptions o;
  o.max_error = 0.5;  // mm
  size_t best = size_with(t, o, "none");
  std::string best_name = "none";
  for (const TransformCodec* c : all_codecs()) {
    size_t s = size_with(t, o, c->name());
    if (s < best) best = s, best_name = c->name();
  }
  o.codec = "auto";
  CompressStats st;
  std::vector<uint8_t> bytes = compress(t, o, &st);
  EXPECT_EQ(bytes.size(), best);
  EXPECT_EQ(st.codec, best_name);
  Take back = decompress(bytes.data(), bytes.size(), "auto.capz");
  ErrorStats e = compare(t, back);
  EXPECT_LE(e.max_abs, 0.5);
  EXPECT_EQ(e.mask_mismatches, 0u);
  EXPECT_EQ(describe(bytes.data(), bytes.size()).codec, best_name);
}

TEST(AutoCodec, GivenTooFewPointsForTransformsWhenAutoThenPlainCoderStillWorks) {
  const Take t = small_moving_take(40, 2);
  CompressOptions o;
  o.max_error = 0.1;
  o.codec = "auto";
  CompressStats st;
  std::vector<uint8_t> bytes = compress(t, o, &st);
  Take back = decompress(bytes.data(), bytes.size(), "tiny.capz");
  EXPECT_LE(compare(t, back).max_abs, 0.1);
  EXPECT_EQ(bytes.size(), size_with(t, o, st.codec));
}

namespace {

// false when compress rejects the options as kInvalidParameter; any other error propagates.
bool accepted(const Take& t, const CompressOptions& o) {
  try {
    compress(t, o);
  } catch (const Error& e) {
    if (e.code() != ErrorCode::kInvalidParameter) throw;
    return false;
  }
  return true;
}

}  // namespace

// A mistyped option must be an error under auto too, not a reason to skip the codec.
TEST(AutoCodec, GivenUnknownOrUnaddressedOptionWhenAutoThenInvalidParameter) {
  const Take t = small_moving_take(30, 12);
  CompressOptions o;
  o.max_error = 0.1;
  o.codec = "auto";
  o.codec_options = {{"ts.lpc_ordr", "2"}};  // typo in the key
  EXPECT_FALSE(accepted(t, o));
  o.codec_options = {{"pdct.zero_share", "7"}};  // out of range
  EXPECT_FALSE(accepted(t, o));
  o.codec_options = {{"lpc_order", "2"}};  // no codec named
  EXPECT_FALSE(accepted(t, o));
  o.codec_options = {{"nosuch.lpc_order", "2"}};
  EXPECT_FALSE(accepted(t, o));
}

TEST(AutoCodec, GivenOptionsNamedPerCodecWhenAutoOrExplicitThenEachCodecGetsOnlyItsOwn) {
  const Take t = small_moving_take(30, 12);
  CompressOptions o;
  o.max_error = 0.1;
  o.codec = "auto";
  o.codec_options = {{"ts.lpc_order", "1"}, {"pdct.knn", "4"}};
  EXPECT_TRUE(accepted(t, o));
  o.codec = "ts";  // pdct.knn is for pdct and ignored here; lpc_order reaches ts
  EXPECT_TRUE(accepted(t, o));
  o.codec_options = {{"ts.lpc_order", "1"}, {"lpc_order", "1"}};
  EXPECT_TRUE(accepted(t, o));
  o.codec_options = {{"knn", "4"}};  // a pdct key given bare to ts
  EXPECT_FALSE(accepted(t, o));
  o.codec = "none";  // the plain coder has no options
  o.codec_options = {{"lpc_order", "1"}};
  EXPECT_FALSE(accepted(t, o));
}
