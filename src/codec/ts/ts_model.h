// ts codec — the quantised model: everything the payload holds, as integers and a few steps.
// The encoder builds it, reconstruct() turns it into positions (the one reconstruction path the
// encoder and the decoder share), write_model()/read_model() (de)serialise it (docs/CODEC-TS.md).
#pragma once

#include <cstddef>
#include <cstdint>
#include <vector>

#include "codec/ts/lcps.h"
#include "codec/ts/lpc.h"
#include "codec/ts/pca.h"
#include "codec/ts/rigid.h"
#include "coding/bytes.h"

namespace capz {
namespace ts {

// Largest segment count a payload can hold.
constexpr int kMaxSegments = 64;

struct TsCluster {
  std::vector<QuantisedVector> basis;  // r PCs, each 3N entries
  LpcCode first;                       // r x l1: the first motion fragment's coefficients
  int lcps_weight_bits = 14;
  std::vector<LcpsFrame> later;  // the cluster's later frames, in time order
};

struct TsModel {
  size_t frames = 0, points = 0;
  double coef_step = 1;       // quantisation step of every PC coefficient / residual
  bool rigid = false;         // frames were aligned; rigid_code holds their 6 parameters
  bool basis_predict = true;  // basis entries coded as residuals of basis_predict.h
  double rot_step = 0, trans_step = 0;
  LpcCode rigid_code;  // 6 x frames: rotation vector (3), translation (3)
  int clusters = 1;
  std::vector<uint8_t> label;  // per frame, < clusters
  // Point segments (payload version 2 when > 1): per point its segment, < segments; empty (or
  // all 0) for one segment.
  int segments = 1;
  std::vector<uint8_t> segment;
  // Per-segment rigid motion (version 2, flags bit 2): each segment's points, moved by -center
  // (its centroid in frame 0, so that rotations turn about the segment itself), were aligned to
  // its frame 0 with these decoded parameters (6 x frames each, like rigid_code) before its PCA.
  struct SegmentMotion {
    double rot_step = 0, trans_step = 0;
    double center[3] = {0, 0, 0};
    LpcCode code;
  };
  bool segment_rigid = false;
  bool f32_scales = false;  // version 2, flags bit 3: basis scales are float32 values
  std::vector<SegmentMotion> segment_motion;  // per segment when segment_rigid
  // segments x clusters, segment-major (cluster[s * clusters + c]); the bases of segment s have
  // 3 N_s entries, entry 3 i + axis for the segment's i-th point (points in increasing order).
  std::vector<TsCluster> cluster;
};

// Frames of each cluster in time order, and l1 = the length of its first motion fragment
// (the first run of temporally consecutive frames). Throws kCorrupt on an empty cluster or a
// label >= clusters.
struct ClusterLayout {
  std::vector<size_t> frames;
  size_t first_len = 0;
};
std::vector<ClusterLayout> cluster_layout(const std::vector<uint8_t>& label, int clusters);

// Points of each segment in increasing order (all points for one segment). Throws kCorrupt on
// an inconsistent model (label >= segments, empty segment, label count != points).
std::vector<std::vector<uint32_t>> segment_points_of(const TsModel& model);

// Points of each segment in increasing order. Throws kCorrupt ("ts payload") on a label >=
// segments or an empty segment.
std::vector<std::vector<uint32_t>> segment_members(const std::vector<uint8_t>& label, int segments);

// Positions (frames x points x 3) from the model. The decoder's only reconstruction path; the
// encoder calls it too, so its `recon` is bit for bit the decoder's.
void reconstruct(const TsModel& model, std::vector<double>* xyz);

// The decoded rigid parameters of `code` (6 x frames: rotation vector, translation) for frame f.
RigidParams rigid_at(const Eigen::MatrixXd& decoded, size_t f);

void write_model(const TsModel& model, ByteWriter* out);
// `frames`/`points` come from the container; any disagreement or overrun throws kCorrupt.
TsModel read_model(const uint8_t* data, size_t size, size_t frames, size_t points);

}  // namespace ts
}  // namespace capz
