#include "codec/pdct/pdct_encoder.h"

#include <algorithm>
#include <climits>
#include <cmath>
#include <limits>
#include <memory>

#include "capz/error.h"
#include "capz/metrics.h"
#include "codec/pdct/cluster.h"
#include "codec/pdct/dct.h"
#include "codec/pdct/lcf.h"
#include "codec/pdct/pdct_shared.h"
#include "codec/pdct/predict.h"
#include "codec/pdct/seeds.h"
#include "coding/bytes.h"
#include "coding/entropy.h"

namespace capz {
namespace {

using pdct::coef_context;
using pdct::grid_context;
using pdct::kCoefContexts;
using pdct::kFirstContexts;
using pdct::kGridContexts;
using pdct::kSeedContexts;
using pdct::Layout;
using pdct::Lcf;
using pdct::SeedContexts;
using pdct::Steps;

// ---------------------------------------------------------------------------------------------
// Options

double parse_double(const std::string& key, const std::string& v, double lo, double hi) {
  size_t used = 0;
  double d = 0;
  try {
    d = std::stod(v, &used);
  } catch (const std::exception&) {
    used = 0;
  }
  if (used != v.size() || !(d >= lo && d <= hi))
    throw Error(ErrorCode::kInvalidParameter, "pdct option " + key + "=" + v +
                                                  ": expected a number in [" + std::to_string(lo) +
                                                  ", " + std::to_string(hi) + "]");
  return d;
}

int parse_int(const std::string& key, const std::string& v, int lo, int hi) {
  const double d = parse_double(key, v, lo, hi);
  if (d != std::floor(d))
    throw Error(ErrorCode::kInvalidParameter,
                "pdct option " + key + "=" + v + ": expected an integer");
  return static_cast<int>(d);
}

// ---------------------------------------------------------------------------------------------
// Quantisation: every stored integer within 2^29 steps (pdct_shared.h).

constexpr double kMaxQuantised = 536870912.0;  // 2^29

int64_t quantise_checked(double v, double step, const char* what) {
  const double x = v / step;
  if (!(std::fabs(x) < kMaxQuantised))
    throw Error(ErrorCode::kInvalidParameter,
                std::string("pdct: ") + what + " " + std::to_string(v) +
                    " is more than 2^29 steps of " + std::to_string(step) +
                    " (step too small for this take)");
  return std::llround(x);
}

int32_t to_i32(int64_t r) {
  if (r < INT32_MIN || r > INT32_MAX)
    throw Error(ErrorCode::kInvalidParameter,
                "pdct: a residual exceeds 2^31 steps (step too small for this take)");
  return static_cast<int32_t>(r);
}

// ---------------------------------------------------------------------------------------------
// Layout (encoder): seeds, triangles, clusters.

Layout build_layout(const PositionsView& in, size_t clusters, const PdctOptions& o) {
  const size_t F = in.frames, P = in.points;
  Layout L;
  L.frames = F;
  L.points = P;
  L.dct_block = o.dct_block;
  // Seed candidates: points measured in every frame if at least 3, else in frame 0, else all.
  std::vector<uint8_t> always(P, 1), first(P, 0);
  size_t n_always = 0, n_first = 0;
  for (size_t i = 0; i < P; ++i) {
    for (size_t f = 0; f < F && always[i]; ++f) always[i] = in.valid[f * P + i];
    first[i] = in.valid[i];
    n_always += always[i];
    n_first += first[i];
  }
  const uint8_t* cand = n_always >= 3 ? always.data() : n_first >= 3 ? first.data() : nullptr;
  std::vector<pdct::Triangle> tris;
  if (P >= 3 && clusters > 0) {
    const auto seeds = pdct::farthest_point_seeds(in.xyz, P, cand, pdct::SeedParams{clusters});
    pdct::TriangleParams tp;
    tp.knn = o.knn;
    tp.min_angle_deg = o.min_angle_deg;
    tp.min_edge = o.min_edge;
    tris = pdct::seed_triangles(in, seeds, tp);
  }
  std::vector<uint8_t> is_fp(P, 0);
  for (const auto& t : tris) is_fp[t.p1] = is_fp[t.p2] = is_fp[t.p3] = 1;
  std::vector<uint32_t> where(P, 0);
  for (size_t i = 0; i < P; ++i)
    if (is_fp[i]) {
      where[i] = static_cast<uint32_t>(L.frame_points.size());
      L.frame_points.push_back(static_cast<uint32_t>(i));
    }
  std::vector<Lcf> lcfs;
  if (tris.empty()) {
    L.triangles.push_back({0, 0, 0});
    lcfs.assign(F, pdct::identity_lcf());
  } else {
    for (const auto& t : tris) {
      L.triangles.push_back({where[t.p1], where[t.p2], where[t.p3]});
      for (size_t f = 0; f < F; ++f) {
        const double* b = in.xyz + 3 * f * P;
        lcfs.push_back(pdct::make_lcf(b + 3 * t.p1, b + 3 * t.p2, b + 3 * t.p3));
      }
    }
  }
  const auto assign =
      pdct::assign_clusters(in, lcfs, L.triangles.size(), is_fp, pdct::ClusterParams{});
  L.members.assign(L.triangles.size(), {});
  for (size_t i = 0; i < P; ++i)
    if (assign[i] >= 0)
      L.members[static_cast<size_t>(assign[i])].push_back(static_cast<uint32_t>(i));
  return L;
}

// ---------------------------------------------------------------------------------------------
// Encoder hooks: integers from the original.

class EncoderHooks : public pdct::LoopHooks {
 public:
  EncoderHooks(const PositionsView& in, const Layout& L, const Steps& S, double zero_share)
      : in_(in), L_(L), S_(S), zero_share_(zero_share), sc_(L.frame_points.size()) {}

  int64_t seed_residual(size_t f, size_t k, int a, int64_t prediction) override {
    const double v = in_.xyz[3 * (f * in_.points + L_.frame_points[k]) + a];
    const int32_t r = to_i32(quantise_checked(v, S_.seed, "frame-point coordinate") - prediction);
    sc_.update(k, a, seed.put_signed(r, sc_.context(k, a)));
    return r;
  }

  int64_t first_residual(size_t c, size_t m, int a, const Lcf& frame, int64_t prediction) override {
    if (a == 0) pdct::to_local(frame, in_.xyz + 3 * L_.members[c][m], q_);
    const int32_t r =
        to_i32(quantise_checked(q_[a], S_.first, "frame-0 local coordinate") - prediction);
    first.put_signed(r, a);
    return r;
  }

  void coefficients(size_t f, size_t c, const Lcf& frame, const double* pred,
                    const pdct::BlockDct& dct, int64_t* coefs) override {
    const auto& mem = L_.members[c];
    const size_t n = mem.size();
    delta_.assign(3 * n, 0.0);
    for (size_t m = 0; m < n; ++m) {
      const size_t s = f * in_.points + mem[m];
      if (!in_.valid[s]) continue;  // a gap rides with its cluster's frame: delta 0
      double q[3];
      pdct::to_local(frame, in_.xyz + 3 * s, q);
      for (int a = 0; a < 3; ++a) delta_[a * n + m] = q[a] - pred[3 * m + a];
    }
    X_.resize(n);
    for (int a = 0; a < 3; ++a) {
      dct.forward(&delta_[a * n], X_.data());
      for (size_t b = 0; b < dct.blocks(); ++b) {
        const size_t o = dct.block_begin(b);
        const size_t len = dct.block_size(b);
        for (size_t l = 0; l < len; ++l)
          if (!(std::fabs(X_[o + l] / S_.coef) < kMaxQuantised))
            quantise_checked(X_[o + l], S_.coef, "DCT coefficient");  // throws
        pdct::zero_and_quantise(&X_[o], len, pdct::CoefQuantParams{S_.coef, zero_share_},
                                coefs + a * n + o);
        int prev = 0;
        for (size_t l = 0; l < len; ++l)
          prev = coef.put_signed(static_cast<int32_t>(coefs[a * n + o + l]), coef_context(l, prev));
      }
    }
  }

  IntEncoder seed{kSeedContexts}, first{kFirstContexts}, coef{kCoefContexts};

 private:
  const PositionsView& in_;
  const Layout& L_;
  const Steps& S_;
  double zero_share_;
  SeedContexts sc_;
  double q_[3] = {0, 0, 0};
  std::vector<double> delta_, X_;
};

// ---------------------------------------------------------------------------------------------
// Grid mode (predict.h): hooks and encoder.

// Rough cost in bits of a residual, for choosing predictors (not the coder's exact cost).
double residual_bits(int64_t r) {
  return r == 0 ? 0.3 : 2.0 + 2.0 * std::log2(1.0 + std::fabs(static_cast<double>(r)));
}

class GridEncoderHooks : public pdct::GridHooks {
 public:
  GridEncoderHooks(const PositionsView& in, const Layout& L, double grid, bool code)
      : in_(in),
        L_(L),
        g_(grid),
        code_(code),
        sc_(L.frame_points.size()),
        last_(in.points * 3, 0),
        cost(in.points, 0.0) {}

  int64_t seed_residual(size_t f, size_t k, int a, int64_t prediction) override {
    const double v = in_.xyz[3 * (f * in_.points + L_.frame_points[k]) + a];
    const int32_t r = to_i32(quantise_checked(v, g_, "frame-point coordinate") - prediction);
    if (code_) sc_.update(k, a, seed.put_signed(r, sc_.context(k, a)));
    return r;
  }
  int64_t point_residual(size_t f, uint32_t i, int a, int kind, int64_t prediction) override {
    const size_t s = f * in_.points + i;
    int32_t r = 0;
    if (in_.valid[s] || f == 0)  // frame 0 codes filled values too: later frames predict from them
      r = to_i32(quantise_checked(in_.xyz[3 * s + a], g_, "coordinate") - prediction);
    if (f >= 1 && in_.valid[s]) cost[i] += residual_bits(r);
    if (!code_) return r;
    if (f == 0) {
      first.put_signed(r, a);
    } else {
      uint8_t& last = last_[3 * static_cast<size_t>(i) + a];
      prev_tok_ = resid.put_signed(r, grid_context(kind, a, prev_tok_, last));
      last = static_cast<uint8_t>(prev_tok_);
    }
    return r;
  }

  IntEncoder seed{kSeedContexts}, first{kFirstContexts}, resid{kGridContexts};

 private:
  const PositionsView& in_;
  const Layout& L_;
  double g_;
  bool code_;
  SeedContexts sc_;
  int prev_tok_ = 0;
  std::vector<uint8_t> last_;  // per point and axis: token of the previous frame's residual

 public:
  std::vector<double>
      cost;  // per point: estimated bits of its residuals (f >= 1, measured samples)
};

// ---------------------------------------------------------------------------------------------
// Serialisation

// Header and layout (docs/CODEC-PDCT.md), then the given blocks (each varint length + bytes).
void write_payload(const Layout& L, const Steps& S, bool grid, const std::vector<uint8_t>* kinds,
                   const std::vector<std::vector<uint8_t>>& blocks, std::vector<uint8_t>* out,
                   PdctReport* rep) {
  ByteWriter w;
  w.u8(pdct::kVersion);
  w.u8(static_cast<uint8_t>((S.seed_order == 2 ? pdct::kFlagSeedOrder2 : 0) |
                            (S.local_order == 2 ? pdct::kFlagLocalOrder2 : 0) |
                            (grid ? pdct::kFlagGrid : 0)));
  w.f64(S.seed);
  w.f64(S.first);
  w.f64(S.coef);
  w.varint(L.dct_block);
  w.varint(L.frame_points.size());
  uint32_t prev = 0;
  for (size_t k = 0; k < L.frame_points.size(); ++k) {
    w.varint(k == 0 ? L.frame_points[0] : L.frame_points[k] - prev - 1);
    prev = L.frame_points[k];
  }
  w.varint(L.triangles.size());
  for (const auto& t : L.triangles)
    for (uint32_t v : t) w.varint(v);
  // Cluster (and in grid mode predictor kind) of every non-frame point, in ascending point order.
  std::vector<uint32_t> cl(L.points, 0);
  for (size_t c = 0; c < L.members.size(); ++c)
    for (uint32_t p : L.members[c]) cl[p] = static_cast<uint32_t>(c);
  std::vector<uint8_t> is_fp(L.points, 0);
  for (uint32_t p : L.frame_points) is_fp[p] = 1;
  std::vector<uint32_t> ids, ks;
  for (size_t i = 0; i < L.points; ++i)
    if (!is_fp[i]) {
      ids.push_back(cl[i]);
      if (kinds) ks.push_back((*kinds)[i]);
    }
  put_block(&w, encode_uints(ids));
  if (grid) put_block(&w, encode_uints(ks));
  const size_t layout_bytes = w.size();
  std::vector<size_t> sizes;
  for (const auto& b : blocks) {
    const size_t before = w.size();
    put_block(&w, b);
    sizes.push_back(w.size() - before);
  }
  if (rep) {
    rep->layout_bytes = layout_bytes;
    rep->seed_bytes = sizes.size() > 0 ? sizes[0] : 0;
    rep->first_bytes = sizes.size() > 1 ? sizes[1] : 0;
    rep->coef_bytes = sizes.size() > 2 ? sizes[2] : 0;
    rep->payload_bytes = w.size();
  }
  out->insert(out->end(), w.buffer().begin(), w.buffer().end());
}

// ---------------------------------------------------------------------------------------------
// Encoder driver

struct Trial {
  std::vector<uint8_t> bytes;
  std::vector<double> recon;
  PdctReport report;
};

Trial run_encode(const PositionsView& in, const Layout& L, const Steps& S, double zero_share) {
  Trial t;
  EncoderHooks h(in, L, S, zero_share);
  pdct::run_closed_loop(L, S, &h, &t.recon);
  write_payload(L, S, false, nullptr, {h.seed.finish(), h.first.finish(), h.coef.finish()},
                &t.bytes, &t.report);
  t.report.clusters = L.triangles.size();
  t.report.frame_points = L.frame_points.size();
  t.report.seed_step = S.seed;
  t.report.first_step = S.first;
  t.report.coef_step = S.coef;
  return t;
}

// Grid mode: each point's predictor is the kind with the lowest estimated residual cost over the
// window (one trial pass per kind; frame 0 and gaps do not count), then the coding pass.
Trial run_grid_encode(const PositionsView& in, const Layout& L, double grid) {
  std::vector<std::vector<double>> costs;
  for (int k = 0; k < pdct::kPointPredictors; ++k) {
    std::vector<uint8_t> kinds(in.points, static_cast<uint8_t>(k));
    GridEncoderHooks h(in, L, grid, false);
    std::vector<double> rec;
    pdct::run_grid_loop(L, grid, 2, kinds, &h, &rec);
    costs.push_back(h.cost);
  }
  std::vector<uint8_t> kinds(in.points, pdct::kLocal1);
  for (size_t i = 0; i < in.points; ++i)
    for (int k = 0; k < pdct::kPointPredictors; ++k)
      if (costs[static_cast<size_t>(k)][i] < costs[kinds[i]][i]) kinds[i] = static_cast<uint8_t>(k);
  Trial t;
  GridEncoderHooks h(in, L, grid, true);
  pdct::run_grid_loop(L, grid, 2, kinds, &h, &t.recon);
  Steps S;
  S.seed = S.first = S.coef = grid;
  S.seed_order = 2;
  write_payload(L, S, true, &kinds, {h.seed.finish(), h.first.finish(), h.resid.finish()}, &t.bytes,
                &t.report);
  t.report.clusters = L.triangles.size();
  t.report.frame_points = L.frame_points.size();
  t.report.seed_step = t.report.first_step = t.report.coef_step = grid;
  t.report.grid_mode = true;
  std::vector<uint8_t> is_fp(in.points, 0);
  for (uint32_t p : L.frame_points) is_fp[p] = 1;
  for (size_t i = 0; i < in.points; ++i)
    if (!is_fp[i]) ++t.report.predictors[kinds[i]];
  return t;
}

// Largest |DCT coefficient| of an open-loop pass (deltas between the original local coordinates
// of consecutive frames, frames built on the original triangles): the range coef_bits spans.
double open_loop_max_coefficient(const PositionsView& in, const Layout& L) {
  const size_t F = in.frames, P = in.points;
  double M = 0;
  std::vector<double> d, X;
  for (size_t c = 0; c < L.triangles.size(); ++c) {
    const auto& mem = L.members[c];
    const size_t n = mem.size();
    if (n == 0 || F < 2) continue;
    const pdct::BlockDct dct(n, L.dct_block);
    const auto& t = L.triangles[c];
    auto frame_at = [&](size_t f) {
      if (t[0] == t[1] && t[1] == t[2]) return pdct::identity_lcf();
      const double* b = in.xyz + 3 * f * P;
      return pdct::make_lcf(b + 3 * L.frame_points[t[0]], b + 3 * L.frame_points[t[1]],
                            b + 3 * L.frame_points[t[2]]);
    };
    Lcf prev = frame_at(0);
    d.resize(3 * n);
    X.resize(n);
    for (size_t f = 1; f < F; ++f) {
      const Lcf cur = frame_at(f);
      for (size_t m = 0; m < n; ++m) {
        double q0[3], q1[3];
        pdct::to_local(prev, in.xyz + 3 * ((f - 1) * P + mem[m]), q0);
        pdct::to_local(cur, in.xyz + 3 * (f * P + mem[m]), q1);
        for (int a = 0; a < 3; ++a) d[a * n + m] = q1[a] - q0[a];
      }
      for (int a = 0; a < 3; ++a) {
        dct.forward(&d[a * n], X.data());
        for (double x : X) M = std::max(M, std::fabs(x));
      }
      prev = cur;
    }
  }
  return M;
}

// Rough bits the bound layer would spend on the residual left by `recon` (for --clusters auto).
double bound_bits_estimate(const PositionsView& in, const std::vector<double>& recon,
                           double max_error) {
  double bits = 0;
  const double grid = 2 * max_error;
  for (size_t s = 0; s < in.frames * in.points; ++s) {
    if (!in.valid[s]) continue;
    for (int a = 0; a < 3; ++a) {
      const double r = std::fabs(std::round((in.xyz[3 * s + a] - recon[3 * s + a]) / grid));
      bits += r == 0 ? 0.05 : 2.0 + 2.0 * std::log2(r + 1);
    }
  }
  return bits;
}

double max_abs_coordinate(const PositionsView& in) {
  double m = 0;
  for (size_t i = 0; i < in.frames * in.points * 3; ++i) {
    const double v = in.xyz[i];
    if (!std::isfinite(v))
      throw Error(ErrorCode::kInvalidParameter,
                  "pdct: position " + std::to_string(i / 3) +
                      " is not finite (gaps must be filled before coding)");
    m = std::max(m, std::fabs(v));
  }
  return m;
}

// KG target without a max error: scale the frame-0 and coefficient steps by 2^e, e found by a
// guess (KG is close to proportional to the step) then bisection, to the largest scale whose KG
// error is at or below the target (to 2^(1/32)). An unreachable target (e.g. too many zeroed
// coefficients) gives the lowest KG error seen.
// best is the trial at the unscaled steps S (on layout).
Trial kg_search(const PositionsView& in, const Layout& layout, const Steps& S, double min_step,
                double zero_share, double target, const Trial& best) {
  struct Point {
    double e, kg;
    Trial t;
  };
  auto at = [&](double e) {
    Steps s = S;
    s.first = std::max(S.first * std::exp2(e), min_step);
    s.coef = std::max(S.coef * std::exp2(e), min_step);
    Point p{e, 0, run_encode(in, layout, s, zero_share)};
    p.kg = compare(in.frames, in.points, in.xyz, p.t.recon.data(), in.valid).kg_error;
    return p;
  };
  const double kg0 = compare(in.frames, in.points, in.xyz, best.recon.data(), in.valid).kg_error;
  Point cur =
      kg0 > 0 ? at(std::min(8.0, std::max(-16.0, std::log2(target / kg0)))) : Point{0, 0, best};
  Point ok{0, 0, {}}, bad{0, 0, {}};
  bool have_ok = false, have_bad = false;
  // For an unreachable target: the lowest KG seen, preferring a smaller payload within 2%.
  Point lowest = cur;
  for (int it = 0; it < 8; ++it) {
    if (cur.kg < 0.98 * lowest.kg ||
        (cur.kg <= 1.02 * lowest.kg && cur.t.bytes.size() < lowest.t.bytes.size()))
      lowest = cur;
    if (cur.kg <= target) {
      ok = cur;
      have_ok = true;
      if (have_bad || cur.e >= 8) break;
      cur = at(cur.e + 1);
    } else {
      bad = cur;
      have_bad = true;
      if (have_ok || cur.e <= -16) break;
      cur = at(cur.e - 1);
    }
  }
  if (have_ok && have_bad) {
    for (int it = 0; it < 5; ++it) {
      Point mid = at(0.5 * (ok.e + bad.e));
      if (mid.kg <= target)
        ok = std::move(mid);
      else
        bad = std::move(mid);
    }
  }
  return have_ok ? std::move(ok.t) : std::move(lowest.t);
}

}  // namespace

// ---------------------------------------------------------------------------------------------

PdctOptions parse_pdct_options(const TransformParams& params) {
  PdctOptions o;
  for (const auto& kv : params.options) {
    const std::string& k = kv.first;
    const std::string& v = kv.second;
    if (k == "mode") {
      if (v != "auto" && v != "grid" && v != "dct")
        throw Error(ErrorCode::kInvalidParameter,
                    "pdct option mode=" + v + ": expected auto, grid or dct");
      o.mode = v;
    } else if (k == "zero_share")
      o.zero_share = parse_double(k, v, 0, 0.999);
    else if (k == "coef_bits")
      o.coef_bits = parse_int(k, v, 2, 24);
    else if (k == "first_bits")
      o.first_bits = parse_int(k, v, 2, 24);
    else if (k == "seed_bits")
      o.seed_bits = parse_int(k, v, 2, 30);
    else if (k == "coef_factor")
      o.coef_factor = parse_double(k, v, 1e-3, 1e3);
    else if (k == "first_factor")
      o.first_factor = parse_double(k, v, 1e-3, 1e3);
    else if (k == "seed_factor")
      o.seed_factor = parse_double(k, v, 1e-3, 1e3);
    else if (k == "seed_order")
      o.seed_order = parse_int(k, v, 1, 2);
    else if (k == "local_order")
      o.local_order = parse_int(k, v, 1, 2);
    else if (k == "dct_block")
      o.dct_block = static_cast<size_t>(parse_int(k, v, 1, static_cast<int>(pdct::kMaxDctBlock)));
    else if (k == "knn")
      o.knn = parse_int(k, v, 2, 64);
    else if (k == "min_angle_deg")
      o.min_angle_deg = parse_double(k, v, 0, 59);
    else if (k == "min_edge")
      o.min_edge = parse_double(k, v, 0, 0.5);
    else
      throw Error(ErrorCode::kInvalidParameter,
                  "pdct: unknown option '" + k +
                      "' (known: mode zero_share coef_bits first_bits seed_bits "
                      "coef_factor first_factor seed_factor seed_order local_order dct_block knn "
                      "min_angle_deg min_edge)");
  }
  return o;
}

size_t pdct_default_clusters(size_t points) {
  return std::min<size_t>(40, std::max<size_t>(1, points / 8));
}

namespace {

// The steps before any search: seed and first steps (and the coefficients' when bounded) from
// the max error, else from the diagonal; none below min_step.
Steps initial_steps(const TransformParams& params, const PdctOptions& o, double diag,
                    double min_step) {
  Steps S;
  S.seed_order = o.seed_order;
  S.local_order = o.local_order;
  if (params.max_error > 0) {
    S.seed = o.seed_factor * 2 * params.max_error;
    S.first = o.first_factor * 2 * params.max_error;
    S.coef = o.coef_factor * 2 * params.max_error;
  } else {
    S.seed = std::ldexp(diag, -o.seed_bits);
    S.first = std::ldexp(diag, -o.first_bits);
  }
  S.seed = std::max(S.seed, min_step);
  S.first = std::max(S.first, min_step);
  return S;
}

// Candidate cluster counts: the one asked for, the default, or (auto) a ladder of counts with at
// least 3 points a cluster.
std::vector<size_t> candidate_counts(const TransformParams& params, size_t points) {
  std::vector<size_t> counts;
  if (params.clusters > 0) {
    counts.push_back(static_cast<size_t>(params.clusters));
  } else if (params.clusters == 0) {
    counts.push_back(pdct_default_clusters(points));
  } else {
    for (size_t n : {2, 4, 6, 8, 12, 16, 24, 32, 40, 56, 80})
      if (n == 2 || 3 * n <= points) counts.push_back(n);
  }
  return counts;
}

// mode=grid: the trial with the fewest bytes over the cluster counts.
Trial best_grid_trial(const PositionsView& in, const TransformParams& params, const PdctOptions& o,
                      const std::vector<size_t>& counts, double min_step) {
  const double grid =
      params.grid_step > 0 ? params.grid_step : 2.0 * params.max_error * (1.0 - 0x1p-30);
  if (!(grid >= min_step) || !std::isfinite(grid))
    throw Error(ErrorCode::kInvalidParameter,
                "pdct: grid step " + std::to_string(grid) + " too fine for this take");
  Trial best;
  bool have = false;
  for (size_t n : counts) {
    Trial t = run_grid_encode(in, build_layout(in, n, o), grid);
    if (!have || t.bytes.size() < best.bytes.size()) best = std::move(t);
    have = true;
  }
  return best;
}

// mode=dct: the trial of least cost (its bits, plus the bound layer's estimate when bounded) over
// the cluster counts; sets *best_layout to its layout and S->coef to its coefficients' step.
Trial best_dct_trial(const PositionsView& in, const TransformParams& params, const PdctOptions& o,
                     const std::vector<size_t>& counts, double min_step, Steps* S,
                     Layout* best_layout) {
  const bool bounded = params.max_error > 0;
  auto coef_step_for = [&](const Layout& L) {
    if (bounded) return std::max(S->coef, min_step);
    const double M = open_loop_max_coefficient(in, L);
    return std::max(M > 0 ? std::ldexp(2 * M, -o.coef_bits) : S->first, min_step);
  };
  Trial best;
  double best_cost = std::numeric_limits<double>::infinity();
  for (size_t n : counts) {
    Layout L = build_layout(in, n, o);
    Steps s = *S;
    s.coef = coef_step_for(
        counts.size() == 1 ? L : build_layout(in, pdct_default_clusters(in.points), o));
    Trial t = run_encode(in, L, s, o.zero_share);
    double cost = 8.0 * static_cast<double>(t.bytes.size());
    if (bounded) cost += bound_bits_estimate(in, t.recon, params.max_error);
    if (cost < best_cost) {
      best_cost = cost;
      best = std::move(t);
      *best_layout = std::move(L);
      S->coef = s.coef;
    }
  }
  return best;
}

}  // namespace

void encode_pdct(const PositionsView& in, const TransformParams& params, std::vector<uint8_t>* out,
                 std::vector<double>* recon, PdctReport* report) {
  const PdctOptions o = parse_pdct_options(params);
  if (params.max_error < 0 || params.kg_error < 0 || !std::isfinite(params.max_error) ||
      !std::isfinite(params.kg_error))
    throw Error(ErrorCode::kInvalidParameter, "pdct: error targets must be finite and >= 0");
  const double maxabs = max_abs_coordinate(in);
  double diag = pdct::first_frame_diagonal(in);
  if (!(diag > 0)) diag = maxabs > 0 ? maxabs : 1.0;
  // No step below 2^-26 of the take's extent, so positions (|local| <= 2 extent) stay well inside
  // the 2^29 steps a stored integer may hold.
  const double min_step = std::max(maxabs, diag) * std::ldexp(1.0, -26);
  Steps S = initial_steps(params, o, diag, min_step);
  const std::vector<size_t> counts = candidate_counts(params, in.points);

  const bool bounded = params.max_error > 0;
  const bool grid_mode = o.mode == "grid" || (o.mode == "auto" && bounded);
  if (grid_mode && !bounded)
    throw Error(ErrorCode::kInvalidParameter,
                "pdct: mode=grid needs a max error (the bound layer's grid)");
  Trial best;
  if (grid_mode) {
    best = best_grid_trial(in, params, o, counts, min_step);
  } else {
    Layout best_layout;
    best = best_dct_trial(in, params, o, counts, min_step, &S, &best_layout);
    // KG target without a max error: scale the steps to meet it (kg_search).
    if (!bounded && params.kg_error > 0)
      best = kg_search(in, best_layout, S, min_step, o.zero_share, params.kg_error, best);
  }
  out->insert(out->end(), best.bytes.begin(), best.bytes.end());
  *recon = std::move(best.recon);
  if (report) *report = best.report;
}

void PdctCodec::encode(const PositionsView& in, const TransformParams& params,
                       std::vector<uint8_t>* out, std::vector<double>* recon) const {
  encode_pdct(in, params, out, recon, nullptr);
}

}  // namespace capz
