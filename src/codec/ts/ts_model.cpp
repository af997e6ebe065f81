// Decoder library (capz_decode): builds without PCL and without the transform encoders.
#include "codec/ts/ts_model.h"

#include <Eigen/Core>
#include <algorithm>
#include <cmath>
#include <string>

#include "capz/error.h"
#include "codec/ts/basis_predict.h"
#include "codec/ts/rigid.h"
#include "coding/entropy.h"

namespace capz {
namespace ts {

namespace {

const char* kWhat = "ts payload";
constexpr uint8_t kVersionOneSegment = 1;  // the paper's model
constexpr uint8_t kVersionSegments = 2;    // point segments (docs/CODEC-TS.md)

[[noreturn]] void corrupt(const std::string& what) {
  fail(ErrorCode::kCorrupt, kWhat, what);
}

Eigen::MatrixXd dequantise_basis(const std::vector<QuantisedVector>& basis, size_t dim) {
  Eigen::MatrixXd b(static_cast<Eigen::Index>(dim), static_cast<Eigen::Index>(basis.size()));
  for (size_t j = 0; j < basis.size(); ++j)
    dequantise_vector(basis[j], b.col(static_cast<Eigen::Index>(j)).data());
  return b;
}

// The entropy-coded part: one IntEncoder block; each kind of value has its own group of 16
// contexts chosen by the previous token of that group, labels use context 128 + previous label,
// segment labels 384 + the previous point's segment.
enum Group {
  kLabels = 0,
  kRigid,
  kBasis,
  kLpcWeight,
  kLpcValue,
  kLcpsCount,
  kLcpsWeight,
  kLcpsResid,
  kGroups
};
constexpr int kLabelCtx = kGroups * 16;
constexpr int kSegmentCtx = kLabelCtx + 256;
constexpr int kContexts = kSegmentCtx + kMaxSegments;

// Move-to-front list of segment indices (segment labels are coded as their rank in it).
class SegmentMtf {
 public:
  explicit SegmentMtf(int segments) {
    for (int s = 0; s < segments; ++s) list_.push_back(static_cast<uint8_t>(s));
  }
  uint32_t rank_of(uint8_t seg) const {
    return static_cast<uint32_t>(std::find(list_.begin(), list_.end(), seg) - list_.begin());
  }
  // The segment at `rank` (< size), moved to the front.
  uint8_t take(uint32_t rank) {
    const uint8_t seg = list_[rank];
    list_.erase(list_.begin() + rank);
    list_.insert(list_.begin(), seg);
    return seg;
  }
  size_t size() const { return list_.size(); }

 private:
  std::vector<uint8_t> list_;
};

class Out {
 public:
  Out() : enc_(kContexts) {}
  void put(int64_t v, Group g) {
    if (v < INT32_MIN || v > INT32_MAX) fail(ErrorCode::kInternal, kWhat, "value outside int32");
    prev_[g] = std::min(enc_.put_signed(static_cast<int32_t>(v), g * 16 + prev_[g]), 15);
  }
  void put_unsigned(uint32_t v, Group g) {
    prev_[g] = std::min(enc_.put(v, g * 16 + prev_[g]), 15);
  }
  void label(int v) {
    enc_.put(static_cast<uint32_t>(v), kLabelCtx + prev_label_);
    prev_label_ = v;
  }
  void segment_rank(uint32_t rank, int prev_segment) { enc_.put(rank, kSegmentCtx + prev_segment); }
  void raw(uint32_t v, int n) { enc_.raw_bits(v, n); }
  std::vector<uint8_t> finish() { return enc_.finish(); }

 private:
  IntEncoder enc_;
  int prev_[kGroups] = {};
  int prev_label_ = 0;
};

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

int index_bits(size_t l1) {  // ceil(log2 l1)
  int b = 0;
  while ((size_t{1} << b) < l1) ++b;
  return b;
}

void write_lpc_header(const LpcCode& c, ByteWriter* out) {
  out->u8(static_cast<uint8_t>(c.order));
  out->u8(static_cast<uint8_t>(c.weight_bits));
}
void read_lpc_header(ByteReader* in, LpcCode* c, size_t rows, size_t length) {
  c->rows = rows;
  c->length = length;
  c->order = in->u8();
  c->weight_bits = in->u8();
  if (c->order > 8 || c->weight_bits > 30) corrupt("LPC order or weight bits out of range");
}
void write_lpc_body(const LpcCode& c, Group g, Out* out) {
  for (int32_t w : c.weights) out->put(w, kLpcWeight);
  for (int64_t v : c.values) out->put(v, g);
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

// One unit's header (PC count, LPC header of its first fragment, LCPS weight bits, basis bits
// and scales): what read_unit_header reads.
static void write_unit_header(const TsCluster& c, bool f32_scales, ByteWriter* out) {
  out->varint(c.basis.size());
  write_lpc_header(c.first, out);
  out->u8(static_cast<uint8_t>(c.lcps_weight_bits));
  for (const QuantisedVector& q : c.basis) {
    out->u8(static_cast<uint8_t>(q.bits));
    if (f32_scales) {
      if (static_cast<double>(static_cast<float>(q.scale)) != q.scale)
        fail(ErrorCode::kInternal, kWhat, "basis scale is not a float32 value");
      out->f32(static_cast<float>(q.scale));
    } else {
      out->f64(q.scale);
    }
  }
}

// One unit's body values (np points, a first fragment of first_len frames): what read_unit_body
// reads.
static void write_unit_body(const TsCluster& tc, bool basis_predict, size_t np, size_t first_len,
                            Out* e) {
  std::vector<uint32_t> parents;
  for (size_t j = 0; j < tc.basis.size(); ++j) {
    const QuantisedVector& q = tc.basis[j];
    for (size_t i = 0; i < np; ++i)
      for (int a = 0; a < 3; ++a)
        e->put(q.q[3 * i + static_cast<size_t>(a)] -
                   (basis_predict ? basis_prediction(q.q.data(), parents, i, a) : 0),
               kBasis);
    if (j == 0 && basis_predict) parents = spatial_parents(q.q, np);
  }
  write_lpc_body(tc.first, kLpcValue, e);
  const int ib = index_bits(first_len);
  for (const LcpsFrame& f : tc.later) {
    e->put_unsigned(static_cast<uint32_t>(f.index.size()), kLcpsCount);
    for (uint32_t i : f.index) e->raw(i, ib);
    for (int32_t w : f.weight) e->put(w, kLcpsWeight);
    for (int64_t v : f.resid) e->put(v, kLcpsResid);
  }
}

void write_model(const TsModel& m, ByteWriter* out) {
  const bool segmented = m.segments > 1;
  out->u8(segmented ? kVersionSegments : kVersionOneSegment);
  if (m.segment_rigid && !segmented)
    fail(ErrorCode::kInternal, kWhat, "segment motion without segments");
  if (m.f32_scales && !segmented)
    fail(ErrorCode::kInternal, kWhat, "float32 scales without segments");
  out->u8(static_cast<uint8_t>((m.rigid ? 1 : 0) | (m.basis_predict ? 2 : 0) |
                               (m.segment_rigid ? 4 : 0) | (m.f32_scales ? 8 : 0)));
  out->varint(m.frames);
  out->varint(m.points);
  out->f64(m.coef_step);
  out->u8(static_cast<uint8_t>(m.clusters));
  if (m.rigid) {
    out->f64(m.rot_step);
    out->f64(m.trans_step);
    write_lpc_header(m.rigid_code, out);
  }
  if (segmented) out->u8(static_cast<uint8_t>(m.segments));
  if (m.segment_rigid)
    for (const TsModel::SegmentMotion& sm : m.segment_motion) {
      out->f64(sm.rot_step);
      out->f64(sm.trans_step);
      for (double c : sm.center) out->f64(c);
      write_lpc_header(sm.code, out);
    }
  for (const TsCluster& c : m.cluster) write_unit_header(c, m.f32_scales, out);
  Out e;
  if (m.clusters > 1)
    for (uint8_t l : m.label) e.label(l);
  if (segmented) {
    if (m.segment.size() != m.points)
      fail(ErrorCode::kInternal, kWhat, "segment labels disagree with the points");
    SegmentMtf mtf(m.segments);
    int prev = 0;
    for (uint8_t sg : m.segment) {
      const uint32_t rank = mtf.rank_of(sg);
      if (rank >= mtf.size()) fail(ErrorCode::kInternal, kWhat, "segment label out of range");
      e.segment_rank(rank, prev);
      mtf.take(rank);
      prev = sg;
    }
  }
  if (m.rigid) write_lpc_body(m.rigid_code, kRigid, &e);
  if (m.segment_rigid)
    for (const TsModel::SegmentMotion& sm : m.segment_motion) write_lpc_body(sm.code, kRigid, &e);
  if (!m.frames) {
    out->bytes(e.finish());
    return;
  }
  const auto layout = cluster_layout(m.label, m.clusters);
  const auto members = segment_points_of(m);
  for (size_t u = 0; u < m.cluster.size(); ++u) {
    const size_t c = u % layout.size(), np = members[u / layout.size()].size();
    write_unit_body(m.cluster[u], m.basis_predict, np, layout[c].first_len, &e);
  }
  out->bytes(e.finish());
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
