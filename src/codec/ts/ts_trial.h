// ts codec, encode side: one model for a window (ts_encoder.cpp searches over them). Given the
// aligned frames, a cluster count and a point segmentation: the PCA of each (segment, cluster)
// unit (`prepare`), then for an error budget the PCs kept, the basis quantised and the
// coefficients LPC/LCPS-coded into a payload (`rate_search` scales the budget until the error
// lands just under the target); `fallback_trial` is the model every window can be written with.
// Internal to the ts encoder (capz::capz).
#pragma once

#include <Eigen/Core>
#include <chrono>
#include <cstddef>
#include <cstdint>
#include <vector>

#include "codec/transform.h"
#include "codec/ts/lpc.h"
#include "codec/ts/pca.h"
#include "codec/ts/segment.h"
#include "codec/ts/ts_encoder.h"
#include "codec/ts/ts_model.h"

namespace capz {
namespace ts {
namespace enc {

using Clock = std::chrono::steady_clock;
inline double since(Clock::time_point t0) {
  return std::chrono::duration<double>(Clock::now() - t0).count();
}

// The options of TransformParams::options (parse_options in ts_encoder.cpp; docs/CODEC-TS.md).
struct Options {
  int lpc_order = 2;
  int lcps_k = 2;
  int bits_min = 4, bits_max = 20;  // the paper: 8..16
  bool basis_predict = true;        // the paper: false (plain quantised values)
  bool free_step = true;            // basis step chosen freely per PC (the paper: 2^q levels)
  bool align = true;
  int max_clusters = 5;
  int segments = 0;           // point segments; 0 = auto (the smallest payload of a few counts)
  bool segment_align = true;  // each segment gets its own rigid alignment (flags bit 2)
  int restarts = 4;
  uint64_t seed = 0x5eed;
  double trunc_share = 0.1;    // share of the squared-error budget left to PCA truncation
  double basis_share = 0.8;    // share for basis quantisation (the rest: coefficients)
  double rms_per_bound = 0.5;  // with a max error: aim the transform's RMS at this x bound
};

// What every trial shares: the input, the aligned frames, the coded rigid motion.
struct Base {
  PositionsView in;
  size_t dim = 0;
  double target_sq = 0;     // allowed sum of squared errors over valid samples
  double rms = 0;           // the target RMS per coordinate, sqrt(target_sq / (3 valid samples))
  Eigen::MatrixXd aligned;  // dim x F
  bool rigid = false;
  double rot_step = 0, trans_step = 0;
  ts::LpcCode rigid_code;
};

// Per cluster count and segmentation: the PCA of each (segment, cluster) unit, segment-major
// (unit u = s * k + c, as TsModel::cluster).
struct Prepared {
  int k = 0;
  std::vector<uint8_t> label;
  std::vector<ClusterLayout> layout;
  int segments = 1;
  std::vector<uint8_t> segment;                // per point (empty for one segment)
  std::vector<std::vector<uint32_t>> members;  // points of each segment, increasing
  std::vector<TsModel::SegmentMotion> motion;  // per segment, when segments are aligned
  std::vector<Eigen::MatrixXd> frames;         // per unit: 3 N_s x l_c, time order
  std::vector<ts::Pca> pca;                    // per unit
  size_t unit_dim(size_t u) const { return 3 * members[u / layout.size()].size(); }
};

struct Trial {
  TsModel model;
  std::vector<double> recon;
  std::vector<uint8_t> bytes;
  double sq = 0;  // sum of squared errors over valid samples
  bool ok = false;
};

// Aligns the frames of one segment (or of all points) and codes their rigid motion (ts_trial.cpp).
LpcCode code_rigid(const uint8_t* valid, size_t valid_stride, double rms, double extent,
                   int lpc_order, Eigen::MatrixXd* frames, double* rot_step, double* trans_step,
                   const std::vector<uint32_t>& valid_map = {});
// Clusters the frames into k (k <= 1: one cluster), cuts them by `seg`, and runs the PCA of
// every (segment, cluster) unit, aligning each segment first when o.segment_align asks.
Prepared prepare(const Base& base, int k, const Segmentation& seg, const Options& o,
                 TsEncodeReport* rep);
// The smallest trial that meets base.target_sq over budget scales starting at *scale (which it
// updates to the scale of the trial returned); the one closest to the target when none does.
Trial rate_search(const Base& base, const Prepared& prep, const Options& o, double* scale,
                  TsEncodeReport* rep);
// One cluster, no rigid motion, one PC: a model that fits the payload's int32 values always.
Trial fallback_trial(const Base& base, const Options& o);

}  // namespace enc
}  // namespace ts
}  // namespace capz
