// ATTR's predictor 12, quantum (docs/FORMAT.md "Scans (format 1.1)": point fields of a ragged
// window), shared by the encoder and the decoder: a float lane's values as integer multiples k of
// a step D, k predicted from the lane's previous k, from the k of the latest point with the same
// key (a ring or channel field) or from the point's decoded range, then the value's correction
// against k D. Also the key-first coding order of a ragged window's attributes.
#pragma once

#include <algorithm>
#include <cmath>
#include <cstdint>
#include <cstring>
#include <memory>
#include <vector>

#include "coding/attributes.h"
#include "coding/attributes_lanes.h"
#include "coding/bytes.h"
#include "coding/entropy.h"

namespace capz {
namespace attr {

inline constexpr int kQuantumPredictor = 12;
enum QuantumBase : uint8_t { kBasePrevious = 0, kBaseKey = 1, kBaseRange = 2, kBaseNear = 3 };

// Predictor 12's parameters (FORMAT.md: quantum, base, key or offset).
struct QuantumParams {
  double quantum = 1;
  uint8_t base = kBasePrevious;
  UnitRef key;        // base 1
  double offset = 0;  // base 2
  bool wide = false;  // a float32 field's k D in binary64, rounded once (the base byte's bit 2)
  int sweep = 0;      // base 1 with the previous sweep's cells (bit 3): their bins' s, else 0
};
inline constexpr uint8_t kWideBit = 4, kSweepBit = 8;
inline constexpr int kMinSweepBins = 4, kMaxSweepBins = 12, kSweepKeys = 256;

// True for an attribute that can be a key (type U or I, size 1 or 2); a ragged window codes them
// first.
inline bool is_key_field(const AttrSpec& s) {
  return (s.type == 'U' || s.type == 'I') && (s.size == 1 || s.size == 2);
}

// The order in which a window's attributes are coded: the layout's, or (ragged) key-first.
inline std::vector<size_t> coding_order(const std::vector<AttrSpec>& specs, bool ragged) {
  std::vector<size_t> order;
  for (int pass = ragged ? 0 : 1; pass < 2; ++pass)
    for (size_t a = 0; a < specs.size(); ++a)
      if (!ragged || is_key_field(specs[a]) == (pass == 0)) order.push_back(a);
  return order;
}

// The lane value of k D for a field of size 4 or 8: size 4, the float32 product of k and D each
// rounded to float32 (as drivers compute it; exact in binary64, then rounded once), or with
// `wide` the binary64 product rounded to float32 (as --attr-error quantises); size 8 the binary64
// product.
inline uint64_t quantum_value(int32_t k, double quantum, int size, bool wide = false) {
  if (size == 4 && wide)
    return to_ordered(float_bits(static_cast<float>(static_cast<double>(k) * quantum)), 'F', 32);
  if (size == 4) {
    const double e = static_cast<double>(static_cast<float>(k)) *
                     static_cast<double>(static_cast<float>(quantum));
    return to_ordered(float_bits(static_cast<float>(e)), 'F', 32);
  }
  const double e = static_cast<double>(k) * quantum;
  uint64_t b;
  std::memcpy(&b, &e, 8);
  return to_ordered(b, 'F', 64);
}

// Base 2's prediction of k from a point's decoded coordinates (binary64, attributes_shared.cpp,
// compiled without fused multiply-add).
int32_t quantum_range_k(const double* xyz, double quantum, double offset);

// The key lane values of element `e` of attribute bytes `b` (n points, spec s).
inline std::vector<uint16_t> key_values(const AttrSpec& s, const std::vector<uint8_t>& b, size_t n,
                                        size_t e) {
  std::vector<uint16_t> out(n);
  const size_t count = static_cast<size_t>(s.count), size = static_cast<size_t>(s.size);
  for (size_t i = 0; i < n; ++i)
    out[i] = static_cast<uint16_t>(
        to_ordered(load_le(b.data() + (i * count + e) * size, s.size), s.type, 8 * s.size));
  return out;
}

// The sweep bit's cell of each point (FORMAT.md: its key v below 256 and the bin c of its
// diamond angle among 2^s, as v 2^s + c), -1 for none (a gap, a larger key, x = y = 0). keys:
// the key lane values, q: the SCNW integers (n x 3).
inline std::vector<int32_t> sweep_cells(const uint16_t* keys, const int32_t* q,
                                        const uint8_t* valid, size_t n, int s) {
  std::vector<int32_t> out(n, -1);
  const int32_t top = (int32_t{1} << s) - 1;
  const double scale = static_cast<double>(int32_t{1} << s) / 4;  // 2^(s-2): a exact product
  for (size_t p = 0; p < n; ++p) {
    const int32_t x = q[3 * p], y = q[3 * p + 1];
    if (!valid[p] || keys[p] >= kSweepKeys || (x == 0 && y == 0)) continue;
    const double ax = std::fabs(static_cast<double>(x)), ay = std::fabs(static_cast<double>(y));
    const double d = ax + ay;  // exact: below 2^32
    const double a = y >= 0 ? (x >= 0 ? ay / d : 1 + ax / d) : (x < 0 ? 2 + ay / d : 3 + ax / d);
    const auto c = static_cast<int32_t>(std::min<double>(std::floor(a * scale), top));
    out[p] = (static_cast<int32_t>(keys[p]) << s) | c;
  }
  return out;
}

// The previous sweep's k per cell (FORMAT.md, the sweep bit): two tables, the frame before's and
// this frame's, each cell with 1 + the frame that wrote it (no clearing between frames).
class SweepTable {
 public:
  SweepTable(const int32_t* cells, size_t n, int s) {
    int32_t most = -1;
    for (size_t p = 0; p < n; ++p) most = std::max(most, cells[p]);
    const size_t size = most < 0 ? 0 : (static_cast<size_t>(most >> s) + 1) << s;
    for (int t = 0; t < 2; ++t) {
      k_[t].assign(size, 0);
      at_[t].assign(size, 0);
    }
  }
  // The k of cell c in frame f - 1 (f > 0), when a point there had it.
  bool before(int32_t c, size_t f, int32_t* k) const {
    const int t = static_cast<int>((f - 1) & 1);
    if (at_[t][static_cast<size_t>(c)] != f) return false;
    *k = k_[t][static_cast<size_t>(c)];
    return true;
  }
  void set(int32_t c, size_t f, int32_t k) {
    const int t = static_cast<int>(f & 1);
    k_[t][static_cast<size_t>(c)] = k;
    at_[t][static_cast<size_t>(c)] = f + 1;
  }

 private:
  std::vector<int32_t> k_[2];
  std::vector<size_t> at_[2];
};

// The cells of qp's sweep bit for n points (keys: base 1's key values), else none.
inline std::vector<int32_t> cells_of(const QuantumParams& qp, const uint16_t* keys,
                                     const uint8_t* valid, size_t n, const RaggedFields* rf) {
  if (qp.sweep == 0 || !rf || !rf->q || !keys) return {};
  return sweep_cells(keys, rf->q, valid, n, qp.sweep);
}

// Walks a predictor-12 lane in coding order: gap(&value, prediction) for a gap point,
// valid(&value, kh, &k) for a valid one (which sets k). keys: base 1's key values (n), xyz: the
// decoded coordinates (n x 3) for base 2, near: each point's nearest earlier point (n, kNoPoint
// for none; FORMAT.md 13.5) for base 3. With the sweep bit, cells: each point's sweep_cells and
// rf: the window's frames.
template <typename Gap, typename Valid>
inline void walk_quantum(std::vector<uint64_t>* lane, const uint8_t* valid, const QuantumParams& qp,
                         const uint16_t* keys, const double* xyz, const uint32_t* near, Gap&& gap,
                         Valid&& step, const int32_t* cells = nullptr,
                         const RaggedFields* rf = nullptr) {
  const bool sweep = qp.sweep > 0 && cells && rf && rf->frame_offsets && rf->frames > 0;
  std::unique_ptr<SweepTable> table;
  if (sweep) table.reset(new SweepTable(cells, lane->size(), qp.sweep));
  size_t f = 0;  // the frame of point p (sweep)
  uint64_t last_gap = 0;
  int32_t lastk = 0;
  std::vector<int32_t> by_key;
  std::vector<uint8_t> seen;
  if (qp.base == kBaseKey) {
    by_key.assign(65536, 0);
    seen.assign(65536, 0);
  }
  std::vector<int32_t> ks;  // base 3: every valid point's k
  if (qp.base == kBaseNear) ks.assign(lane->size(), 0);
  for (size_t p = 0; p < lane->size(); ++p) {
    uint64_t* v = &(*lane)[p];
    if (!valid[p]) {
      gap(v, last_gap);
      last_gap = *v;
      continue;
    }
    int32_t kh = lastk;
    if (qp.base == kBaseKey && seen[keys[p]]) kh = by_key[keys[p]];
    if (qp.base == kBaseRange) kh = quantum_range_k(xyz + 3 * p, qp.quantum, qp.offset);
    if (qp.base == kBaseNear && near[p] != kNoPoint && valid[near[p]]) kh = ks[near[p]];
    if (sweep) {
      while (f + 1 < rf->frames && p >= rf->frame_offsets[f + 1]) ++f;
      int32_t before = 0;
      if (cells[p] >= 0 && f > 0 && table->before(cells[p], f, &before)) kh = before;
    }
    int32_t k = 0;
    step(v, kh, &k);
    lastk = k;
    if (sweep && cells[p] >= 0) table->set(cells[p], f, k);
    if (qp.base == kBaseNear) ks[p] = k;
    if (qp.base == kBaseKey) {
      by_key[keys[p]] = k;
      seen[keys[p]] = 1;
    }
  }
}

// What choose_quantum found for each point of the lane, whatever the base: a valid point's k and
// its correction's residual, or own (no int32 multiple: k is the prediction, kh, and the
// correction is against kh D).
struct QuantumPoints {
  std::vector<int32_t> k;
  std::vector<int64_t> corr;
  std::vector<uint8_t> own;
};

// The encoder's side (attributes_quantum_encode.cpp). choose_quantum: predictor 12's parameters
// for lane l of attribute a and their cost (the sum of the bit lengths of the zig-zagged integer
// residuals and corrections, and of the gap residuals), false when no quantum fits the lane.
// Base 3 is tried when near (the points' nearest earlier points) is given. With points, the
// lane's k and corrections are left there for encode_quantum_lane.
bool choose_quantum(const std::vector<AttrSpec>& specs,
                    const std::vector<std::vector<uint8_t>>& data, size_t a, Lane& l,
                    const uint8_t* valid, const double* xyz, const uint32_t* near,
                    QuantumParams* qp, uint64_t* cost, QuantumPoints* points = nullptr,
                    const RaggedFields* rf = nullptr);
// The parameters after the predictor byte.
void write_quantum(ByteWriter* w, const QuantumParams& qp);
// The lane's residuals under predictor 12, with the points choose_quantum left for the same lane
// and quantum.
void encode_quantum_lane(IntEncoder::Cursor* c, const QuantumParams& qp,
                         const std::vector<AttrSpec>& specs,
                         const std::vector<std::vector<uint8_t>>& data, const uint8_t* valid,
                         const double* xyz, const uint32_t* near, const QuantumPoints& points,
                         LaneState* st, Lane& l, const RaggedFields* rf = nullptr);

}  // namespace attr
}  // namespace capz
