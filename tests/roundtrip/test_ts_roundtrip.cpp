// ts codec on the real PCD sequences: the transform alone at a KG target (its reconstruction is
// the output), asserting the decoder reproduces the encoder bit for bit and the KG error holds.
#include <gtest/gtest.h>

#include <cstring>
#include <string>

#include "capz/io.h"
#include "capz/metrics.h"
#include "codec/ts/ts_codec.h"

using namespace capz;

namespace {

struct Case {
  const char* name;
  size_t frames;  // 0 = all (keeps the runtime modest on long sequences)
  double kg;
  int clusters;
  double max_bpvf;  // a regression bound well above what the codec reaches today
};

void run_case(const Case& c) {
  Take t = read_pcd_folder(std::string(CAPZ_SHARED_DATA) + "/pcd/" + c.name);
  const size_t nf = c.frames ? std::min(c.frames, t.frames) : t.frames;
  PositionsView v{nf, t.points, t.xyz.data(), t.valid.data()};
  TransformParams tp;
  tp.kg_error = c.kg;
  tp.clusters = c.clusters;
  TsCodec codec;
  TsEncodeReport rep;
  std::vector<uint8_t> bytes;
  std::vector<double> recon, dec;
  codec.encode_report(v, tp, &bytes, &recon, &rep);
  codec.decode(bytes.data(), bytes.size(), nf, t.points, &dec);
  ASSERT_EQ(dec.size(), recon.size());
  EXPECT_EQ(0, std::memcmp(dec.data(), recon.data(), dec.size() * sizeof(double)));
  ErrorStats e = compare(nf, t.points, t.xyz.data(), dec.data(), t.valid.data());
  EXPECT_LE(e.kg_error, c.kg);
  EXPECT_GT(e.kg_error, 0.5 * c.kg);  // the rate search spends the budget it is given
  const double rate = bpvf(bytes.size(), nf, t.points);
  std::string pcs;
  for (int p : rep.pcs) pcs += std::to_string(p) + " ";
  std::printf("%s: %zu frames x %zu points, K=%d PCs {%s} KG %.4f%% max %.4g  %zu bytes  %.3f bpvf  %.2fs\n",
              c.name, nf, t.points, rep.clusters, pcs.c_str(), e.kg_error, e.max_error,
              bytes.size(), rate, rep.t_total);
  EXPECT_LT(rate, c.max_bpvf);
}

}  // namespace

// Measured at landing: horse 2.6 bpvf (auto picks K = 1), chickenCrossing 2.1 (all 400 frames,
// K = 1), pcow 5.6 (K = 1); see docs/BENCHMARKS.md.
TEST(TsRoundtrip, HorseGallopAutoClusters) { run_case({"horse-gallop", 0, 0.15, -1, 3.5}); }
TEST(TsRoundtrip, ChickenCrossingFirst200FramesThreeClusters) {
  run_case({"chickenCrossing", 200, 0.15, 3, 4.5});
}
TEST(TsRoundtrip, PcowTwoClustersLooseTarget) { run_case({"pcow", 0, 0.5, 2, 4.0}); }
