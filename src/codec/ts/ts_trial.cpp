// ts codec, encode side: one model for a window (ts_trial.h).
#include "codec/ts/ts_trial.h"

#include <Eigen/Cholesky>
#include <algorithm>
#include <cmath>
#include <limits>

#include "capz/error.h"
#include "codec/ts/align.h"
#include "codec/ts/cluster.h"
#include "codec/ts/lcps.h"
#include "codec/ts/rigid.h"

namespace capz {
namespace ts {
namespace enc {

namespace {
using ts::ClusterLayout;
using ts::TsCluster;
using ts::TsModel;
}  // namespace

// Stage 1 (and per segment): aligns the frames (3n x F, column = frame) to frame 0 in place, with
// the decoded parameters of the returned LPC code so that the decoder's inverse is exact; the
// quantisation steps are tied to the target RMS: translation 0.5 rms, rotation 0.5 rms / extent.
// `valid` is per (frame, point) with stride `valid_stride` points per frame, `valid_map` (if not
// empty) the points' indices in it.
ts::LpcCode code_rigid(const uint8_t* valid, size_t valid_stride, double rms, double extent,
                       int lpc_order, Eigen::MatrixXd* frames, double* rot_step, double* trans_step,
                       const std::vector<uint32_t>& valid_map) {
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

namespace {

// The model's fields that the window, its alignment and the preparation fix.
void init_model(const Base& base, const Prepared& prep, const Options& o, TsModel* model) {
  TsModel& m = *model;
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
}

// PCs kept per unit: a global threshold on sigma^2 (the paper's per-cluster "covered variation"
// threshold, set from the error target): drops the smallest components of all units while their
// energy fits in d_trunc.
std::vector<int> kept_ranks(const Prepared& prep, double d_trunc) {
  const size_t nc = prep.pca.size();
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
  return r;
}

// The decoder's reconstruction path on the quantised model, its error, and the model's bytes;
// a quantised value outside int32 makes the trial unusable (infinite error, not ok).
void finish_trial(const Base& base, Trial* tr) {
  ts::reconstruct(tr->model, &tr->recon);
  tr->sq = sq_error(base.in, tr->recon);
  ByteWriter bw;
  try {
    ts::write_model(tr->model, &bw);
    tr->bytes = std::move(bw.buffer());
    tr->ok = tr->sq <= base.target_sq;
  } catch (const Error& e) {  // a quantised value outside int32: this budget is unusable
    if (e.code() != ErrorCode::kInternal) throw;
    tr->sq = std::numeric_limits<double>::infinity();
    tr->ok = false;
  }
}

}  // namespace

Trial build_trial(const Base& base, const Prepared& prep, double budget, const Options& o,
                  TsEncodeReport* rep) {
  auto t0 = Clock::now();
  Trial tr;
  TsModel& m = tr.model;
  init_model(base, prep, o, &m);
  const size_t nc = prep.pca.size();  // units: segments x clusters

  const double d_trunc = o.trunc_share * budget, d_basis = o.basis_share * budget;
  const double d_coef = budget - d_trunc - d_basis;
  const std::vector<int> r = kept_ranks(prep, d_trunc);
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
  finish_trial(base, &tr);
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

namespace {

// The frames' clusters into p (k <= 1: one cluster of every frame, else k-means) and their
// layout.
void cluster_frames(const Base& base, int k, const Options& o, Prepared* p) {
  if (k <= 1) {
    p->k = 1;
    p->label.assign(base.in.frames, 0);
  } else {
    ts::ClusterParams cp;
    cp.k = k;
    cp.seed = o.seed;
    cp.restarts = o.restarts;
    ts::Clustering cl = ts::kmeans_frames(base.aligned, cp);
    p->k = cl.k;
    p->label.assign(cl.label.begin(), cl.label.end());
  }
  p->layout = ts::cluster_layout(p->label, p->k);
}

// The aligned frames of the points pts (3 N_s x F).
Eigen::MatrixXd segment_frames(const Base& base, const std::vector<uint32_t>& pts) {
  const size_t nf_all = base.in.frames;
  Eigen::MatrixXd frames_s(static_cast<Eigen::Index>(3 * pts.size()),
                           static_cast<Eigen::Index>(nf_all));
  for (size_t f = 0; f < nf_all; ++f) {
    const double* src = base.aligned.col(static_cast<Eigen::Index>(f)).data();
    double* dst = frames_s.col(static_cast<Eigen::Index>(f)).data();
    for (size_t i = 0; i < pts.size(); ++i)
      for (size_t a = 0; a < 3; ++a) dst[3 * i + a] = src[3 * size_t{pts[i]} + a];
  }
  return frames_s;
}

// Removes the segment's own rigid motion from its frames (of the points pts) and returns it
// coded: about the segment's centroid in frame 0.
TsModel::SegmentMotion remove_segment_motion(const Base& base, const Options& o,
                                             const std::vector<uint32_t>& pts,
                                             Eigen::MatrixXd* frames) {
  Eigen::MatrixXd& frames_s = *frames;
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
  return sm;
}

}  // namespace

Prepared prepare(const Base& base, int k, const ts::Segmentation& seg, const Options& o,
                 TsEncodeReport* rep) {
  Prepared p;
  auto t0 = Clock::now();
  cluster_frames(base, k, o, &p);
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
  for (const auto& pts : p.members) {
    // The segment's aligned frames, with its own rigid motion removed when asked.
    Eigen::MatrixXd frames_s = segment_frames(base, pts);
    if (p.segments > 1 && o.segment_align && base.in.frames > 1)
      p.motion.push_back(remove_segment_motion(base, o, pts, &frames_s));
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

}  // namespace enc
}  // namespace ts
}  // namespace capz
