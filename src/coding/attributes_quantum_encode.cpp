// ATTR's predictor 12 on the encoder's side (docs/FORMAT.md "Scans (format 1.1)": point fields of
// a ragged window; how the encoder chooses: "The encoder", informative): the quantum found among
// decimal steps, each base costed, the lane's residuals coded.
#include <algorithm>
#include <cmath>
#include <cstring>
#include <string>

#include "capz/error.h"
#include "coding/attributes_entropy.h"
#include "coding/attributes_quantum.h"

namespace capz {
namespace attr {

namespace {

// The sweep bit's bins the encoder tries (FORMAT.md, informative): 2^11 a turn, about 0.18
// degree (pandar64-factory20: 2^10 and 2^12 coded more, docs/lab/2026-11-30-fields-ring.md).
constexpr int kSweepBinsTried = 11;

// The value of a lane value of a float field (size 4 or 8).
double lane_double(uint64_t u, int bits) {
  const uint64_t b = from_ordered(u, 'F', bits);
  if (bits == 32) return static_cast<double>(bits_float(static_cast<uint32_t>(b)));
  double d;
  std::memcpy(&d, &b, 8);
  return d;
}

// The largest decimal step m 10^e (m 5, 2.5, 2, 1; e 3 .. -6) for which all but 1/256 of the
// valid values are k D under one of the rounding rules (float32 fields: the float32 product or
// the binary64 one, *wide); 0 for none.
double find_quantum(const Lane& l, const uint8_t* valid, bool* wide) {
  const int size = l.bits / 8;
  size_t nv = 0;
  for (size_t p = 0; p < l.u.size(); ++p) nv += valid[p] ? 1 : 0;
  if (nv == 0) return 0;
  static const char* const kMantissas[] = {"5", "2.5", "2", "1"};
  for (int e = 3; e >= -6; --e)
    for (const char* m : kMantissas) {
      const double quantum = std::stod(std::string(m) + "e" + std::to_string(e));
      for (int w = 0; w < (size == 4 ? 2 : 1); ++w) {
        size_t misses = 0;
        for (size_t p = 0; p < l.u.size() && misses <= nv / 256; ++p) {
          if (!valid[p]) continue;
          const double t = lane_double(l.u[p], l.bits) / quantum;
          if (!std::isfinite(t) || std::fabs(t) >= 2147483647.0 ||
              quantum_value(static_cast<int32_t>(std::nearbyint(t)), quantum, size, w == 1) !=
                  l.u[p])
            ++misses;
        }
        if (misses <= nv / 256) {
          *wide = w == 1;
          return quantum;
        }
      }
    }
  return 0;
}

// Base 2's offset: the median of range - value over up to 4096 valid points, to 2^-20.
double range_offset(const Lane& l, const uint8_t* valid, const double* xyz) {
  std::vector<double> d;
  const size_t n = l.u.size(), stride = std::max<size_t>(1, n / 4096);
  for (size_t p = 0; p < n; p += stride) {
    if (!valid[p]) continue;
    const double* x = xyz + 3 * p;
    const double r = std::sqrt((x[0] * x[0] + x[1] * x[1]) + x[2] * x[2]);
    const double v = lane_double(l.u[p], l.bits);
    if (std::isfinite(r - v)) d.push_back(r - v);
  }
  if (d.empty()) return 0;
  std::nth_element(d.begin(), d.begin() + static_cast<std::ptrdiff_t>(d.size() / 2), d.end());
  return std::round(d[d.size() / 2] * 1048576.0) / 1048576.0;
}

// The key values of qp's key (base 1), else none.
std::vector<uint16_t> keys_of(const QuantumParams& qp, const std::vector<AttrSpec>& specs,
                              const std::vector<std::vector<uint8_t>>& data, size_t n) {
  if (qp.base != kBaseKey) return {};
  return key_values(specs[qp.key.attribute], data[qp.key.attribute], n, qp.key.element);
}

// Predictor 12's candidates for a lane on `quantum`: the previous value's base, each key field's
// element (by sweep bins too in a ragged window of frames), the range and the nearest point.
std::vector<QuantumParams> quantum_candidates(const std::vector<AttrSpec>& specs, const Lane& l,
                                              const uint8_t* valid, const double* xyz,
                                              const uint32_t* near, double quantum, bool wide,
                                              const RaggedFields* rf) {
  std::vector<QuantumParams> cands;
  cands.push_back({quantum, kBasePrevious, {}, 0, wide});
  for (size_t b = 0; b < specs.size(); ++b)
    for (size_t e = 0; is_key_field(specs[b]) && e < static_cast<size_t>(specs[b].count) && e < 8;
         ++e)
      for (int sweep : {0, kSweepBinsTried})
        if (sweep == 0 || (rf && rf->q && rf->frame_offsets && rf->frames > 1))
          cands.push_back({quantum, kBaseKey, {b, e}, 0, wide, sweep});
  if (xyz) cands.push_back({quantum, kBaseRange, {}, range_offset(l, valid, xyz), wide});
  if (near) cands.push_back({quantum, kBaseNear, {}, 0, wide});
  return cands;
}

// What every candidate's walk_encode would sum alike, summed once: each valid point's k and
// correction (k_of depends on the prediction only for a value without an int32 multiple, `own`:
// those are costed per candidate) and the gap points' residuals. Fills pts (corr with `corr`).
uint64_t shared_cost(const Lane& l, const uint8_t* valid, double quantum, bool wide, bool corr,
                     QuantumPoints* pts) {
  const uint64_t mask = mask_of(l.bits);
  const int size = l.bits / 8;
  const size_t n = l.u.size();
  pts->k.assign(n, 0);
  pts->own.assign(n, 0);
  pts->corr.assign(corr ? n : 0, 0);
  uint64_t shared = 0, last_gap = 0;
  for (size_t p = 0; p < n; ++p) {
    const uint64_t v = l.u[p];
    if (!valid[p]) {
      shared += bit_length(zigzag64(signed_residual((v - last_gap) & mask, l.bits)));
      last_gap = v;
      continue;
    }
    const double t = lane_double(v, l.bits) / quantum;
    if (!std::isfinite(t) || std::fabs(t) >= 2147483647.0) {
      pts->own[p] = 1;
      continue;
    }
    pts->k[p] = static_cast<int32_t>(std::nearbyint(t));
    const int64_t r =
        signed_residual((v - quantum_value(pts->k[p], quantum, size, wide)) & mask, l.bits);
    if (corr) pts->corr[p] = r;
    shared += bit_length(zigzag64(r));
  }
  return shared;
}

// Candidate c's cost beyond shared_cost's: its k residuals, and the corrections of the `own`
// values against its predictions.
uint64_t candidate_cost(const std::vector<AttrSpec>& specs,
                        const std::vector<std::vector<uint8_t>>& data, Lane& l,
                        const uint8_t* valid, const double* xyz, const uint32_t* near,
                        const QuantumParams& c, const QuantumPoints& pts, const RaggedFields* rf) {
  const uint64_t mask = mask_of(l.bits);
  const int size = l.bits / 8;
  const size_t n = l.u.size();
  uint64_t sum = 0;
  const uint64_t* base = l.u.data();
  const std::vector<uint16_t> keys = keys_of(c, specs, data, n);
  const std::vector<int32_t> cells = cells_of(c, keys.data(), valid, n, rf);
  walk_quantum(
      &l.u, valid, c, keys.data(), xyz, near, [](uint64_t*, uint64_t) {},
      [&](uint64_t* v, int32_t kh, int32_t* k) {
        const size_t p = static_cast<size_t>(v - base);
        if (pts.own[p]) {  // k = kh: no integer residual, the correction against kh D
          *k = kh;
          sum += bit_length(zigzag64(
              signed_residual((*v - quantum_value(kh, c.quantum, size, c.wide)) & mask, l.bits)));
          return;
        }
        *k = pts.k[p];
        sum += bit_length(zigzag(
            static_cast<int32_t>(static_cast<uint32_t>(pts.k[p]) - static_cast<uint32_t>(kh))));
      },
      cells.empty() ? nullptr : cells.data(), rf);
  return sum;
}

}  // namespace

bool choose_quantum(const std::vector<AttrSpec>& specs,
                    const std::vector<std::vector<uint8_t>>& data, size_t a, Lane& l,
                    const uint8_t* valid, const double* xyz, const uint32_t* near,
                    QuantumParams* qp, uint64_t* cost, QuantumPoints* points,
                    const RaggedFields* rf) {
  const AttrSpec& s = specs[a];
  if (s.type != 'F' || (s.size != 4 && s.size != 8) || l.u.empty()) return false;
  bool wide = false;
  const double quantum = find_quantum(l, valid, &wide);
  if (quantum == 0) return false;
  const std::vector<QuantumParams> cands =
      quantum_candidates(specs, l, valid, xyz, near, quantum, wide, rf);
  QuantumPoints local;
  QuantumPoints& pts = points ? *points : local;
  const uint64_t shared = shared_cost(l, valid, quantum, wide, points != nullptr, &pts);
  *cost = ~uint64_t{0};
  for (const QuantumParams& c : cands) {
    const uint64_t sum = shared + candidate_cost(specs, data, l, valid, xyz, near, c, pts, rf);
    if (sum < *cost) {
      *cost = sum;
      *qp = c;
    }
  }
  return true;
}

void write_quantum(ByteWriter* w, const QuantumParams& qp) {
  w->f64(qp.quantum);
  w->u8(static_cast<uint8_t>(qp.base | (qp.wide ? kWideBit : 0) | (qp.sweep ? kSweepBit : 0)));
  if (qp.base == kBaseKey) {
    w->varint(qp.key.attribute);
    w->varint(qp.key.element);
  } else if (qp.base == kBaseRange) {
    w->f64(qp.offset);
  }
  if (qp.sweep) w->u8(static_cast<uint8_t>(qp.sweep));
}

void encode_quantum_lane(IntEncoder::Cursor* c, const QuantumParams& qp,
                         const std::vector<AttrSpec>& specs,
                         const std::vector<std::vector<uint8_t>>& data, const uint8_t* valid,
                         const double* xyz, const uint32_t* near, const QuantumPoints& points,
                         LaneState* st, Lane& l, const RaggedFields* rf) {
  if (points.k.size() != l.u.size() || points.corr.size() != l.u.size())
    fail(ErrorCode::kInternal, "attributes", "predictor 12's points are not the lane's");
  const uint64_t mask = mask_of(l.bits);
  const int size = l.bits / 8;
  const uint64_t* base = l.u.data();
  const std::vector<uint16_t> keys = keys_of(qp, specs, data, l.u.size());
  const std::vector<int32_t> cells = cells_of(qp, keys.data(), valid, l.u.size(), rf);
  walk_quantum(
      &l.u, valid, qp, keys.data(), xyz, near,
      [&](uint64_t* v, uint64_t p) {
        put_float_residual(c, &st->prev_nb[1], signed_residual((*v - p) & mask, l.bits));
      },
      [&](uint64_t* v, int32_t kh, int32_t* k) {
        const size_t p = static_cast<size_t>(v - base);
        // A value without an int32 multiple keeps the prediction, kh.
        *k = points.own[p] ? kh : points.k[p];
        put_int_residual(
            c, &st->mag[0],
            static_cast<int32_t>(static_cast<uint32_t>(*k) - static_cast<uint32_t>(kh)));
        const int64_t r =
            points.own[p] ? signed_residual(
                                (*v - quantum_value(kh, qp.quantum, size, qp.wide)) & mask, l.bits)
                          : points.corr[p];
        put_float_residual(c, &st->prev_nb[0], r);
      },
      cells.empty() ? nullptr : cells.data(), rf);
}

}  // namespace attr
}  // namespace capz
