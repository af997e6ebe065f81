#include "codec/ts/ts_model.h"

#include <Eigen/Core>
#include <cmath>
#include <string>

#include "capz/error.h"
#include "codec/ts/rigid.h"

namespace capz {
namespace ts {

namespace {

const char* kWhat = "ts payload";
constexpr uint8_t kVersion = 1;

[[noreturn]] void corrupt(const std::string& what) { fail(ErrorCode::kCorrupt, kWhat, what); }

Eigen::MatrixXd dequantise_basis(const std::vector<QuantisedVector>& basis, size_t dim) {
  Eigen::MatrixXd b(static_cast<Eigen::Index>(dim), static_cast<Eigen::Index>(basis.size()));
  for (size_t j = 0; j < basis.size(); ++j) dequantise_vector(basis[j], b.col(static_cast<Eigen::Index>(j)).data());
  return b;
}

void write_lpc(const LpcCode& c, ByteWriter* out) {
  out->u8(static_cast<uint8_t>(c.order));
  out->u8(static_cast<uint8_t>(c.weight_bits));
  for (int32_t w : c.weights) out->svarint(w);
  for (int64_t v : c.values) out->svarint(v);
}

LpcCode read_lpc(ByteReader* in, size_t rows, size_t length) {
  LpcCode c;
  c.rows = rows;
  c.length = length;
  c.order = in->u8();
  c.weight_bits = in->u8();
  if (c.order > 8 || c.weight_bits > 30) corrupt("LPC order or weight bits out of range");
  const size_t nw = c.has_weights() ? rows * static_cast<size_t>(c.order) : 0;
  if (rows > 0 && length > in->remaining() / rows) corrupt("LPC block larger than the payload");
  if (nw + rows * length > in->remaining()) corrupt("LPC block larger than the payload");
  c.weights.resize(nw);
  for (auto& w : c.weights) {
    int64_t v = in->svarint();
    if (v < INT32_MIN || v > INT32_MAX) corrupt("LPC weight out of range");
    w = static_cast<int32_t>(v);
  }
  c.values.resize(rows * length);
  for (auto& v : c.values) v = in->svarint();
  return c;
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
    if (label[f] >= clusters) corrupt("frame " + std::to_string(f) + " has cluster index " + std::to_string(label[f]));
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

void reconstruct(const TsModel& m, std::vector<double>* xyz) {
  const size_t dim = 3 * m.points;
  xyz->assign(m.frames * dim, 0.0);
  const auto layout = cluster_layout(m.label, m.clusters);
  if (m.cluster.size() != layout.size()) corrupt("cluster count disagrees with the labels");
  for (size_t c = 0; c < layout.size(); ++c) {
    const TsCluster& tc = m.cluster[c];
    const ClusterLayout& lay = layout[c];
    const size_t r = tc.basis.size();
    if (tc.first.rows != r || tc.first.length != lay.first_len ||
        tc.later.size() != lay.frames.size() - lay.first_len)
      corrupt("cluster " + std::to_string(c) + " sizes disagree with its frames");
    const Eigen::MatrixXd b = dequantise_basis(tc.basis, dim);
    Eigen::MatrixXd w(static_cast<Eigen::Index>(r), static_cast<Eigen::Index>(lay.frames.size()));
    const Eigen::MatrixXd first = lpc_decode(tc.first, std::vector<double>(r, m.coef_step));
    w.leftCols(static_cast<Eigen::Index>(lay.first_len)) = first;
    for (size_t j = 0; j < tc.later.size(); ++j)
      w.col(static_cast<Eigen::Index>(lay.first_len + j)) =
          lcps_decode(tc.later[j], first, m.coef_step, tc.lcps_weight_bits);
    const Eigen::MatrixXd x = b * w;  // dim x l_c
    for (size_t j = 0; j < lay.frames.size(); ++j) {
      const double* src = x.col(static_cast<Eigen::Index>(j)).data();
      std::copy(src, src + dim, xyz->begin() + static_cast<std::ptrdiff_t>(lay.frames[j] * dim));
    }
  }
  if (m.rigid) {
    if (m.rigid_code.rows != 6 || m.rigid_code.length != m.frames) corrupt("rigid block size");
    std::vector<double> steps = {m.rot_step, m.rot_step, m.rot_step, m.trans_step, m.trans_step, m.trans_step};
    const Eigen::MatrixXd p = lpc_decode(m.rigid_code, steps);
    for (size_t f = 0; f < m.frames; ++f) {
      RigidParams rp;
      for (int a = 0; a < 3; ++a) {
        rp.rot[a] = p(a, static_cast<Eigen::Index>(f));
        rp.trans[a] = p(3 + a, static_cast<Eigen::Index>(f));
      }
      apply_rigid_inverse(rp, xyz->data() + f * dim, m.points);
    }
  }
}

void write_model(const TsModel& m, ByteWriter* out) {
  out->u8(kVersion);
  out->u8(m.rigid ? 1 : 0);
  out->varint(m.frames);
  out->varint(m.points);
  out->f64(m.coef_step);
  out->u8(static_cast<uint8_t>(m.clusters));
  if (m.clusters > 1)
    for (uint8_t l : m.label) out->u8(l);
  if (m.rigid) {
    out->f64(m.rot_step);
    out->f64(m.trans_step);
    write_lpc(m.rigid_code, out);
  }
  for (const TsCluster& c : m.cluster) {
    out->varint(c.basis.size());
    for (const QuantisedVector& q : c.basis) {
      out->u8(static_cast<uint8_t>(q.bits));
      out->f64(q.scale);
      for (int32_t v : q.q) out->svarint(v);
    }
    write_lpc(c.first, out);
    out->u8(static_cast<uint8_t>(c.lcps_weight_bits));
    for (const LcpsFrame& f : c.later) {
      out->u8(static_cast<uint8_t>(f.index.size()));
      for (uint32_t i : f.index) out->varint(i);
      for (int32_t w : f.weight) out->svarint(w);
      for (int64_t v : f.resid) out->svarint(v);
    }
  }
}

TsModel read_model(const uint8_t* data, size_t size, size_t frames, size_t points) {
  ByteReader in(data, size, kWhat);
  TsModel m;
  const uint8_t version = in.u8();
  if (version != kVersion)
    fail(ErrorCode::kUnsupportedVersion, kWhat, "version " + std::to_string(version) + " (this build reads 1)");
  const uint8_t flags = in.u8();
  if (flags > 1) corrupt("unknown flags");
  m.rigid = flags & 1;
  m.frames = in.varint();
  m.points = in.varint();
  if (m.frames != frames || m.points != points) corrupt("window shape disagrees with the container");
  const size_t dim = 3 * points;
  m.coef_step = read_step(&in, "coefficient step");
  m.clusters = in.u8();
  if (m.clusters < 1 || static_cast<size_t>(m.clusters) > std::max<size_t>(frames, 1)) corrupt("cluster count out of range");
  if (frames > in.remaining()) corrupt("frame count larger than the payload");
  m.label.assign(frames, 0);
  if (m.clusters > 1)
    for (auto& l : m.label) l = in.u8();
  if (m.rigid) {
    m.rot_step = read_step(&in, "rotation step");
    m.trans_step = read_step(&in, "translation step");
    m.rigid_code = read_lpc(&in, 6, frames);
  }
  if (frames == 0) return m;
  const auto layout = cluster_layout(m.label, m.clusters);
  m.cluster.resize(layout.size());
  for (size_t c = 0; c < layout.size(); ++c) {
    TsCluster& tc = m.cluster[c];
    const size_t lc = layout[c].frames.size(), l1 = layout[c].first_len;
    const uint64_t r = in.varint();
    if (r > std::min(dim, lc)) corrupt("cluster " + std::to_string(c) + " has more PCs than frames or dimensions");
    if (dim > 0 && r > in.remaining() / dim) corrupt("basis larger than the payload");
    tc.basis.resize(r);
    for (auto& q : tc.basis) {
      q.bits = in.u8();
      if (q.bits < 2 || q.bits > 30) corrupt("basis bits out of 2..30");
      q.scale = in.f64();
      if (!std::isfinite(q.scale) || q.scale < 0) corrupt("basis scale is not a finite number >= 0");
      const int64_t lim = (int64_t{1} << (q.bits - 1)) - 1;
      q.q.resize(dim);
      for (auto& v : q.q) {
        const int64_t x = in.svarint();
        if (x < -lim || x > lim) corrupt("basis value outside its bit range");
        v = static_cast<int32_t>(x);
      }
    }
    tc.first = read_lpc(&in, r, l1);
    tc.lcps_weight_bits = in.u8();
    if (tc.lcps_weight_bits > 30) corrupt("LCPS weight bits out of range");
    if (lc - l1 > in.remaining()) corrupt("LCPS frames larger than the payload");
    tc.later.resize(lc - l1);
    for (LcpsFrame& f : tc.later) {
      const size_t k = in.u8();
      if (k > l1) corrupt("LCPS uses more references than the first fragment has");
      f.index.resize(k);
      for (auto& i : f.index) {
        const uint64_t v = in.varint();
        if (v >= l1) corrupt("LCPS reference index out of range");
        i = static_cast<uint32_t>(v);
      }
      f.weight.resize(k);
      for (auto& w : f.weight) {
        const int64_t v = in.svarint();
        if (v < INT32_MIN || v > INT32_MAX) corrupt("LCPS weight out of range");
        w = static_cast<int32_t>(v);
      }
      if (r > in.remaining()) corrupt("LCPS residuals larger than the payload");
      f.resid.resize(r);
      for (auto& v : f.resid) v = in.svarint();
    }
  }
  if (!in.at_end()) corrupt(std::to_string(in.remaining()) + " trailing bytes");
  return m;
}

}  // namespace ts
}  // namespace capz
