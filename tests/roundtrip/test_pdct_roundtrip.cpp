// pdct on the real sequences: encoder reconstruction == decoder output bit for bit, and the
// error targets hold. Frame subsets keep the runtime modest.
#include <gtest/gtest.h>

#include <cstring>
#include <string>

#include "capz/codec.h"
#include "capz/io.h"
#include "capz/metrics.h"
#include "codec/pdct/pdct_encoder.h"
#include "codec/transform.h"
#include "test_util.h"
#include "unit/synthetic.h"

namespace {

// The first `frames` frames of a take, gaps filled as the container fills them for coding.
using Window = capz_test::Synth;

Window window_of(const capz::Take& t, size_t frames) {
  Window w;
  w.frames = std::min(frames, t.frames);
  w.points = t.points;
  w.valid.assign(t.valid.begin(),
                 t.valid.begin() + static_cast<std::ptrdiff_t>(w.frames * w.points));
  w.xyz = capz::fill_gaps(w.frames, w.points, t.xyz.data(), w.valid.data());
  return w;
}

struct Outcome {
  capz::ErrorStats stats;
  double bpvf = 0;
  capz::PdctReport report;
};

Outcome round_trip(const Window& w, const capz::TransformParams& p) {
  Outcome o;
  std::vector<uint8_t> bytes;
  std::vector<double> enc, dec;
  capz::encode_pdct(w.view(), p, &bytes, &enc, &o.report);
  capz::PdctCodec().decode(bytes.data(), bytes.size(), w.frames, w.points, &dec);
  EXPECT_EQ(enc.size(), dec.size());
  EXPECT_EQ(std::memcmp(enc.data(), dec.data(), enc.size() * sizeof(double)), 0)
      << "encoder reconstruction differs from the decoder's output";
  o.stats = capz::compare(w.frames, w.points, w.xyz.data(), dec.data(), w.valid.data());
  o.bpvf = capz::bpvf(bytes.size(), w.frames, w.points);
  return o;
}

}  // namespace

TEST(PdctRoundTrip, GivenPcdSequencesWhenKgTargetThenMetAndBitIdentical) {
  const std::string data = capz_test::shared_data_or_skip();
  if (data.empty()) return;
  struct Case {
    const char* dir;
    size_t frames;
    double kg;
    double max_bpvf;  // regression guard, well above what the codec reaches
  };
  for (const Case c : {Case{"chickenCrossing", 60, 0.5, 6}, Case{"pcow", 60, 1.0, 8},
                       Case{"horse-gallop", 16, 1.0, 10}}) {
    SCOPED_TRACE(c.dir);
    const capz::Take t = capz::read_pcd_folder(data + "/pcd/" + c.dir);
    const Window w = window_of(t, c.frames);
    capz::TransformParams p;
    p.kg_error = c.kg;
    p.clusters = 25;
    const Outcome o = round_trip(w, p);
    EXPECT_LE(o.stats.kg_error, c.kg);
    EXPECT_GT(o.stats.kg_error, c.kg / 3);  // the search uses the budget
    EXPECT_LT(o.bpvf, c.max_bpvf);
    EXPECT_EQ(o.report.clusters, 25u);
  }
}

TEST(PdctRoundTrip, GivenChickenWhenZeroingCoefficientsThenRateDropsAndErrorRises) {
  const std::string data = capz_test::shared_data_or_skip();
  if (data.empty()) return;
  const capz::Take t = capz::read_pcd_folder(data + "/pcd/chickenCrossing");
  const Window w = window_of(t, 40);
  // Fixed quantisation (the paper's 12 bits): zeroing coefficients lowers the rate and raises
  // the error.
  capz::TransformParams p;
  p.clusters = 25;
  const Outcome full = round_trip(w, p);
  p.options["zero_share"] = "0.75";
  const Outcome zeroed = round_trip(w, p);
  EXPECT_LT(zeroed.bpvf, full.bpvf);
  EXPECT_GT(zeroed.stats.kg_error, full.stats.kg_error);
  EXPECT_LT(full.stats.kg_error, 0.2);
}

TEST(PdctRoundTrip, GivenMaxErrorWhenEncodedThenGridModeHoldsTheBound) {
  const std::string data = capz_test::shared_data_or_skip();
  if (data.empty()) return;
  for (const char* dir : {"pcow", "chickenCrossing"}) {
    SCOPED_TRACE(dir);
    const capz::Take t = capz::read_pcd_folder(data + "/pcd/" + dir);
    const Window w = window_of(t, 40);
    capz::TransformParams p;
    p.max_error = 0.002;  // the sequences span ~4 and ~18 units
    p.clusters = 25;
    const Outcome o = round_trip(w, p);
    EXPECT_TRUE(o.report.grid_mode);
    EXPECT_LE(o.stats.max_abs, p.max_error);  // on the bound layer's grid: nothing left to code
    EXPECT_LT(o.bpvf, 16);
  }
}

TEST(PdctRoundTrip, GivenMaxErrorInDctModeWhenEncodedThenTransformAloneStaysNearTheBound) {
  const std::string data = capz_test::shared_data_or_skip();
  if (data.empty()) return;
  const capz::Take t = capz::read_pcd_folder(data + "/pcd/pcow");
  const Window w = window_of(t, 40);
  capz::TransformParams p;
  p.max_error = 0.002;
  p.options["mode"] = "dct";
  const Outcome o = round_trip(w, p);
  // The bound itself is the bound layer's job; the transform's steps sit on its grid, so its RMS
  // error is below the bound and its worst case within a few grid steps.
  EXPECT_LT(o.stats.rmse, p.max_error);
  EXPECT_LT(o.stats.max_abs, 8 * p.max_error);
}

// Real mocap takes with gaps (Plug-in-Gait with holes, the c3d.org gait trial, a c3d.org sample
// with gaps in 27 of 36 markers).
const char* const kMocap[] = {"/c3d/btkdata/PiG/PiG_Motion-FlatFoot-Hole.c3d",
                              "/c3d/c3dorg/sample_01/Eb015pr.c3d",
                              "/c3d/c3dorg/sample_02/pc_real.c3d"};

TEST(PdctRoundTrip, GivenMocapWithGapsWhenMaxErrorThenGridModeExactAndBitIdentical) {
  const std::string data = capz_test::shared_data_or_skip();
  if (data.empty()) return;
  for (const char* rel : kMocap) {
    SCOPED_TRACE(rel);
    const capz::Take t = capz::read_c3d(data + rel);
    ASSERT_GT(t.gap_samples(), 0u);
    const Window w = window_of(t, 200);
    for (double e : {0.1, 1.0}) {  // mm
      capz::TransformParams p;
      p.max_error = e;
      const Outcome o = round_trip(w, p);
      EXPECT_TRUE(o.report.grid_mode);
      EXPECT_LE(o.stats.max_abs, e);
      EXPECT_GT(o.report.clusters, 1u);
    }
  }
}

TEST(PdctRoundTrip, GivenMocapWithGapsWhenKgTargetInDctModeThenMet) {
  const std::string data = capz_test::shared_data_or_skip();
  if (data.empty()) return;
  for (const char* rel : kMocap) {
    SCOPED_TRACE(rel);
    const capz::Take t = capz::read_c3d(data + rel);
    const Window w = window_of(t, 200);
    capz::TransformParams p;
    p.kg_error = 0.5;
    const Outcome o = round_trip(w, p);
    EXPECT_FALSE(o.report.grid_mode);
    EXPECT_LE(o.stats.kg_error, 0.5);
  }
}

TEST(PdctRoundTrip, GivenMocapWhenCompressedWithCodecPdctThenBoundHoldsAndGapsComeBack) {
  const std::string data = capz_test::shared_data_or_skip();
  if (data.empty()) return;
  for (const char* rel : kMocap) {
    SCOPED_TRACE(rel);
    const capz::Take t = capz::read_c3d(data + rel);
    capz::CompressOptions o;
    o.max_error = 0.1;
    o.codec = "pdct";
    o.window_frames = 128;  // several windows, each coded on its own
    capz::CompressStats st;
    const auto bytes = capz::compress(t, o, &st);
    const capz::Take back = capz::decompress(bytes.data(), bytes.size(), rel);
    const auto s = capz::compare(t, back);
    EXPECT_LE(s.max_abs, 0.1);
    EXPECT_EQ(s.mask_mismatches, 0u);
    EXPECT_EQ(capz::describe(bytes.data(), bytes.size()).codec, "pdct");
  }
}
