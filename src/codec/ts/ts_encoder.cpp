#include "codec/ts/ts_encoder.h"

#include <Eigen/Cholesky>
#include <algorithm>
#include <chrono>
#include <cmath>
#include <limits>

#include "capz/error.h"
#include "codec/ts/align.h"
#include "codec/ts/cluster.h"
#include "codec/ts/lcps.h"
#include "codec/ts/lpc.h"
#include "codec/ts/pca.h"
#include "codec/ts/rigid.h"
#include "codec/ts/segment.h"
#include "codec/ts/ts_model.h"

namespace capz {

namespace {

using ts::ClusterLayout;
using ts::TsCluster;
using ts::TsModel;

using Clock = std::chrono::steady_clock;

// segments=auto: where the search over 1, 2, 4, .., 64 segments starts, and the fewest points a
// segment needs on average to be tried.
constexpr int kAutoSegmentsStart = 16;
constexpr size_t kMinPointsPerSegment = 48;
double since(Clock::time_point t0) {
  return std::chrono::duration<double>(Clock::now() - t0).count();
}

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

long parse_int(const std::string& key, const std::string& v, long lo, long hi) {
  char* end = nullptr;
  long x = std::strtol(v.c_str(), &end, 10);
  if (v.empty() || *end != '\0' || x < lo || x > hi)
    fail(ErrorCode::kInvalidParameter, "",
         "ts: option " + key + "=" + v + " is not an integer in " + std::to_string(lo) + ".." +
             std::to_string(hi));
  return x;
}
double parse_real(const std::string& key, const std::string& v, double lo, double hi) {
  char* end = nullptr;
  double x = std::strtod(v.c_str(), &end);
  if (v.empty() || *end != '\0' || !(x >= lo && x <= hi))
    fail(ErrorCode::kInvalidParameter, "",
         "ts: option " + key + "=" + v + " is not a number in [" + std::to_string(lo) + ", " +
             std::to_string(hi) + "]");
  return x;
}

Options parse_options(const TransformParams& p) {
  Options o;
  for (const auto& kv : p.options) {
    const std::string& k = kv.first;
    const std::string& v = kv.second;
    if (k == "lpc_order")
      o.lpc_order = static_cast<int>(parse_int(k, v, 0, 8));
    else if (k == "lcps_k")
      o.lcps_k = static_cast<int>(parse_int(k, v, 1, 16));
    else if (k == "basis_bits")
      o.bits_min = o.bits_max = static_cast<int>(parse_int(k, v, 2, 24));
    else if (k == "basis_bits_min")
      o.bits_min = static_cast<int>(parse_int(k, v, 2, 24));
    else if (k == "basis_bits_max")
      o.bits_max = static_cast<int>(parse_int(k, v, 2, 24));
    else if (k == "basis_predict")
      o.basis_predict = parse_int(k, v, 0, 1) != 0;
    else if (k == "basis_free_step")
      o.free_step = parse_int(k, v, 0, 1) != 0;
    else if (k == "align")
      o.align = parse_int(k, v, 0, 1) != 0;
    else if (k == "segments")
      o.segments = v == "auto" ? 0 : static_cast<int>(parse_int(k, v, 1, ts::kMaxSegments));
    else if (k == "segment_align")
      o.segment_align = parse_int(k, v, 0, 1) != 0;
    else if (k == "max_clusters")
      o.max_clusters = static_cast<int>(parse_int(k, v, 1, 64));
    else if (k == "kmeans_restarts")
      o.restarts = static_cast<int>(parse_int(k, v, 1, 100));
    else if (k == "seed")
      o.seed = static_cast<uint64_t>(parse_int(k, v, 0, 0x7fffffff));
    else if (k == "trunc_share")
      o.trunc_share = parse_real(k, v, 0.0, 0.95);
    else if (k == "basis_share")
      o.basis_share = parse_real(k, v, 0.0, 0.9);
    else if (k == "rms_per_bound")
      o.rms_per_bound = parse_real(k, v, 0.01, 100.0);
    else
      fail(ErrorCode::kInvalidParameter, "",
           "ts: unknown option '" + k + "' (see docs/CODEC-TS.md)");
  }
  if (o.bits_min > o.bits_max)
    fail(ErrorCode::kInvalidParameter, "", "ts: basis_bits_min > basis_bits_max");
  if (o.trunc_share + o.basis_share >= 0.99)
    fail(ErrorCode::kInvalidParameter, "",
         "ts: trunc_share + basis_share must leave room for the coefficients");
  if (p.clusters < -1 || p.clusters > 64)
    fail(ErrorCode::kInvalidParameter, "", "ts: clusters must be auto or 1..64");
  return o;
}

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

// Stage 1 (and per segment): aligns the frames (3n x F, column = frame) to frame 0 in place, with
// the decoded parameters of the returned LPC code so that the decoder's inverse is exact; the
// quantisation steps are tied to the target RMS: translation 0.5 rms, rotation 0.5 rms / extent.
// `valid` is per (frame, point) with stride `valid_stride` points per frame, `valid_map` (if not
// empty) the points' indices in it.
ts::LpcCode code_rigid(const uint8_t* valid, size_t valid_stride, double rms, double extent,
                       int lpc_order, Eigen::MatrixXd* frames, double* rot_step, double* trans_step,
                       const std::vector<uint32_t>& valid_map = {}) {
  const size_t nf = static_cast<size_t>(frames->cols()),
               n = static_cast<size_t>(frames->rows() / 3);
  std::vector<uint8_t> v(nf * n);
  for (size_t f = 0; f < nf; ++f)
    for (size_t i = 0; i < n; ++i)
      v[f * n + i] = valid[f * valid_stride + (valid_map.empty() ? i : valid_map[i])];
  const PositionsView view{nf, n, frames->data(), v.data()};
  std::vector<ts::RigidParams> rp = ts::estimate_alignment(view, ts::AlignParams());
  extent = std::max(extent, 1e-300);
  *trans_step = std::max(0.5 * rms, extent * 1e-9);
  *rot_step = std::min(1e-2, std::max(0.5 * rms / extent, 1e-9));
  Eigen::MatrixXd series(6, static_cast<Eigen::Index>(nf));
  for (size_t f = 0; f < nf; ++f)
    for (int a = 0; a < 3; ++a) {
      series(a, static_cast<Eigen::Index>(f)) = rp[f].rot[a];
      series(3 + a, static_cast<Eigen::Index>(f)) = rp[f].trans[a];
    }
  ts::LpcParams lp;
  lp.order = lpc_order;
  Eigen::MatrixXd dec;
  ts::LpcCode code = ts::lpc_encode(
      series, {*rot_step, *rot_step, *rot_step, *trans_step, *trans_step, *trans_step}, lp, &dec);
  for (size_t f = 0; f < nf; ++f)
    ts::apply_rigid(ts::rigid_at(dec, f), frames->col(static_cast<Eigen::Index>(f)).data(), n);
  return code;
}

double sq_error(const PositionsView& in, const std::vector<double>& recon) {
  double s = 0;
  for (size_t f = 0; f < in.frames; ++f)
    for (size_t p = 0; p < in.points; ++p) {
      if (!in.valid[f * in.points + p]) continue;
      for (int a = 0; a < 3; ++a) {
        const size_t i = (f * in.points + p) * 3 + static_cast<size_t>(a);
        const double d = in.xyz[i] - recon[i];
        s += d * d;
      }
    }
  return s;
}

// Codes unit c of prep with its first `rank` PCs: the basis quantised (per_entry: the basis
// error budget per entry), the coefficients refitted on the quantised basis, then LPC-coded on the
// cluster's first fragment (step coef_step) and LCPS-coded on the rest. Adds the times taken.
void code_unit(const Prepared& prep, size_t c, int rank, double per_entry, double coef_step,
               bool f32_scales, const Options& o, TsCluster* out, double* t_quant, double* t_lcps) {
  const ts::Pca& pca = prep.pca[c];
  const ClusterLayout& lay = prep.layout[c % prep.layout.size()];
  TsCluster& tc = *out;
  const size_t dim = prep.unit_dim(c);
  const double per_pc = per_entry * static_cast<double>(dim);
  auto tq = Clock::now();
  Eigen::MatrixXd bq(static_cast<Eigen::Index>(dim), rank);
  for (int j = 0; j < rank; ++j) {
    const double* col = pca.basis.col(j).data();
    double scale = 0;
    for (size_t i = 0; i < dim; ++i) scale = std::max(scale, std::fabs(col[i]));
    if (o.free_step && o.bits_min != o.bits_max) {
      // The PC's share of the basis budget: sigma^2 3N_s step^2 / 12 = per_pc.
      const double sg = std::max(static_cast<double>(pca.sigma[j]), 1e-300);
      const double step = std::sqrt(12.0 * per_pc / (sg * sg * static_cast<double>(dim)));
      tc.basis.push_back(ts::quantise_vector_step(col, dim, step, o.bits_max, f32_scales));
    } else {
      const int bits = ts::basis_bits_for(pca.sigma[j], scale, dim, per_pc, o.bits_min, o.bits_max);
      tc.basis.push_back(ts::quantise_vector(col, dim, bits, f32_scales));
    }
    ts::dequantise_vector(tc.basis.back(), bq.col(j).data());
  }
  // Coefficients refitted on the quantised basis (least squares), which absorbs part of the
  // basis quantisation error.
  Eigen::MatrixXd w;
  if (rank > 0) {
    Eigen::MatrixXd g = bq.transpose() * bq;
    w = g.ldlt().solve(bq.transpose() * prep.frames[c]);
  } else {
    w.resize(0, static_cast<Eigen::Index>(lay.frames.size()));
  }
  *t_quant += since(tq);
  auto tl = Clock::now();
  const Eigen::Index l1 = static_cast<Eigen::Index>(lay.first_len);
  ts::LpcParams lp;
  lp.order = o.lpc_order;
  Eigen::MatrixXd first;
  tc.first = ts::lpc_encode(w.leftCols(l1),
                            std::vector<double>(static_cast<size_t>(rank), coef_step), lp, &first);
  double maxnorm = 0;
  for (Eigen::Index j = 0; j < first.cols(); ++j) maxnorm = std::max(maxnorm, first.col(j).norm());
  int wb = maxnorm > 0 ? static_cast<int>(std::ceil(std::log2(maxnorm / coef_step))) + 2 : 4;
  tc.lcps_weight_bits = std::max(4, std::min(30, wb));
  ts::LcpsParams cp;
  cp.k = o.lcps_k;
  cp.weight_bits = tc.lcps_weight_bits;
  for (Eigen::Index j = l1; j < w.cols(); ++j)
    tc.later.push_back(ts::lcps_encode(w.col(j), first, coef_step, cp, nullptr));
  *t_lcps += since(tl);
}

Trial build_trial(const Base& base, const Prepared& prep, double budget, const Options& o,
                  TsEncodeReport* rep) {
  auto t0 = Clock::now();
  Trial tr;
  TsModel& m = tr.model;
  m.frames = base.in.frames;
  m.points = base.in.points;
  m.rigid = base.rigid;
  m.basis_predict = o.basis_predict;
  m.rot_step = base.rot_step;
  m.trans_step = base.trans_step;
  m.rigid_code = base.rigid_code;
  m.clusters = prep.k;
  m.label = prep.label;
  m.segments = prep.segments;
  m.segment = prep.segment;
  m.segment_rigid = !prep.motion.empty();
  m.f32_scales = prep.segments > 1;
  m.segment_motion = prep.motion;
  const size_t nc = prep.pca.size();  // units: segments x clusters

  // PCs: a global threshold on sigma^2 (the paper's per-cluster "covered variation" threshold,
  // set from the error target): drop the smallest components of all units while their energy
  // fits.
  const double d_trunc = o.trunc_share * budget, d_basis = o.basis_share * budget;
  const double d_coef = budget - d_trunc - d_basis;
  // (Measured: ordering by sigma^2 / 3N_s, the reverse water-filling order, instead of sigma^2
  // changes the size by < 0.3 % on horse-gallop and chickenCrossing at 16 segments.)
  std::vector<std::pair<double, size_t>> comp;  // (sigma^2, unit)
  for (size_t c = 0; c < nc; ++c)
    for (Eigen::Index j = 0; j < prep.pca[c].sigma.size(); ++j)
      comp.emplace_back(prep.pca[c].sigma[j] * prep.pca[c].sigma[j], c);
  std::sort(comp.begin(), comp.end());
  std::vector<int> r(nc);
  for (size_t c = 0; c < nc; ++c) r[c] = static_cast<int>(prep.pca[c].sigma.size());
  double dropped = 0;
  for (const auto& e : comp) {
    if (dropped + e.first > d_trunc) break;
    if (r[e.second] <= 1) continue;  // every unit keeps its mean-shape component
    dropped += e.first;
    --r[e.second];
  }
  size_t total_entries = 0, total_coefs = 0;
  for (size_t c = 0; c < nc; ++c) {
    total_entries += static_cast<size_t>(r[c]) * prep.unit_dim(c);
    total_coefs += static_cast<size_t>(r[c]) * prep.layout[c % prep.layout.size()].frames.size();
  }
  m.coef_step = total_coefs > 0 ? std::sqrt(12.0 * d_coef / static_cast<double>(total_coefs)) : 1.0;
  if (!(m.coef_step > 0) || !std::isfinite(m.coef_step)) m.coef_step = 1e-12;
  // Basis budget per PC proportional to its entries (3 N_s): step x sigma is the same for every
  // PC of every unit (with one segment: an equal share per PC).
  const double per_entry = total_entries > 0 ? d_basis / static_cast<double>(total_entries) : 0;

  m.cluster.resize(nc);
  double t_quant = 0, t_lcps = 0;
  for (size_t c = 0; c < nc; ++c)
    code_unit(prep, c, r[c], per_entry, m.coef_step, m.f32_scales, o, &m.cluster[c], &t_quant,
              &t_lcps);
  // The decoder's reconstruction path on the quantised model.
  ts::reconstruct(m, &tr.recon);
  tr.sq = sq_error(base.in, tr.recon);
  ByteWriter bw;
  try {
    ts::write_model(m, &bw);
    tr.bytes = std::move(bw.buffer());
    tr.ok = tr.sq <= base.target_sq;
  } catch (const Error& e) {  // a quantised value outside int32: this budget is unusable
    if (e.code() != ErrorCode::kInternal) throw;
    tr.sq = std::numeric_limits<double>::infinity();
    tr.ok = false;
  }
  if (rep) {
    rep->t_quant += t_quant;
    rep->t_lcps += t_lcps;
    ++rep->trials;
  }
  (void)t0;
  return tr;
}

// Searches the budget scale so that the error lands just under the target; smallest passing wins.
Trial rate_search(const Base& base, const Prepared& prep, const Options& o, double* scale,
                  TsEncodeReport* rep) {
  Trial best;
  bool have = false;
  Trial fallback;
  bool have_fb = false;
  double lo = 0, hi = std::numeric_limits<double>::infinity();
  double s = *scale, best_s = s;
  for (int it = 0; it < 10; ++it) {
    Trial t = build_trial(base, prep, s * base.target_sq, o, rep);
    const double err = std::max(t.sq, 1e-300);
    if (t.ok) {
      lo = std::max(lo, s);
      if (!have || t.bytes.size() < best.bytes.size()) {
        best = std::move(t);
        have = true;
        best_s = s;
      }
    } else {
      hi = std::min(hi, s);
      if (!have_fb || t.sq < fallback.sq) {
        fallback = std::move(t);
        have_fb = true;
      }
    }
    // Error grows about linearly with the budget: aim just under the target.
    double next = s * base.target_sq / err * 0.97;
    if (!(next > lo && next < hi))
      next = std::isinf(hi) ? std::max(lo, s) * 2 : (lo > 0 ? std::sqrt(lo * hi) : hi / 4);
    if (have && std::fabs(next / s - 1) < 0.02) break;
    if (have && hi < std::numeric_limits<double>::infinity() && hi / lo < 1.04) break;
    if (s < 1e-12) break;
    s = next;
  }
  *scale = best_s;
  return have ? best : fallback;
}

// The model every window can be written with (when no trial fits the payload's int32 values):
// one cluster, no rigid motion, one PC = the direction of the mean frame, its coefficients coded
// directly (LPC order 0) with a step fine enough for the target when int32 allows, else the
// finest that fits (|value| <= 2^29). An all-zero window gets zero PCs.
Trial fallback_trial(const Base& base, const Options& o) {
  Trial tr;
  TsModel& m = tr.model;
  const size_t nf = base.in.frames;
  m.frames = nf;
  m.points = base.in.points;
  m.basis_predict = o.basis_predict;
  m.clusters = 1;
  m.label.assign(nf, 0);
  m.cluster.resize(1);
  TsCluster& tc = m.cluster[0];
  Eigen::Map<const Eigen::MatrixXd> x(base.in.xyz, static_cast<Eigen::Index>(base.dim),
                                      static_cast<Eigen::Index>(nf));
  const Eigen::VectorXd mean = x.rowwise().mean();
  Eigen::MatrixXd w(0, static_cast<Eigen::Index>(nf));
  if (mean.norm() > 0 && std::isfinite(mean.norm())) {
    const Eigen::VectorXd dir = mean / mean.norm();
    tc.basis.push_back(ts::quantise_vector_step(dir.data(), base.dim, std::ldexp(1.0, -24), 30));
    Eigen::VectorXd bq(static_cast<Eigen::Index>(base.dim));
    ts::dequantise_vector(tc.basis[0], bq.data());
    w = (bq.transpose() * x) / bq.squaredNorm();
  }
  double top = 0;
  for (Eigen::Index j = 0; j < w.size(); ++j) top = std::max(top, std::fabs(w(j)));
  const double target_step =
      std::sqrt(12.0 * base.target_sq / std::max<double>(1.0, static_cast<double>(w.size())));
  m.coef_step = std::max({target_step, top * std::ldexp(1.0, -29), 1e-300});
  ts::LpcParams lp;
  lp.order = 0;
  tc.first = ts::lpc_encode(w, std::vector<double>(static_cast<size_t>(w.rows()), m.coef_step), lp,
                            nullptr);
  tc.lcps_weight_bits = 4;
  ts::reconstruct(m, &tr.recon);
  tr.sq = sq_error(base.in, tr.recon);
  ByteWriter bw;
  ts::write_model(m, &bw);
  tr.bytes = std::move(bw.buffer());
  tr.ok = tr.sq <= base.target_sq;
  return tr;
}

Prepared prepare(const Base& base, int k, const ts::Segmentation& seg, const Options& o,
                 TsEncodeReport* rep) {
  Prepared p;
  auto t0 = Clock::now();
  const size_t nf = base.in.frames;
  if (k <= 1) {
    p.k = 1;
    p.label.assign(nf, 0);
  } else {
    ts::ClusterParams cp;
    cp.k = k;
    cp.seed = o.seed;
    cp.restarts = o.restarts;
    ts::Clustering cl = ts::kmeans_frames(base.aligned, cp);
    p.k = cl.k;
    p.label.assign(cl.label.begin(), cl.label.end());
  }
  p.layout = ts::cluster_layout(p.label, p.k);
  if (seg.segments > 1) {
    p.segments = seg.segments;
    p.segment = seg.label;
    p.members = ts::segment_members(seg.label, seg.segments);
  } else {
    p.members.assign(1, std::vector<uint32_t>(base.in.points));
    for (size_t i = 0; i < base.in.points; ++i) p.members[0][i] = static_cast<uint32_t>(i);
  }
  if (rep) rep->t_cluster += since(t0);
  auto t1 = Clock::now();
  const size_t nf_all = base.in.frames;
  for (const auto& pts : p.members) {
    // The segment's aligned frames (3 N_s x F), with its own rigid motion removed when asked.
    Eigen::MatrixXd frames_s(static_cast<Eigen::Index>(3 * pts.size()),
                             static_cast<Eigen::Index>(nf_all));
    for (size_t f = 0; f < nf_all; ++f) {
      const double* src = base.aligned.col(static_cast<Eigen::Index>(f)).data();
      double* dst = frames_s.col(static_cast<Eigen::Index>(f)).data();
      for (size_t i = 0; i < pts.size(); ++i)
        for (size_t a = 0; a < 3; ++a) dst[3 * i + a] = src[3 * size_t{pts[i]} + a];
    }
    if (p.segments > 1 && o.segment_align && nf_all > 1) {
      TsModel::SegmentMotion sm;
      Eigen::Vector3d lo = Eigen::Vector3d::Constant(INFINITY), hi = -lo;
      for (Eigen::Index f = 0; f < frames_s.cols(); ++f)
        for (Eigen::Index i = 0; i < frames_s.rows() / 3; ++i) {
          lo = lo.cwiseMin(frames_s.col(f).segment<3>(3 * i));
          hi = hi.cwiseMax(frames_s.col(f).segment<3>(3 * i));
        }
      // Rotations about the segment's centroid in frame 0, not the origin: the translations stay
      // small and smooth (measured: -19 % on chickenCrossing, -1.6 % on horse-gallop).
      for (Eigen::Index a = 0; a < 3; ++a) {
        double c = 0;
        for (Eigen::Index i = 0; i < frames_s.rows() / 3; ++i) c += frames_s(3 * i + a, 0);
        sm.center[a] = c / static_cast<double>(frames_s.rows() / 3);
      }
      for (Eigen::Index f = 0; f < frames_s.cols(); ++f)
        for (Eigen::Index i = 0; i < frames_s.rows() / 3; ++i)
          for (Eigen::Index a = 0; a < 3; ++a) frames_s(3 * i + a, f) -= sm.center[a];
      // (Measured: steps 4x / 16x / 64x coarser cut the rigid part but the PCs absorb the
      // misalignment: -1 % / 0 % / 0 % on chickenCrossing, +3 % / +7 % / +18 % on horse-gallop.)
      sm.code = code_rigid(base.in.valid, base.in.points, base.rms, (hi - lo).norm(), o.lpc_order,
                           &frames_s, &sm.rot_step, &sm.trans_step, pts);
      p.motion.push_back(std::move(sm));
    }
    for (const auto& lay : p.layout) {
      Eigen::MatrixXd f(frames_s.rows(), static_cast<Eigen::Index>(lay.frames.size()));
      for (size_t j = 0; j < lay.frames.size(); ++j)
        f.col(static_cast<Eigen::Index>(j)) =
            frames_s.col(static_cast<Eigen::Index>(lay.frames[j]));
      p.pca.push_back(ts::pca_frames(f, ts::PcaParams()));
      p.frames.push_back(std::move(f));
    }
  }
  if (rep) rep->t_pca += since(t1);
  return p;
}

// Sums over a window's valid samples: their count, the squared distances from each frame's
// centroid, and the squared diagonal of their bounding box (0 when there are none).
struct WindowStats {
  size_t samples = 0;
  double centred = 0, diag2 = 0;
};

WindowStats window_stats(const PositionsView& in) {
  WindowStats st;
  const size_t nf = in.frames;
  double lo[3] = {INFINITY, INFINITY, INFINITY}, hi[3] = {-INFINITY, -INFINITY, -INFINITY};
  for (size_t f = 0; f < nf; ++f) {
    double c[3] = {0, 0, 0};
    size_t n = 0;
    for (size_t p = 0; p < in.points; ++p) {
      if (!in.valid[f * in.points + p]) continue;
      for (int a = 0; a < 3; ++a) c[a] += in.xyz[(f * in.points + p) * 3 + a];
      ++n;
    }
    if (n == 0) continue;
    st.samples += n;
    for (int a = 0; a < 3; ++a) c[a] /= static_cast<double>(n);
    for (size_t p = 0; p < in.points; ++p) {
      if (!in.valid[f * in.points + p]) continue;
      for (int a = 0; a < 3; ++a) {
        const double x = in.xyz[(f * in.points + p) * 3 + a];
        st.centred += (x - c[a]) * (x - c[a]);
        lo[a] = std::min(lo[a], x);
        hi[a] = std::max(hi[a], x);
      }
    }
  }
  if (st.samples > 0)
    for (int a = 0; a < 3; ++a) st.diag2 += (hi[a] - lo[a]) * (hi[a] - lo[a]);
  return st;
}

// Sets base->target_sq (the error budget: a sum of squared errors over the valid samples) and
// rep->kg_target from the error targets.
void set_target(const TransformParams& params, const Options& o, const WindowStats& st, Base* base,
                TsEncodeReport* rep) {
  if (params.kg_error > 0 && params.max_error == 0) {
    base->target_sq = (params.kg_error / 100) * (params.kg_error / 100) * st.centred;
    rep->kg_target = params.kg_error;
  } else if (params.max_error > 0) {
    const double rms = o.rms_per_bound * params.max_error;
    base->target_sq = 3.0 * static_cast<double>(st.samples) * rms * rms;
    rep->kg_target = st.centred > 0 ? 100 * std::sqrt(base->target_sq / st.centred) : 0;
  } else {
    base->target_sq = 1e-6 * st.centred;  // KG 0.1 %
    rep->kg_target = 0.1;
  }
  if (!(base->target_sq > 0))
    base->target_sq =
        1e-20 * std::max(1.0, st.diag2) * static_cast<double>(std::max<size_t>(st.samples, 1));
}

// Stage 1: copies the frames into base->aligned and, when alignment applies, codes their rigid
// motion (6 parameters, LPC) and removes it with the decoded parameters, so that the decoder's
// inverse is exact.
void align_stage(const PositionsView& in, const Options& o, const WindowStats& st, Base* base,
                 TsEncodeReport* rep) {
  const size_t nf = in.frames;
  auto ta = Clock::now();
  base->aligned.resize(static_cast<Eigen::Index>(base->dim), static_cast<Eigen::Index>(nf));
  for (size_t f = 0; f < nf; ++f)
    std::copy(in.xyz + f * base->dim, in.xyz + (f + 1) * base->dim,
              base->aligned.col(static_cast<Eigen::Index>(f)).data());
  base->rigid = o.align && nf > 1 && in.points >= 3;
  base->rms =
      std::sqrt(base->target_sq / (3.0 * static_cast<double>(std::max<size_t>(st.samples, 1))));
  if (base->rigid)
    base->rigid_code = code_rigid(in.valid, in.points, base->rms, std::sqrt(st.diag2), o.lpc_order,
                                  &base->aligned, &base->rot_step, &base->trans_step);
  rep->t_align = since(ta);
}

// Stages 2..4 for each (segment count, cluster count) tried: the trial with the smallest payload
// that meets the target (else the one closest to it); the fallback model when no trial fits the
// payload's int32 values, the empty model for an empty window.
Trial search_models(const Base& base, const TransformParams& params, const Options& o,
                    TsEncodeReport* rep) {
  const PositionsView& in = base.in;
  const size_t nf = in.frames;
  const int kmax = static_cast<int>(
      std::min<size_t>(static_cast<size_t>(o.max_clusters), std::max<size_t>(nf, 1)));
  const bool k_auto = params.clusters <= 0;  // auto (the default): K = 1..max_clusters
  const int k_fixed = k_auto ? 1
                             : static_cast<int>(std::min<size_t>(
                                   static_cast<size_t>(params.clusters), std::max<size_t>(nf, 1)));
  Trial best;
  bool have = false;
  double scale = 1.0;  // each run starts its search where the previous one ended
  // One run: returns the payload size of its best trial (infinity when none met the target).
  auto run = [&](int k, const ts::Segmentation& seg) {
    Prepared prep = prepare(base, k, seg, o, rep);
    Trial t = rate_search(base, prep, o, &scale, rep);
    // A target tighter than the basis quantiser allows (the first PC carries the mean shape and
    // needs the finest step): widen the basis bits beyond the paper's 16 until it is met.
    for (Options wide = o; !t.ok && wide.bits_max < 24;) {
      wide.bits_max = std::min(24, wide.bits_max + 4);
      double s2 = 1.0;
      Trial t2 = rate_search(base, prep, wide, &s2, rep);
      if (t2.ok || t2.sq < t.sq) t = std::move(t2);
    }
    const double size = t.ok && !t.bytes.empty() ? static_cast<double>(t.bytes.size()) : INFINITY;
    const bool better =
        !have || (t.ok && !best.ok) ||
        (t.ok == best.ok && (t.ok ? t.bytes.size() < best.bytes.size() : t.sq < best.sq));
    if (better) {
      best = std::move(t);
      have = true;
    }
    return size;
  };
  if (nf > 0) {
    // Point segments: a fixed count, or (auto) the counts of kAutoSegments with at least
    // kMinPointsPerSegment points each on average, in increasing order while the payload shrinks.
    auto segment = [&](int n) {
      ts::SegmentParams sp;
      sp.segments = n;
      sp.seed = o.seed;
      auto t0 = Clock::now();
      ts::Segmentation sg = ts::segment_points(base.aligned, sp);
      rep->t_segment += since(t0);
      return sg;
    };
    ts::Segmentation best_seg = segment(1);
    double seg_size = INFINITY;  // payload size at best_seg
    if (o.segments > 0) {
      best_seg = segment(o.segments);
      seg_size = run(k_fixed, best_seg);
    } else {
      // The ladder 1, 2, 4, .., 64 cut to counts with >= kMinPointsPerSegment points per segment
      // on average; start at kAutoSegmentsStart (or the largest allowed), then walk down while
      // the payload shrinks, else up while it shrinks.
      std::vector<int> ladder;
      for (int n = 1; n <= ts::kMaxSegments &&
                      (n == 1 || static_cast<size_t>(n) * kMinPointsPerSegment <= in.points);
           n *= 2)
        ladder.push_back(n);
      size_t at = 0;
      while (at + 1 < ladder.size() && ladder[at + 1] <= kAutoSegmentsStart) ++at;
      std::vector<double> size(ladder.size(), -1);
      std::vector<ts::Segmentation> segs(ladder.size());
      auto eval = [&](size_t i) {
        if (size[i] < 0) {
          segs[i] = segment(ladder[i]);
          size[i] = run(k_fixed, segs[i]);
        }
        return size[i];
      };
      size_t best_i = at;
      eval(at);
      for (size_t i = at; i > 0 && eval(i - 1) < size[best_i]; --i) best_i = i - 1;
      if (best_i == at)
        for (size_t i = at; i + 1 < ladder.size() && eval(i + 1) < size[best_i]; ++i)
          best_i = i + 1;
      best_seg = std::move(segs[best_i]);
      seg_size = size[best_i];
    }
    // --clusters auto: K = 2, 3, .. max_clusters at the chosen segments while the payload shrinks.
    for (int k = 2; k_auto && k <= kmax; ++k) {
      const double size = run(k, best_seg);
      if (!(size < seg_size)) break;
      seg_size = size;
    }
  }
  if (have && best.bytes.empty())  // every budget tried gave values outside the payload's range
    best = fallback_trial(base, o);
  if (!have) {  // empty window
    best.model.frames = nf;
    best.model.points = in.points;
    best.model.clusters = 1;
    best.model.label.assign(nf, 0);
    ts::reconstruct(best.model, &best.recon);
    ByteWriter bw;
    ts::write_model(best.model, &bw);
    best.bytes = std::move(bw.buffer());
  }
  return best;
}

// Fills the report's model description and achieved error from the chosen trial.
void fill_report(const Trial& best, size_t nf, const WindowStats& st, TsEncodeReport* rep) {
  rep->clusters = best.model.clusters;
  rep->segments = best.model.segments;
  rep->pcs.clear();
  rep->cluster_frames.clear();
  rep->segment_points.clear();
  if (nf > 0) {
    const auto lay = ts::cluster_layout(best.model.label, best.model.clusters);
    for (const auto& l : lay) rep->cluster_frames.push_back(l.frames.size());
    for (const auto& pts : ts::segment_points_of(best.model))
      rep->segment_points.push_back(pts.size());
    for (const TsCluster& tc : best.model.cluster) {
      rep->pcs.push_back(static_cast<int>(tc.basis.size()));
      for (const auto& q : tc.basis) rep->basis_bits.push_back(q.bits);
    }
  }
  rep->kg_error = st.centred > 0 ? 100 * std::sqrt(best.sq / st.centred) : 0;
  rep->bytes = best.bytes.size();
  rep->coef_step = best.model.coef_step;
}

}  // namespace

void TsCodec::check_params(const TransformParams& params) const {
  parse_options(params);
}

void TsCodec::encode(const PositionsView& in, const TransformParams& params,
                     std::vector<uint8_t>* out, std::vector<double>* recon) const {
  encode_report(in, params, out, recon, nullptr);
}

void TsCodec::encode_report(const PositionsView& in, const TransformParams& params,
                            std::vector<uint8_t>* out, std::vector<double>* recon,
                            TsEncodeReport* report) const {
  TsEncodeReport local;
  TsEncodeReport* rep = report ? report : &local;
  *rep = TsEncodeReport();
  auto t_start = Clock::now();
  const Options o = parse_options(params);
  if (params.max_error < 0 || params.kg_error < 0 || !std::isfinite(params.max_error) ||
      !std::isfinite(params.kg_error))
    fail(ErrorCode::kInvalidParameter, "", "ts: error targets must be finite and >= 0");
  Base base;
  base.in = in;
  base.dim = 3 * in.points;
  const size_t nf = in.frames;

  // Error budget: sum of squared errors over the valid samples.
  const WindowStats st = window_stats(in);
  set_target(params, o, st, &base, rep);
  // Stage 1: alignment.
  align_stage(in, o, st, &base, rep);
  Trial best = search_models(base, params, o, rep);
  fill_report(best, nf, st, rep);
  out->insert(out->end(), best.bytes.begin(), best.bytes.end());
  *recon = std::move(best.recon);
  rep->t_total = since(t_start);
}

}  // namespace capz
