// ATTR's predictor 12 on the encoder's side (docs/FORMAT.md "Scans (format 1.1)": point fields of
// a ragged window; how the encoder chooses: "The encoder", informative): the quantum found among
// decimal steps, each base costed, the lane's residuals coded.
#include <algorithm>
#include <cmath>
#include <cstring>
#include <string>

#include "coding/attributes_entropy.h"
#include "coding/attributes_quantum.h"

namespace capz {
namespace attr {

namespace {

// The value of a lane value of a float field (size 4 or 8).
double lane_double(uint64_t u, int bits) {
  const uint64_t b = from_ordered(u, 'F', bits);
  if (bits == 32) return static_cast<double>(bits_float(static_cast<uint32_t>(b)));
  double d;
  std::memcpy(&d, &b, 8);
  return d;
}

// The k the encoder gives a value: the nearest multiple, or kh (no integer change) when the
// value has none in int32.
int32_t k_of(double v, double quantum, int32_t kh) {
  const double t = v / quantum;
  if (!std::isfinite(t) || std::fabs(t) >= 2147483647.0) return kh;
  return static_cast<int32_t>(std::nearbyint(t));
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

// Walks the lane under qp as the encoder codes it: int_res(d), corr(c, gap) per residual.
template <typename Int, typename Corr>
void walk_encode(const QuantumParams& qp, const std::vector<uint16_t>& keys, const uint8_t* valid,
                 const double* xyz, const uint32_t* near, Lane& l, Int&& int_res, Corr&& corr) {
  const uint64_t mask = mask_of(l.bits);
  const int size = l.bits / 8;
  walk_quantum(
      &l.u, valid, qp, keys.data(), xyz, near,
      [&](uint64_t* v, uint64_t p) { corr(signed_residual((*v - p) & mask, l.bits), true); },
      [&](uint64_t* v, int32_t kh, int32_t* k) {
        *k = k_of(lane_double(*v, l.bits), qp.quantum, kh);
        int_res(static_cast<int32_t>(static_cast<uint32_t>(*k) - static_cast<uint32_t>(kh)));
        corr(signed_residual((*v - quantum_value(*k, qp.quantum, size, qp.wide)) & mask, l.bits),
             false);
      });
}

}  // namespace

bool choose_quantum(const std::vector<AttrSpec>& specs,
                    const std::vector<std::vector<uint8_t>>& data, size_t a, Lane& l,
                    const uint8_t* valid, const double* xyz, const uint32_t* near,
                    QuantumParams* qp, uint64_t* cost) {
  const AttrSpec& s = specs[a];
  if (s.type != 'F' || (s.size != 4 && s.size != 8) || l.u.empty()) return false;
  bool wide = false;
  const double quantum = find_quantum(l, valid, &wide);
  if (quantum == 0) return false;
  std::vector<QuantumParams> cands;
  cands.push_back({quantum, kBasePrevious, {}, 0, wide});
  for (size_t b = 0; b < specs.size(); ++b)
    for (size_t e = 0; is_key_field(specs[b]) && e < static_cast<size_t>(specs[b].count) && e < 8;
         ++e)
      cands.push_back({quantum, kBaseKey, {b, e}, 0, wide});
  if (xyz) cands.push_back({quantum, kBaseRange, {}, range_offset(l, valid, xyz), wide});
  if (near) cands.push_back({quantum, kBaseNear, {}, 0, wide});
  // What every candidate's walk_encode would sum alike, summed once: each valid point's k and
  // correction (k_of depends on the prediction only for a value without an int32 multiple,
  // `own`: those are costed per candidate) and the gap points' residuals.
  const uint64_t mask = mask_of(l.bits);
  const int size = l.bits / 8;
  const size_t n = l.u.size();
  std::vector<int32_t> ks(n, 0);
  std::vector<uint8_t> own(n, 0);
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
      own[p] = 1;
      continue;
    }
    ks[p] = static_cast<int32_t>(std::nearbyint(t));
    shared += bit_length(
        zigzag64(signed_residual((v - quantum_value(ks[p], quantum, size, wide)) & mask, l.bits)));
  }
  *cost = ~uint64_t{0};
  for (const QuantumParams& c : cands) {
    uint64_t sum = shared;
    const uint64_t* base = l.u.data();
    walk_quantum(
        &l.u, valid, c, keys_of(c, specs, data, n).data(), xyz, near, [](uint64_t*, uint64_t) {},
        [&](uint64_t* v, int32_t kh, int32_t* k) {
          const size_t p = static_cast<size_t>(v - base);
          if (own[p]) {  // k = kh: no integer residual, the correction against kh D
            *k = kh;
            sum += bit_length(zigzag64(
                signed_residual((*v - quantum_value(kh, quantum, size, wide)) & mask, l.bits)));
            return;
          }
          *k = ks[p];
          sum += bit_length(zigzag(
              static_cast<int32_t>(static_cast<uint32_t>(ks[p]) - static_cast<uint32_t>(kh))));
        });
    if (sum < *cost) {
      *cost = sum;
      *qp = c;
    }
  }
  return true;
}

void write_quantum(ByteWriter* w, const QuantumParams& qp) {
  w->f64(qp.quantum);
  w->u8(static_cast<uint8_t>(qp.base | (qp.wide ? kWideBit : 0)));
  if (qp.base == kBaseKey) {
    w->varint(qp.key.attribute);
    w->varint(qp.key.element);
  } else if (qp.base == kBaseRange) {
    w->f64(qp.offset);
  }
}

void encode_quantum_lane(IntEncoder::Cursor* c, const QuantumParams& qp,
                         const std::vector<AttrSpec>& specs,
                         const std::vector<std::vector<uint8_t>>& data, const uint8_t* valid,
                         const double* xyz, const uint32_t* near, LaneState* st, Lane& l) {
  walk_encode(
      qp, keys_of(qp, specs, data, l.u.size()), valid, xyz, near, l,
      [&](int32_t d) { put_int_residual(c, &st->mag[0], d); },
      [&](int64_t r, bool gap) { put_float_residual(c, &st->prev_nb[gap ? 1 : 0], r); });
}

}  // namespace attr
}  // namespace capz
