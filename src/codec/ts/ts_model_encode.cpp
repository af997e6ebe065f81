// The ts payload's writer (docs/CODEC-TS.md): write_model, what read_model (ts_model.cpp) reads.
#include <algorithm>
#include <string>

#include "capz/error.h"
#include "codec/ts/basis_predict.h"
#include "codec/ts/ts_model.h"
#include "codec/ts/ts_model_shared.h"
#include "coding/bytes.h"
#include "coding/entropy.h"

namespace capz {
namespace ts {

namespace {

using namespace payload;

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

void write_lpc_header(const LpcCode& c, ByteWriter* out) {
  out->u8(static_cast<uint8_t>(c.order));
  out->u8(static_cast<uint8_t>(c.weight_bits));
}
void write_lpc_body(const LpcCode& c, Group g, Out* out) {
  for (int32_t w : c.weights) out->put(w, kLpcWeight);
  for (int64_t v : c.values) out->put(v, g);
}

// One unit's header (PC count, LPC header of its first fragment, LCPS weight bits, basis bits
// and scales): what read_unit_header reads.
void write_unit_header(const TsCluster& c, bool f32_scales, ByteWriter* out) {
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
void write_unit_body(const TsCluster& tc, bool basis_predict, size_t np, size_t first_len, Out* e) {
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

}  // namespace

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

}  // namespace ts
}  // namespace capz
