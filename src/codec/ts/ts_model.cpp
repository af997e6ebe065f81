// The ts payload's reader (docs/CODEC-TS.md) and the reconstruction from a model; the writer is
// ts_model_encode.cpp.
#include "codec/ts/ts_model.h"

#include <Eigen/Core>
#include <algorithm>
#include <cmath>
#include <string>

#include "capz/error.h"
#include "codec/ts/basis_predict.h"
#include "codec/ts/rigid.h"
#include "codec/ts/ts_model_shared.h"
#include "coding/entropy.h"

namespace capz {
namespace ts {

namespace {

using namespace payload;

[[noreturn]] void corrupt(const std::string& what) {
  fail(ErrorCode::kCorrupt, kWhat, what);
}

Eigen::MatrixXd dequantise_basis(const std::vector<QuantisedVector>& basis, size_t dim) {
  Eigen::MatrixXd b(static_cast<Eigen::Index>(dim), static_cast<Eigen::Index>(basis.size()));
  for (size_t j = 0; j < basis.size(); ++j)
    dequantise_vector(basis[j], b.col(static_cast<Eigen::Index>(j)).data());
  return b;
}

class In {
 public:
  In(const uint8_t* data, size_t size) : dec_(data, size, kContexts, kWhat), size_(size) {}
  int64_t get(Group g) {
    int tok;
    const int32_t v = dec_.get_signed(g * 16 + prev_[g], &tok);
    prev_[g] = std::min(tok, 15);
    return v;
  }
  uint32_t get_unsigned(Group g) {
    int tok;
    const uint32_t v = dec_.get(g * 16 + prev_[g], &tok);
    prev_[g] = std::min(tok, 15);
    return v;
  }
  int label(int clusters) {
    const uint32_t v = dec_.get(kLabelCtx + prev_label_);
    if (v >= static_cast<uint32_t>(clusters)) corrupt("cluster index out of range");
    prev_label_ = static_cast<int>(v);
    return prev_label_;
  }
  uint32_t segment_rank(int prev_segment) { return dec_.get(kSegmentCtx + prev_segment); }
  uint32_t raw(int n) { return dec_.raw_bits(n); }
  // Guards an allocation of `n` more values: every value costs more than 1/360 bit.
  void budget(uint64_t n) {
    used_ += n;
    if (used_ > kMaxSymbolsPerByte * static_cast<uint64_t>(size_) + 64)
      corrupt("value counts larger than the payload can hold");
  }
  bool at_end() const { return dec_.at_end(); }

 private:
  IntDecoder dec_;
  size_t size_;
  uint64_t used_ = 0;
  int prev_[kGroups] = {};
  int prev_label_ = 0;
};

void read_lpc_header(ByteReader* in, LpcCode* c, size_t rows, size_t length) {
  c->rows = rows;
  c->length = length;
  c->order = in->u8();
  c->weight_bits = in->u8();
  if (c->order > 8 || c->weight_bits > 30) corrupt("LPC order or weight bits out of range");
}
void read_lpc_body(LpcCode* c, Group g, In* in) {
  const size_t nw = c->has_weights() ? c->rows * static_cast<size_t>(c->order) : 0;
  in->budget(nw + c->rows * c->length);
  c->weights.resize(nw);
  for (auto& w : c->weights) w = static_cast<int32_t>(in->get(kLpcWeight));
  c->values.resize(c->rows * c->length);
  for (auto& v : c->values) v = in->get(g);
}

double read_step(ByteReader* in, const char* name) {
  const double s = in->f64();
  if (!std::isfinite(s) || s <= 0) corrupt(std::string(name) + " is not a positive number");
  return s;
}

}  // namespace

std::vector<ClusterLayout> cluster_layout(const std::vector<uint8_t>& label, int clusters) {
  std::vector<ClusterLayout> out(static_cast<size_t>(std::max(0, clusters)));
  for (size_t f = 0; f < label.size(); ++f) {
    if (label[f] >= clusters)
      corrupt("frame " + std::to_string(f) + " has cluster index " + std::to_string(label[f]));
    out[label[f]].frames.push_back(f);
  }
  for (size_t c = 0; c < out.size(); ++c) {
    auto& l = out[c];
    if (l.frames.empty()) corrupt("cluster " + std::to_string(c) + " has no frames");
    l.first_len = 1;
    while (l.first_len < l.frames.size() && l.frames[l.first_len] == l.frames[l.first_len - 1] + 1)
      ++l.first_len;
  }
  return out;
}

std::vector<std::vector<uint32_t>> segment_members(const std::vector<uint8_t>& label,
                                                   int segments) {
  std::vector<std::vector<uint32_t>> out(static_cast<size_t>(std::max(0, segments)));
  for (size_t i = 0; i < label.size(); ++i) {
    if (label[i] >= segments)
      fail(ErrorCode::kCorrupt, "ts payload",
           "point " + std::to_string(i) + " has segment " + std::to_string(label[i]));
    out[label[i]].push_back(static_cast<uint32_t>(i));
  }
  for (size_t s = 0; s < out.size(); ++s)
    if (out[s].empty())
      fail(ErrorCode::kCorrupt, "ts payload", "segment " + std::to_string(s) + " has no points");
  return out;
}

std::vector<std::vector<uint32_t>> segment_points_of(const TsModel& m) {
  if (m.segments < 1 || m.segments > kMaxSegments) corrupt("segment count out of range");
  if (m.segments == 1 && m.segment.empty()) {
    std::vector<std::vector<uint32_t>> all(1);
    all[0].resize(m.points);
    for (size_t i = 0; i < m.points; ++i) all[0][i] = static_cast<uint32_t>(i);
    return all;
  }
  if (m.segment.size() != m.points) corrupt("segment labels disagree with the points");
  return segment_members(m.segment, m.segments);
}

void reconstruct(const TsModel& m, std::vector<double>* xyz) {
  const size_t dim = 3 * m.points;
  xyz->assign(m.frames * dim, 0.0);
  const auto layout = cluster_layout(m.label, m.clusters);
  const auto members = segment_points_of(m);
  if (m.cluster.size() != layout.size() * members.size())
    corrupt("cluster count disagrees with the labels");
  if (m.segment_rigid && m.segment_motion.size() != members.size()) corrupt("segment motion count");
  for (size_t s = 0; s < members.size(); ++s) {
    const std::vector<uint32_t>& pts = members[s];
    const size_t dim_s = 3 * pts.size();
    Eigen::MatrixXd motion;  // 6 x frames when the segment has its own rigid motion
    if (m.segment_rigid) {
      const TsModel::SegmentMotion& sm = m.segment_motion[s];
      if (sm.code.rows != 6 || sm.code.length != m.frames) corrupt("segment rigid block size");
      motion = lpc_decode(sm.code, {sm.rot_step, sm.rot_step, sm.rot_step, sm.trans_step,
                                    sm.trans_step, sm.trans_step});
    }
    for (size_t c = 0; c < layout.size(); ++c) {
      const TsCluster& tc = m.cluster[s * layout.size() + c];
      const ClusterLayout& lay = layout[c];
      const size_t r = tc.basis.size();
      if (tc.first.rows != r || tc.first.length != lay.first_len ||
          tc.later.size() != lay.frames.size() - lay.first_len)
        corrupt("cluster " + std::to_string(c) + " sizes disagree with its frames");
      for (const QuantisedVector& q : tc.basis)
        if (q.q.size() != dim_s) corrupt("basis length disagrees with the segment");
      const Eigen::MatrixXd b = dequantise_basis(tc.basis, dim_s);
      Eigen::MatrixXd w(static_cast<Eigen::Index>(r), static_cast<Eigen::Index>(lay.frames.size()));
      const Eigen::MatrixXd first = lpc_decode(tc.first, std::vector<double>(r, m.coef_step));
      w.leftCols(static_cast<Eigen::Index>(lay.first_len)) = first;
      for (size_t j = 0; j < tc.later.size(); ++j)
        w.col(static_cast<Eigen::Index>(lay.first_len + j)) =
            lcps_decode(tc.later[j], first, m.coef_step, tc.lcps_weight_bits);
      Eigen::MatrixXd x = b * w;  // dim_s x l_c
      for (size_t j = 0; j < lay.frames.size(); ++j) {
        if (m.segment_rigid) {
          double* col = x.col(static_cast<Eigen::Index>(j)).data();
          apply_rigid_inverse(rigid_at(motion, lay.frames[j]), col, pts.size());
          const double* centre = m.segment_motion[s].center;
          for (size_t i = 0; i < pts.size(); ++i)
            for (size_t a = 0; a < 3; ++a) col[3 * i + a] += centre[a];
        }
        const double* src = x.col(static_cast<Eigen::Index>(j)).data();
        double* dst = xyz->data() + lay.frames[j] * dim;
        for (size_t i = 0; i < pts.size(); ++i)
          for (size_t a = 0; a < 3; ++a) dst[3 * size_t{pts[i]} + a] = src[3 * i + a];
      }
    }
  }
  if (m.rigid) {
    if (m.rigid_code.rows != 6 || m.rigid_code.length != m.frames) corrupt("rigid block size");
    std::vector<double> steps = {m.rot_step,   m.rot_step,   m.rot_step,
                                 m.trans_step, m.trans_step, m.trans_step};
    const Eigen::MatrixXd p = lpc_decode(m.rigid_code, steps);
    for (size_t f = 0; f < m.frames; ++f)
      apply_rigid_inverse(rigid_at(p, f), xyz->data() + f * dim, m.points);
  }
}

RigidParams rigid_at(const Eigen::MatrixXd& decoded, size_t f) {
  RigidParams rp;
  for (int a = 0; a < 3; ++a) {
    rp.rot[a] = decoded(a, static_cast<Eigen::Index>(f));
    rp.trans[a] = decoded(3 + a, static_cast<Eigen::Index>(f));
  }
  return rp;
}

// Reads one unit's header (PC count, LPC header of its first fragment, LCPS weight bits, basis
// bits and scales); the counts are checked against the payload left.
static void read_unit_header(ByteReader* in, size_t dim, size_t frames, bool f32_scales,
                             TsCluster* tc) {
  const uint64_t r = in->varint();
  if (r > std::min<size_t>(dim, frames))
    corrupt("a cluster has more PCs than frames or dimensions");
  if (r > in->remaining() / (f32_scales ? 5 : 9)) corrupt("basis headers larger than the payload");
  read_lpc_header(in, &tc->first, r, 0);
  tc->lcps_weight_bits = in->u8();
  if (tc->lcps_weight_bits > 30) corrupt("LCPS weight bits out of range");
  tc->basis.resize(r);
  for (auto& q : tc->basis) {
    q.bits = in->u8();
    if (q.bits < 2 || q.bits > 30) corrupt("basis bits out of 2..30");
    q.scale = f32_scales ? static_cast<double>(in->f32()) : in->f64();
    if (!std::isfinite(q.scale) || q.scale < 0) corrupt("basis scale is not a finite number >= 0");
  }
}

// Reads unit body values: its quantised basis (np points; c is its cluster, for messages), its
// first fragment's LPC values (l1 frames) and the LCPS frames of the rest (lc - l1 frames).
static void read_unit_body(In* e, bool basis_predict, size_t c, size_t np, size_t lc, size_t l1,
                           TsCluster* tc) {
  const size_t dim_s = 3 * np;
  const size_t r = tc->basis.size();
  if (r > lc || r > dim_s)
    corrupt("cluster " + std::to_string(c) + " has more PCs than frames or segment dimensions");
  e->budget(r * dim_s);
  std::vector<uint32_t> parents;
  for (size_t j = 0; j < r; ++j) {
    QuantisedVector& q = tc->basis[j];
    const int64_t lim = (int64_t{1} << (q.bits - 1)) - 1;
    q.q.resize(dim_s);
    for (size_t i = 0; i < np; ++i)
      for (int a = 0; a < 3; ++a) {
        const int64_t x =
            e->get(kBasis) + (basis_predict ? basis_prediction(q.q.data(), parents, i, a) : 0);
        if (x < -lim || x > lim) corrupt("basis value outside its bit range");
        q.q[3 * i + static_cast<size_t>(a)] = static_cast<int32_t>(x);
      }
    if (j == 0 && basis_predict) parents = spatial_parents(q.q, np);
  }
  tc->first.rows = r;
  tc->first.length = l1;
  read_lpc_body(&tc->first, kLpcValue, e);
  const int ib = index_bits(l1);
  e->budget(lc - l1);
  tc->later.resize(lc - l1);
  for (LcpsFrame& f : tc->later) {
    const uint32_t k = e->get_unsigned(kLcpsCount);
    if (k > l1) corrupt("LCPS uses more references than the first fragment has");
    e->budget(2 * k + r);
    f.index.resize(k);
    for (auto& i : f.index) {
      i = e->raw(ib);
      if (i >= l1) corrupt("LCPS reference index out of range");
    }
    f.weight.resize(k);
    for (auto& w : f.weight) w = static_cast<int32_t>(e->get(kLcpsWeight));
    f.resid.resize(r);
    for (auto& v : f.resid) v = e->get(kLcpsResid);
  }
}

// The segments' motion headers (version 2 with flag 4): each segment's steps, centre and LPC
// header, into m->segment_motion.
static void read_segment_motion_headers(ByteReader* in, size_t frames, TsModel* m) {
  if (static_cast<size_t>(m->segments) * 42 > in->remaining())
    corrupt("segment motion headers larger than the payload");
  m->segment_motion.resize(static_cast<size_t>(m->segments));
  for (TsModel::SegmentMotion& sm : m->segment_motion) {
    sm.rot_step = read_step(in, "segment rotation step");
    sm.trans_step = read_step(in, "segment translation step");
    for (double& c : sm.center) {
      c = in->f64();
      if (!std::isfinite(c)) corrupt("segment centre is not a finite number");
    }
    read_lpc_header(in, &sm.code, 6, frames);
  }
}

// Each frame's cluster label and, with segments, each point's segment (move-to-front ranks), from
// the entropy-coded part.
static void read_labels(In* e, size_t frames, size_t points, TsModel* m) {
  e->budget(frames);
  m->label.assign(frames, 0);
  if (m->clusters > 1)
    for (auto& l : m->label) l = static_cast<uint8_t>(e->label(m->clusters));
  if (m->segments <= 1) return;
  e->budget(points);
  m->segment.resize(points);
  SegmentMtf mtf(m->segments);
  int prev = 0;
  for (auto& sg : m->segment) {
    const uint32_t rank = e->segment_rank(prev);
    if (rank >= mtf.size()) corrupt("segment rank out of range");
    sg = mtf.take(rank);
    prev = sg;
  }
}

TsModel read_model(const uint8_t* data, size_t size, size_t frames, size_t points) {
  ByteReader in(data, size, kWhat);
  TsModel m;
  const uint8_t version = in.u8();
  if (version != kVersionOneSegment && version != kVersionSegments)
    fail(ErrorCode::kUnsupportedVersion, kWhat,
         "version " + std::to_string(version) + " (this build reads 1 and 2)");
  const uint8_t flags = in.u8();
  if (flags > (version == kVersionSegments ? 15 : 3)) corrupt("unknown flags");
  m.rigid = flags & 1;
  m.basis_predict = (flags & 2) != 0;
  m.segment_rigid = (flags & 4) != 0;
  m.f32_scales = (flags & 8) != 0;
  m.frames = in.varint();
  m.points = in.varint();
  if (m.frames != frames || m.points != points)
    corrupt("window shape disagrees with the container");
  const size_t dim = 3 * points;
  m.coef_step = read_step(&in, "coefficient step");
  m.clusters = in.u8();
  if (m.clusters < 1 || static_cast<size_t>(m.clusters) > std::max<size_t>(frames, 1))
    corrupt("cluster count out of range");
  if (m.rigid) {
    m.rot_step = read_step(&in, "rotation step");
    m.trans_step = read_step(&in, "translation step");
    read_lpc_header(&in, &m.rigid_code, 6, frames);
  }
  if (version == kVersionSegments) {
    m.segments = in.u8();
    if (m.segments < 2 || m.segments > kMaxSegments || static_cast<size_t>(m.segments) > points)
      corrupt("segment count out of range");
  }
  if (m.segment_rigid) read_segment_motion_headers(&in, frames, &m);
  const size_t units = static_cast<size_t>(m.clusters) * static_cast<size_t>(m.segments);
  if (units > in.remaining()) corrupt("cluster headers larger than the payload");
  m.cluster.resize(units);
  for (TsCluster& tc : m.cluster) read_unit_header(&in, dim, frames, m.f32_scales, &tc);
  In e(data + in.offset(), in.remaining());
  read_labels(&e, frames, points, &m);
  if (m.rigid) read_lpc_body(&m.rigid_code, kRigid, &e);
  for (TsModel::SegmentMotion& sm : m.segment_motion) read_lpc_body(&sm.code, kRigid, &e);
  if (frames > 0) {
    const auto layout = cluster_layout(m.label, m.clusters);
    const auto members = segment_points_of(m);
    for (size_t u = 0; u < units; ++u) {
      const size_t c = u % layout.size(), np = members[u / layout.size()].size();
      read_unit_body(&e, m.basis_predict, c, np, layout[c].frames.size(), layout[c].first_len,
                     &m.cluster[u]);
    }
  }
  if (!e.at_end()) corrupt("bytes left after the last value");
  return m;
}

}  // namespace ts
}  // namespace capz
