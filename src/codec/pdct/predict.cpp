// Decoder library (capz_decode): builds without PCL and without the transform encoders.
#include "codec/pdct/predict.h"

#include <algorithm>
#include <array>
#include <memory>
#include <string>

#include "capz/error.h"
#include "codec/pdct/dct.h"

namespace capz {
namespace pdct {

BlockDct::BlockDct(size_t n, size_t block) : n_(n), block_(block) {
  if (n_ >= block_) full_.reset(new DctPlan(block_));
  if (n_ % block_) tail_.reset(new DctPlan(n_ % block_));
}

size_t BlockDct::block_size(size_t b) const {
  return std::min(block_, n_ - b * block_);
}

void BlockDct::forward(const double* x, double* X) const {
  for (size_t b = 0; b < blocks(); ++b) {
    const DctPlan& p = block_size(b) == block_ ? *full_ : *tail_;
    p.forward(x + b * block_, X + b * block_);
  }
}

void BlockDct::inverse(const double* X, double* x) const {
  for (size_t b = 0; b < blocks(); ++b) {
    const DctPlan& p = block_size(b) == block_ ? *full_ : *tail_;
    p.inverse(X + b * block_, x + b * block_);
  }
}

void check_layout(const Layout& L, const char* what) {
  auto bad = [what](const std::string& m) {
    throw Error(ErrorCode::kCorrupt, std::string(what) + ": " + m);
  };
  std::vector<uint8_t> seen(L.points, 0);
  for (size_t k = 0; k < L.frame_points.size(); ++k) {
    const uint32_t p = L.frame_points[k];
    if (p >= L.points) bad("frame point " + std::to_string(p) + " out of range");
    if (k > 0 && p <= L.frame_points[k - 1]) bad("frame points not ascending");
    seen[p] = 1;
  }
  if (L.dct_block < 1 || L.dct_block > kMaxDctBlock)
    bad("dct block " + std::to_string(L.dct_block));
  if (L.triangles.size() != L.members.size()) bad("cluster count mismatch");
  for (const auto& t : L.triangles)
    if (!(t[0] == t[1] && t[1] == t[2]))
      for (uint32_t v : t)
        if (v >= L.frame_points.size())
          bad("triangle vertex " + std::to_string(v) + " out of range");
  for (const auto& m : L.members)
    for (size_t j = 0; j < m.size(); ++j) {
      if (m[j] >= L.points) bad("member " + std::to_string(m[j]) + " out of range");
      if (j > 0 && m[j] <= m[j - 1]) bad("cluster members not ascending");
      if (seen[m[j]]) bad("point " + std::to_string(m[j]) + " coded twice");
      seen[m[j]] = 1;
    }
  for (size_t i = 0; i < L.points; ++i)
    if (!seen[i]) bad("point " + std::to_string(i) + " belongs to no cluster");
}

namespace {

// Cluster frame of triangle t on the decoded frame-point positions fp: the identity for a
// degenerate triangle (one vertex three times), else make_lcf() on its vertices.
Lcf cluster_frame(const std::array<uint32_t, 3>& t, const double* fp) {
  return (t[0] == t[1] && t[1] == t[2]) ? identity_lcf()
                                        : make_lcf(&fp[3 * t[0]], &fp[3 * t[1]], &fp[3 * t[2]]);
}

// Step 1 of frame f: the K frame points' integers I0 from their predictions (in frame 0 the
// previous frame point, else the last frame or, with seed order 2, the line through the last
// two) and the hooks' residuals.
void decode_seeds(size_t K, int seed_order, size_t f, LoopHooks* hooks, std::vector<int64_t>* I0,
                  const std::vector<int64_t>& I1, const std::vector<int64_t>& I2) {
  for (size_t k = 0; k < K; ++k)
    for (int a = 0; a < 3; ++a) {
      const size_t j = 3 * k + a;
      int64_t p;
      if (f == 0)
        p = k == 0 ? 0 : (*I0)[j - 3];
      else if (seed_order == 2 && f >= 2)
        p = wrap_add(wrap_add(I1[j], I1[j]), -I2[j]);
      else
        p = I1[j];
      (*I0)[j] = wrap_add(p, hooks->seed_residual(f, k, a, p));
    }
}

// Frame 0 of cluster c (n members): each member's local position predicted by the member
// before it (0 for the first), into q.
void decode_first_cluster(size_t c, size_t n, const Lcf& frame, double first_step, LoopHooks* hooks,
                          double* q) {
  int64_t prev[3] = {0, 0, 0};
  for (size_t m = 0; m < n; ++m)
    for (int a = 0; a < 3; ++a) {
      const int64_t v = wrap_add(prev[a], hooks->first_residual(c, m, a, frame, prev[a]));
      prev[a] = v;
      q[3 * m + a] = on_grid(v, first_step);
    }
}

// Buffers reused by decode_cluster_step across clusters and frames.
struct StepScratch {
  std::vector<double> pred, col, col_out;
  std::vector<int64_t> coefs;
};

// Frame f > 0 of cluster c (n members, q1 and q2 its local positions in the last two frames):
// the prediction (the last frame, or with local order 2 the line through the last two) plus the
// inverse DCT of the dequantised coefficients, into q.
void decode_cluster_step(size_t f, size_t c, size_t n, const Lcf& frame, const Steps& S,
                         const BlockDct& plan, const std::vector<double>& q1,
                         const std::vector<double>& q2, LoopHooks* hooks, StepScratch* s,
                         double* q) {
  std::vector<double>& pred = s->pred;
  pred.resize(n * 3);
  if (S.local_order == 2 && f >= 2)
    for (size_t j = 0; j < n * 3; ++j) pred[j] = 2.0 * q1[j] - q2[j];
  else
    pred = q1;
  s->coefs.assign(3 * n, 0);
  hooks->coefficients(f, c, frame, pred.data(), plan, s->coefs.data());
  s->col.resize(n);
  s->col_out.resize(n);
  for (int a = 0; a < 3; ++a) {
    dequantise(&s->coefs[a * n], n, S.coef, s->col.data());
    plan.inverse(s->col.data(), s->col_out.data());
    for (size_t m = 0; m < n; ++m) q[3 * m + a] = pred[3 * m + a] + s->col_out[m];
  }
}

}  // namespace

void run_closed_loop(const Layout& L, const Steps& S, LoopHooks* hooks,
                     std::vector<double>* recon) {
  const size_t F = L.frames, P = L.points, K = L.frame_points.size(), C = L.triangles.size();
  recon->assign(F * P * 3, 0.0);
  if (F == 0 || P == 0) return;

  // Frame points: integer history of the last two frames.
  std::vector<int64_t> I1(K * 3, 0), I2(K * 3, 0), I0(K * 3, 0);
  std::vector<double> fp(K * 3);  // decoded frame-point positions in the current frame
  // Per cluster: decoded local coordinates in the last two frames (members x 3).
  std::vector<std::vector<double>> q1(C), q2(C);
  std::vector<std::unique_ptr<BlockDct>> dcts(C);
  for (size_t c = 0; c < C; ++c) {
    const size_t n = L.members[c].size();
    q1[c].assign(n * 3, 0.0);
    q2[c].assign(n * 3, 0.0);
    if (n > 0 && F > 1) dcts[c].reset(new BlockDct(n, L.dct_block));
  }
  StepScratch scratch;

  for (size_t f = 0; f < F; ++f) {
    // 1. Frame points.
    decode_seeds(K, S.seed_order, f, hooks, &I0, I1, I2);
    for (size_t j = 0; j < K * 3; ++j) {
      fp[j] = on_grid(I0[j], S.seed);
      (*recon)[3 * (f * P + L.frame_points[j / 3]) + j % 3] = fp[j];
    }
    I2.swap(I1);
    I1 = I0;

    // 2. Clusters.
    for (size_t c = 0; c < C; ++c) {
      const Lcf frame = cluster_frame(L.triangles[c], fp.data());
      const auto& mem = L.members[c];
      const size_t n = mem.size();
      if (n == 0) continue;
      std::vector<double> q(n * 3);
      if (f == 0)
        decode_first_cluster(c, n, frame, S.first, hooks, q.data());
      else
        decode_cluster_step(f, c, n, frame, S, *dcts[c], q1[c], q2[c], hooks, &scratch, q.data());
      for (size_t m = 0; m < n; ++m) to_world(frame, &q[3 * m], &(*recon)[3 * (f * P + mem[m])]);
      q2[c].swap(q1[c]);
      q1[c].swap(q);
    }
  }
}

namespace {

// The frame points of frame f on the grid: their integers I0 (at the points' own slots) from
// their predictions as in decode_seeds and the hooks' residuals, their positions into fp.
void decode_grid_seeds(const Layout& L, size_t f, int seed_order, double g, GridHooks* hooks,
                       std::vector<int64_t>* I0, const std::vector<int64_t>& I1,
                       const std::vector<int64_t>& I2, std::vector<double>* fp) {
  for (size_t k = 0; k < L.frame_points.size(); ++k)
    for (int a = 0; a < 3; ++a) {
      const size_t j = 3 * static_cast<size_t>(L.frame_points[k]) + a;
      int64_t p;
      if (f == 0)
        p = k == 0 ? 0 : (*I0)[3 * static_cast<size_t>(L.frame_points[k - 1]) + a];
      else if (seed_order == 2 && f >= 2)
        p = wrap_add(wrap_add(I1[j], I1[j]), -I2[j]);
      else
        p = I1[j];
      (*I0)[j] = wrap_add(p, hooks->seed_residual(f, k, a, p));
      (*fp)[3 * k + a] = on_grid((*I0)[j], g);
    }
}

// The grid prediction pred of a point of kind `kind` in frame f > 0, i1 and i2 its integers in
// the last two frames, fr0..fr2 its cluster's frames at f, f-1 and f-2: world-linear, or its
// local position (the last, or the line through the last two) in the current frame, or the
// world line plus the frame origin's acceleration.
void predict_grid_point(uint8_t kind, size_t f, const int64_t* i1, const int64_t* i2,
                        const Lcf& fr0, const Lcf& fr1, const Lcf& fr2, double g, int64_t* pred) {
  if (kind == kWorldLinear) {
    for (int a = 0; a < 3; ++a) pred[a] = f >= 2 ? wrap_add(wrap_add(i1[a], i1[a]), -i2[a]) : i1[a];
    return;
  }
  double w1[3], q1[3], q[3], x[3];
  for (int a = 0; a < 3; ++a) w1[a] = on_grid(i1[a], g);
  to_local(fr1, w1, q1);
  if (kind == kClusterAccel && f >= 2) {
    for (int a = 0; a < 3; ++a)
      pred[a] = grid_index((on_grid(wrap_add(wrap_add(i1[a], i1[a]), -i2[a]), g) +
                            (fr0.o[a] - 2.0 * fr1.o[a] + fr2.o[a])) /
                           g);
    return;
  }
  if (kind == kLocal2 && f >= 2) {
    double w2[3], q2[3];
    for (int a = 0; a < 3; ++a) w2[a] = on_grid(i2[a], g);
    to_local(fr2, w2, q2);
    for (int a = 0; a < 3; ++a) q[a] = 2.0 * q1[a] - q2[a];
  } else {
    for (int a = 0; a < 3; ++a) q[a] = q1[a];
  }
  to_world(fr0, q, x);
  for (int a = 0; a < 3; ++a) pred[a] = grid_index(x[a] / g);
}

}  // namespace

void run_grid_loop(const Layout& L, double g, int seed_order, const std::vector<uint8_t>& kind,
                   GridHooks* hooks, std::vector<double>* recon) {
  const size_t F = L.frames, P = L.points, K = L.frame_points.size(), C = L.triangles.size();
  recon->assign(F * P * 3, 0.0);
  if (F == 0 || P == 0) return;
  // Decoded grid integers of the last three frames (current, f-1, f-2), all points.
  std::vector<int64_t> I0(P * 3, 0), I1(P * 3, 0), I2(P * 3, 0);
  std::vector<Lcf> fr0(C), fr1(C), fr2(C);  // cluster frames at f, f-1, f-2
  std::vector<double> fp(K * 3);
  for (size_t f = 0; f < F; ++f) {
    decode_grid_seeds(L, f, seed_order, g, hooks, &I0, I1, I2, &fp);
    for (size_t c = 0; c < C; ++c) {
      fr0[c] = cluster_frame(L.triangles[c], fp.data());
      int64_t prev[3] = {0, 0, 0};
      for (uint32_t i : L.members[c]) {
        int64_t pred[3];
        const size_t j = 3 * static_cast<size_t>(i);
        if (f == 0)
          for (int a = 0; a < 3; ++a) pred[a] = prev[a];
        else
          predict_grid_point(kind[i], f, &I1[j], &I2[j], fr0[c], fr1[c], fr2[c], g, pred);
        for (int a = 0; a < 3; ++a) {
          I0[j + a] = wrap_add(pred[a], hooks->point_residual(f, i, a, kind[i], pred[a]));
          prev[a] = I0[j + a];
        }
      }
    }
    double* out = recon->data() + f * P * 3;
    for (size_t j = 0; j < P * 3; ++j) out[j] = on_grid(I0[j], g);
    I2.swap(I1);
    I1 = I0;
    fr2.swap(fr1);
    fr1 = fr0;
  }
}

}  // namespace pdct
}  // namespace capz
