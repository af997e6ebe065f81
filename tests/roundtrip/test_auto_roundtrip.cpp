// --codec auto: the smallest of the plain coder and every transform, decoded within the bound.
#include <gtest/gtest.h>

#include <algorithm>
#include <string>

#include "capz/codec.h"
#include "capz/io.h"
#include "capz/metrics.h"
#include "codec/registry.h"

using namespace capz;

namespace {

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
  Take t;
  t.resize(40, 2);
  t.rate = 100;
  t.units = "mm";
  for (size_t f = 0; f < t.frames; ++f)
    for (size_t p = 0; p < t.points; ++p) {
      t.valid[f * 2 + p] = 1;
      t.at(f, p)[0] = 10.0 * p + 0.25 * f;
      t.at(f, p)[1] = 3.0 * f;
      t.at(f, p)[2] = -1.0 * p;
    }
  CompressOptions o;
  o.max_error = 0.1;
  o.codec = "auto";
  CompressStats st;
  std::vector<uint8_t> bytes = compress(t, o, &st);
  Take back = decompress(bytes.data(), bytes.size(), "tiny.capz");
  EXPECT_LE(compare(t, back).max_abs, 0.1);
  EXPECT_EQ(bytes.size(), size_with(t, o, st.codec));
}
