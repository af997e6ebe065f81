// ts codec, encode side (ts_encoder.h): the options, the error target, the alignment and the
// search over point segmentations and cluster counts; each model tried is built by ts_trial.
#include "codec/ts/ts_encoder.h"

#include <algorithm>
#include <cmath>

#include "capz/error.h"
#include "codec/ts/segment.h"
#include "codec/ts/ts_model.h"
#include "codec/ts/ts_trial.h"

namespace capz {

namespace {

using ts::TsCluster;
using ts::enc::Base;
using ts::enc::Clock;
using ts::enc::Options;
using ts::enc::since;
using ts::enc::Trial;

// segments=auto: where the search over 1, 2, 4, .., 64 segments starts, and the fewest points a
// segment needs on average to be tried.
constexpr int kAutoSegmentsStart = 16;
constexpr size_t kMinPointsPerSegment = 48;

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
    base->rigid_code =
        ts::enc::code_rigid(in.valid, in.points, base->rms, std::sqrt(st.diag2), o.lpc_order,
                            &base->aligned, &base->rot_step, &base->trans_step);
  rep->t_align = since(ta);
}

// The search over models for one window: the best trial of the runs so far (the smallest payload
// that meets the target, else the one closest to it).
class ModelSearch {
 public:
  ModelSearch(const Base& base, const Options& o, TsEncodeReport* rep)
      : base_(base), o_(o), rep_(rep) {}

  // Segments the aligned points into n segments (timed in the report).
  ts::Segmentation segment(int n) const {
    ts::SegmentParams sp;
    sp.segments = n;
    sp.seed = o_.seed;
    auto t0 = Clock::now();
    ts::Segmentation sg = ts::segment_points(base_.aligned, sp);
    rep_->t_segment += since(t0);
    return sg;
  }

  // One run: the trial of k clusters at seg, kept when better than the best so far; returns its
  // payload size (infinity when it did not meet the target).
  double run(int k, const ts::Segmentation& seg) {
    Trial t = trial(k, seg);
    const double size = t.ok && !t.bytes.empty() ? static_cast<double>(t.bytes.size()) : INFINITY;
    const bool better =
        !have_ || (t.ok && !best_.ok) ||
        (t.ok == best_.ok && (t.ok ? t.bytes.size() < best_.bytes.size() : t.sq < best_.sq));
    if (better) {
      best_ = std::move(t);
      have_ = true;
    }
    return size;
  }

  // segments=auto: the ladder 1, 2, 4, .., 64 cut to counts with >= kMinPointsPerSegment points
  // per segment on average; starts at kAutoSegmentsStart (or the largest allowed), then walks
  // down while the payload of k clusters shrinks, else up while it shrinks. Returns the chosen
  // segmentation and sets *seg_size to its payload size.
  ts::Segmentation auto_segments(int k, double* seg_size) {
    std::vector<int> ladder;
    for (int n = 1; n <= ts::kMaxSegments &&
                    (n == 1 || static_cast<size_t>(n) * kMinPointsPerSegment <= base_.in.points);
         n *= 2)
      ladder.push_back(n);
    size_t at = 0;
    while (at + 1 < ladder.size() && ladder[at + 1] <= kAutoSegmentsStart) ++at;
    std::vector<double> size(ladder.size(), -1);
    std::vector<ts::Segmentation> segs(ladder.size());
    auto eval = [&](size_t i) {
      if (size[i] < 0) {
        segs[i] = segment(ladder[i]);
        size[i] = run(k, segs[i]);
      }
      return size[i];
    };
    size_t best_i = at;
    eval(at);
    for (size_t i = at; i > 0 && eval(i - 1) < size[best_i]; --i) best_i = i - 1;
    if (best_i == at)
      for (size_t i = at; i + 1 < ladder.size() && eval(i + 1) < size[best_i]; ++i) best_i = i + 1;
    *seg_size = size[best_i];
    return std::move(segs[best_i]);
  }

  // The best trial; the fallback model when no trial fits the payload's int32 values, the empty
  // model when nothing was run (an empty window).
  Trial result() {
    if (have_ && best_.bytes.empty())  // every budget tried gave values outside the payload's range
      best_ = ts::enc::fallback_trial(base_, o_);
    if (!have_) {  // empty window
      best_.model.frames = base_.in.frames;
      best_.model.points = base_.in.points;
      best_.model.clusters = 1;
      best_.model.label.assign(base_.in.frames, 0);
      ts::reconstruct(best_.model, &best_.recon);
      ByteWriter bw;
      ts::write_model(best_.model, &bw);
      best_.bytes = std::move(bw.buffer());
    }
    return std::move(best_);
  }

 private:
  // The trial of k clusters at seg. A target tighter than the basis quantiser allows (the first
  // PC carries the mean shape and needs the finest step): widens the basis bits beyond the
  // paper's 16 until it is met.
  Trial trial(int k, const ts::Segmentation& seg) {
    ts::enc::Prepared prep = ts::enc::prepare(base_, k, seg, o_, rep_);
    Trial t = ts::enc::rate_search(base_, prep, o_, &scale_, rep_);
    for (Options wide = o_; !t.ok && wide.bits_max < 24;) {
      wide.bits_max = std::min(24, wide.bits_max + 4);
      double s2 = 1.0;
      Trial t2 = ts::enc::rate_search(base_, prep, wide, &s2, rep_);
      if (t2.ok || t2.sq < t.sq) t = std::move(t2);
    }
    return t;
  }

  const Base& base_;
  const Options& o_;
  TsEncodeReport* rep_;
  Trial best_;
  bool have_ = false;
  double scale_ = 1.0;  // each run starts its search where the previous one ended
};

// Stages 2..4 for each (segment count, cluster count) tried: the trial with the smallest payload
// that meets the target (else the one closest to it); the fallback model when no trial fits the
// payload's int32 values, the empty model for an empty window.
Trial search_models(const Base& base, const TransformParams& params, const Options& o,
                    TsEncodeReport* rep) {
  const size_t nf = base.in.frames;
  const int kmax = static_cast<int>(
      std::min<size_t>(static_cast<size_t>(o.max_clusters), std::max<size_t>(nf, 1)));
  const bool k_auto = params.clusters <= 0;  // auto (the default): K = 1..max_clusters
  const int k_fixed = k_auto ? 1
                             : static_cast<int>(std::min<size_t>(
                                   static_cast<size_t>(params.clusters), std::max<size_t>(nf, 1)));
  ModelSearch search(base, o, rep);
  if (nf > 0) {
    // Point segments: a fixed count, or (auto) the counts of kAutoSegments with at least
    // kMinPointsPerSegment points each on average, in increasing order while the payload shrinks.
    ts::Segmentation best_seg = search.segment(1);
    double seg_size = INFINITY;  // payload size at best_seg
    if (o.segments > 0) {
      best_seg = search.segment(o.segments);
      seg_size = search.run(k_fixed, best_seg);
    } else {
      best_seg = search.auto_segments(k_fixed, &seg_size);
    }
    // --clusters auto: K = 2, 3, .. max_clusters at the chosen segments while the payload shrinks.
    for (int k = 2; k_auto && k <= kmax; ++k) {
      const double size = search.run(k, best_seg);
      if (!(size < seg_size)) break;
      seg_size = size;
    }
  }
  return search.result();
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
