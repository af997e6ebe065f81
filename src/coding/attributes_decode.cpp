// ATTR's decoder (docs/FORMAT.md 13, 13.4, 13.7, 13.5): the mirror of attributes_encode.cpp, which
// says what the payload holds; the lanes, predictors and walks are attributes_lanes.h's.
#include <algorithm>
#include <array>
#include <cmath>
#include <string>
#include <type_traits>

#include "capz/error.h"
#include "coding/attributes.h"
#include "coding/attributes_entropy.h"
#include "coding/attributes_lanes.h"
#include "coding/attributes_quantum.h"
#include "coding/attributes_ring.h"
#include "coding/bytes.h"
#include "coding/entropy.h"
#include "coding/lzma_block.h"

namespace capz {

namespace {

using namespace attr;

// Lane j of a plain attribute into its bytes (sized n x count x size).
void store_lane(const AttrSpec& s, const Lane& l, size_t n, size_t j, std::vector<uint8_t>* bytes) {
  const size_t count = static_cast<size_t>(s.count), size = static_cast<size_t>(s.size);
  uint8_t* at = bytes->data() + j * size;
  const size_t step = count * size;
  // The element size and type known to the compiler: one store an element, no branch on the
  // type (make_lane's mirror).
  with_element_size(s.size, [&](auto bytes_per) {
    constexpr int kSize = decltype(bytes_per)::value;
    const int sz = kSize ? kSize : s.size;
    auto fill = [&](auto type) {
      constexpr char kType = decltype(type)::value;
      for (size_t i = 0; i < n; ++i)
        store_le(at + i * step, sz, from_ordered(l.u[i], kType, l.bits));
    };
    if (s.type == 'F') return fill(std::integral_constant<char, 'F'>());
    if (s.type == 'I') return fill(std::integral_constant<char, 'I'>());
    fill(std::integral_constant<char, 'U'>());
  });
}

// Predictor 9's references of lane j of attribute a, read and checked (FORMAT.md 13.4).
void read_unit_refs(ByteReader* r, const std::vector<AttrSpec>& specs, size_t a, size_t j,
                    UnitRef refs[2], const std::string& what) {
  const AttrSpec& s = specs[a];
  if (s.type != 'F' || s.size != 4)
    fail(ErrorCode::kCorrupt, what, "predictor 9 on a field that is not float32");
  for (int k = 0; k < 2; ++k) {
    const uint64_t b = r->varint();
    const uint64_t e = r->varint();
    if (b > a || e >= static_cast<uint64_t>(specs[b].count) || (b == a && e >= j) ||
        specs[b].type != 'F' || specs[b].size != 4)
      fail(ErrorCode::kCorrupt, what, "predictor 9 refers to an element it cannot use");
    refs[k] = {static_cast<size_t>(b), static_cast<size_t>(e)};
  }
  if (refs[0].attribute == refs[1].attribute && refs[0].element == refs[1].element)
    fail(ErrorCode::kCorrupt, what, "predictor 9 refers to one element twice");
}

// A field coded by LZMA2 (transforms 2-5, FORMAT.md 13, 13.7): its n points' bytes into *out.
void decode_lzma_field(ByteReader* in, uint8_t t, const AttrSpec& s, size_t n, const uint8_t* valid,
                       const std::string& awhat, std::vector<uint8_t>* out) {
  ByteReader& r = *in;
  std::vector<uint8_t>& bytes = *out;
  const size_t bpp = static_cast<size_t>(s.size) * static_cast<size_t>(s.count);
  const uint64_t m = r.count(1, "LZMA size");
  // Every byte of the field costs at least 1/2900 byte of its data: checked before
  // allocating.
  if (m == 0 || (n != 0 && bpp > kMaxSymbolsPerByte * m / n))
    fail(ErrorCode::kCorrupt, awhat, "field larger than its LZMA data can hold");
  const uint8_t* z = r.bytes(static_cast<size_t>(m));
  if (t <= 3) {
    bytes = lzma2_decode(z, static_cast<size_t>(m), n * bpp, awhat);
    if (t == 2) bytes = from_planes(bytes, static_cast<size_t>(s.size));
    return;
  }
  // 4, 5 (FORMAT.md 13.7): the valid points' values, then the gap points'.
  if (!valid) fail(ErrorCode::kCorrupt, awhat, "transform " + std::to_string(t) + " without gaps");
  const size_t nv =
      static_cast<size_t>(std::count_if(valid, valid + n, [](uint8_t v) { return v != 0; }));
  ByteReader zr(z, static_cast<size_t>(m), awhat);
  const uint64_t na = zr.varint();
  if (na > zr.remaining() || (na == 0) != (nv == 0) || (zr.remaining() - na == 0) != (nv == n))
    fail(ErrorCode::kCorrupt, awhat, "bad split of the valid and gap values");
  const uint8_t* za = zr.bytes(static_cast<size_t>(na));
  std::vector<uint8_t> at_valid, at_gaps;
  if (nv) at_valid = lzma2_decode(za, static_cast<size_t>(na), nv * bpp, awhat);
  if (t == 4) at_valid = from_planes(at_valid, static_cast<size_t>(s.size));
  const size_t nb = zr.remaining();
  if (nv < n) at_gaps = lzma2_decode(zr.bytes(nb), nb, (n - nv) * bpp, awhat);
  merge_by_mask(at_valid, at_gaps, valid, n, bpp, &bytes);
}

// The predictor of each of a field's lanes (and a unit vector's references to the fields that
// complete it).
// Predictor 12's parameters of a lane of attribute a (FORMAT.md "Scans (format 1.1)"), read and
// checked.
QuantumParams read_quantum(ByteReader* r, const std::vector<AttrSpec>& specs, size_t a,
                           const std::string& awhat) {
  const AttrSpec& s = specs[a];
  if (s.type != 'F' || (s.size != 4 && s.size != 8))
    fail(ErrorCode::kCorrupt, awhat, "predictor 12 on a field that is not a float");
  QuantumParams qp;
  qp.quantum = r->f64();
  if (!std::isfinite(qp.quantum) || !(qp.quantum > 0))
    fail(ErrorCode::kCorrupt, awhat, "predictor 12 with a bad quantum");
  const uint8_t base = r->u8();
  qp.wide = (base & kWideBit) != 0;
  const bool sweep = (base & kSweepBit) != 0;
  qp.base = static_cast<uint8_t>(base & ~(kWideBit | kSweepBit));
  if (qp.wide && s.size != 4)
    fail(ErrorCode::kCorrupt, awhat, "predictor 12's binary64 rounding on a float64 field");
  if (qp.base == kBaseKey) {
    const uint64_t b = r->varint();
    const uint64_t e = r->varint();
    if (b >= specs.size() || !is_key_field(specs[b]) || e >= static_cast<uint64_t>(specs[b].count))
      fail(ErrorCode::kCorrupt, awhat, "predictor 12 keyed by a field it cannot use");
    qp.key = {static_cast<size_t>(b), static_cast<size_t>(e)};
  } else if (qp.base == kBaseRange) {
    qp.offset = r->f64();
    if (!std::isfinite(qp.offset))
      fail(ErrorCode::kCorrupt, awhat, "predictor 12 with a bad offset");
  } else if (qp.base != kBasePrevious && qp.base != kBaseNear) {
    fail(ErrorCode::kCorrupt, awhat, "predictor 12 with an unknown base");
  }
  if (sweep && qp.base != kBaseKey)
    fail(ErrorCode::kCorrupt, awhat, "predictor 12's sweep bit without a key");
  if (sweep) {
    qp.sweep = r->u8();
    if (qp.sweep < kMinSweepBins || qp.sweep > kMaxSweepBins)
      fail(ErrorCode::kCorrupt, awhat, "predictor 12's sweep with bins outside 4..12");
  }
  return qp;
}

void read_lane_predictors(ByteReader* in, const std::vector<AttrSpec>& specs, size_t a, bool colour,
                          bool have_q, const RaggedFields* ragged, const std::string& awhat,
                          std::vector<int>* pred, std::vector<std::array<UnitRef, 2>>* refs,
                          std::vector<QuantumParams>* quanta) {
  for (size_t j = 0; j < pred->size(); ++j) {
    const uint8_t id = in->u8();
    const bool near_id = id == kNearPredictor || id == kNearChangePredictor;
    if (id == kQuantumPredictor && ragged && !colour) {
      (*pred)[j] = id;
      (*quanta)[j] = read_quantum(in, specs, a, awhat);
      if ((*quanta)[j].base == kBaseRange && !ragged->xyz)
        fail(ErrorCode::kCorrupt, awhat, "predictor 12 from positions in a window without them");
      if ((*quanta)[j].base == kBaseNear && !have_q)
        fail(ErrorCode::kCorrupt, awhat,
             "predictor 12 from the nearest points in a window without position integers");
      if ((*quanta)[j].sweep && (!ragged->q || !ragged->frame_offsets || ragged->frames == 0))
        fail(ErrorCode::kCorrupt, awhat,
             "predictor 12 from the previous sweep in a window without position integers");
      continue;
    }
    if (id == kRingPredictor && ragged) {
      if (!ring_lane(specs[a], colour))
        fail(ErrorCode::kCorrupt, awhat,
             "predictor 13 on a field that is not an integer of 1 or 2 bytes");
      (*pred)[j] = id;
      continue;
    }
    if (id >= kPredictors && !(id == kUnitPredictor && !colour) && !near_id)
      fail(ErrorCode::kCorrupt, awhat, "unknown predictor " + std::to_string(id));
    if (near_id && !have_q)
      fail(ErrorCode::kCorrupt, awhat,
           "predictor " + std::to_string(id) + " in a window without position integers");
    (*pred)[j] = id;
    if (id == kUnitPredictor) read_unit_refs(in, specs, a, j, (*refs)[j].data(), awhat);
  }
}

// A predictor-12 lane (FORMAT.md "Scans (format 1.1)"): the integer's residual, then the value's
// correction against k D.
void decode_quantum_lane(IntDecoder::Cursor* c, const QuantumParams& qp,
                         const std::vector<AttrSpec>& specs,
                         const std::vector<std::vector<uint8_t>>& data, const uint8_t* valid,
                         const double* xyz, const uint32_t* near, LaneState* st, Lane* l,
                         const RaggedFields* rf) {
  std::vector<uint16_t> keys;
  if (qp.base == kBaseKey)
    keys = key_values(specs[qp.key.attribute], data[qp.key.attribute], l->u.size(), qp.key.element);
  const std::vector<int32_t> cells = cells_of(qp, keys.data(), valid, l->u.size(), rf);
  const uint64_t mask = mask_of(l->bits);
  const int size = l->bits / 8;
  walk_quantum(
      &l->u, valid, qp, keys.data(), xyz, near,
      [&](uint64_t* v, uint64_t p) {
        *v = (p + static_cast<uint64_t>(get_float_residual(c, &st->prev_nb[1]))) & mask;
      },
      [&](uint64_t* v, int32_t kh, int32_t* k) {
        const uint32_t d = static_cast<uint32_t>(get_int_residual(c, &st->mag[0]));
        *k = static_cast<int32_t>(static_cast<uint32_t>(kh) + d);
        const uint64_t p = quantum_value(*k, qp.quantum, size, qp.wide);
        *v = (p + static_cast<uint64_t>(get_float_residual(c, &st->prev_nb[0]))) & mask;
      },
      cells.empty() ? nullptr : cells.data(), rf);
}

// A predictor-13 lane (FORMAT.md "Scans (format 1.1)"): gap points' residuals, the valid
// points' runs of predictions and misses.
void decode_ring_lane(IntDecoder::Cursor* c, const uint8_t* valid, const uint16_t* rings,
                      LaneState* st, Lane* l, const std::string& awhat) {
  const uint64_t mask = mask_of(l->bits);
  bool need = true;  // a run count is due at the next valid point
  uint64_t left = 0;
  int tok;
  walk_ring(&l->u, valid, rings, [&](uint64_t* v, uint64_t p, bool gap) {
    if (gap) {
      *v = (p + static_cast<uint64_t>(static_cast<int64_t>(get_int_residual(c, &st->mag[1])))) &
           mask;
      return;
    }
    if (need) {
      left = c->get(kRunContext, &tok);
      need = false;
    }
    if (left > 0) {
      --left;
      *v = p;
      return;
    }
    const uint32_t e = c->get(kMissContext, &tok);
    if (e >= mask) fail(ErrorCode::kCorrupt, awhat, "predictor 13's miss beyond the lane's values");
    *v = (p + static_cast<uint64_t>(unzigzag64(uint64_t{e} + 1))) & mask;
    need = true;
  });
  if (left > 0)
    fail(ErrorCode::kCorrupt, awhat, "predictor 13's last run counts points past the lane's end");
}

// Whether the block of m bytes can hold the values of a field's lanes (FORMAT.md 13.6, checked
// before allocating): lanes x n, but a predictor-13 lane's gap points only.
bool block_holds(const std::vector<int>& pred, size_t n, const uint8_t* valid, uint64_t m) {
  const size_t lanes = pred.size();
  if (std::find(pred.begin(), pred.end(), kRingPredictor) == pred.end())
    return n == 0 || lanes <= kMaxSymbolsPerByte * m / n;
  const size_t gaps = valid ? static_cast<size_t>(std::count(valid, valid + n, 0)) : 0;
  uint64_t values = 0;
  for (int id : pred) values += id == kRingPredictor ? gaps : n;
  return values <= kMaxSymbolsPerByte * m;
}

// What a field's lanes read beside their block: the fields decoded before (out), the points'
// validity (mask: every point valid when the window gives none and a lane needs one), the nearest
// earlier points (7.3, when a lane reads them) and the ragged window's geometry.
struct FieldInputs {
  const std::vector<AttrSpec>& specs;
  const std::vector<std::vector<uint8_t>>& out;
  const uint8_t* mask;
  const uint32_t* near;
  size_t frames, points, width;
  const RaggedFields* ragged;
  const std::string& what;
};

// Lane j of field s under predictor `pred` into *lane (its bits and residual kind set by the
// caller). True when the lane is stored whatever the field's transform (predictors 11, 12, 13).
bool decode_lane(IntDecoder::Cursor* c, const FieldInputs& in, int pred, const UnitRef* refs,
                 const QuantumParams& quantum, Lane* lane) {
  LaneState st;
  if (pred == kUnitPredictor) {
    int last_sign = 0;
    walk_unit(&lane->u, in.specs, in.out, refs,
              [&](uint64_t* v, float x, float y, bool completable) {
                uint32_t sign = 0;
                if (completable) {
                  int tok;
                  sign = c->get(kSignContext + last_sign, &tok);
                  if (sign > 1) fail(ErrorCode::kCorrupt, in.what, "bad sign symbol");
                  last_sign = static_cast<int>(sign);
                }
                const uint64_t p = unit_prediction(x, y, completable, sign);
                const int64_t res = get_float_residual(c, &st.prev_nb[completable ? 0 : 1]);
                *v = (p + static_cast<uint64_t>(res)) & 0xFFFFFFFFu;
              });
    return true;
  }
  if (pred == kRingPredictor) {
    decode_ring_lane(c, in.mask, in.ragged->ring, &st, lane, in.what);
    return true;
  }
  if (pred == kQuantumPredictor) {
    decode_quantum_lane(c, quantum, in.specs, in.out, in.mask, in.ragged->xyz, in.near, &st, lane,
                        in.ragged);
    return true;
  }
  const uint64_t mask = mask_of(lane->bits);
  walk_lane(pred, &lane->u, in.mask, in.near, in.frames, in.points, in.width, mask,
            [&](uint64_t* v, uint64_t p, bool gap) {
              const int64_t res = lane->float_residuals ? get_float_residual(c, &st.prev_nb[gap])
                                                        : get_int_residual(c, &st.mag[gap]);
              *v = (p + static_cast<uint64_t>(res)) & mask;
            });
  return false;
}

// Whether a field's lanes read the nearest earlier points (FORMAT.md 7.3).
bool reads_near(const std::vector<int>& pred, const std::vector<QuantumParams>& quanta) {
  bool uses = false;
  for (size_t j = 0; j < pred.size(); ++j)
    uses = uses || pred[j] == kNearPredictor || pred[j] == kNearChangePredictor ||
           (pred[j] == kQuantumPredictor && quanta[j].base == kBaseNear);
  return uses;
}

// Whether a field's lanes read the points' validity.
bool reads_mask(const std::vector<int>& pred, bool near) {
  return near || std::any_of(pred.begin(), pred.end(), [](int id) {
           return (id >= 5 && id <= 8) || id == kQuantumPredictor || id == kRingPredictor;
         });
}

}  // namespace

void decode_attributes(const uint8_t* data, size_t size, const std::vector<AttrSpec>& specs,
                       const uint8_t* valid, size_t frames, size_t points, size_t width,
                       std::vector<std::vector<uint8_t>>* out, const std::string& what,
                       const int32_t* q, const RaggedFields* ragged) {
  ByteReader r(data, size, what);
  const size_t n = frames * points;
  const size_t W = width ? width : std::max<size_t>(points, 1);
  out->assign(specs.size(), std::vector<uint8_t>());
  std::vector<uint8_t> all_valid;  // no mask given: every point valid (made when first needed)
  std::vector<uint32_t> near;      // 7.3: nearest earlier points (found when first needed)
  Lane l, col[4];
  for (size_t a : coding_order(specs, ragged != nullptr)) {
    const AttrSpec& s = specs[a];
    const std::string awhat = what + " field " + s.name;
    const uint8_t t = r.u8();
    if (t > 5 || (t == 1 && (s.size != 4 || s.count != 1)))
      fail(ErrorCode::kCorrupt, awhat, "bad transform " + std::to_string(t));
    const size_t bpp = static_cast<size_t>(s.size) * static_cast<size_t>(s.count);
    std::vector<uint8_t>& bytes = (*out)[a];
    if (t >= 2) {
      decode_lzma_field(&r, t, s, n, valid, awhat, &bytes);
      continue;
    }
    const bool colour = t == 1;
    const size_t lanes = lane_count(s, colour);
    std::vector<int> pred(lanes);
    std::vector<std::array<UnitRef, 2>> refs(lanes);
    std::vector<QuantumParams> quanta(lanes);
    read_lane_predictors(&r, specs, a, colour, q != nullptr, ragged, awhat, &pred, &refs, &quanta);
    const uint64_t m = r.count(1, "block size");
    if (!block_holds(pred, n, valid, m))
      fail(ErrorCode::kCorrupt, awhat, "field larger than its block can hold");
    const uint8_t* block = r.bytes(static_cast<size_t>(m));
    const bool uses_near = reads_near(pred, quanta);
    if (!valid && all_valid.empty() && reads_mask(pred, uses_near)) all_valid.assign(n, 1);
    const uint8_t* mask_of_window = valid ? valid : all_valid.data();
    if (uses_near && near.empty()) near = nearest_points(q, mask_of_window, frames, points);
    const FieldInputs in{specs,  *out, mask_of_window, near.data(), frames,
                         points, W,    ragged,         awhat};
    IntDecoder dec(block, static_cast<size_t>(m), kContexts, awhat);
    IntDecoder::Cursor c = dec.cursor();
    bytes.assign(n * bpp, 0);
    for (size_t j = 0; j < lanes; ++j) {
      Lane& cur_lane = colour ? col[j] : l;
      cur_lane.bits = lane_bits(s, colour, j);
      cur_lane.float_residuals = !colour && (s.type == 'F' || cur_lane.bits == 64);
      cur_lane.u.assign(n, 0);
      if (decode_lane(&c, in, pred[j], refs[j].data(), quanta[j], &cur_lane) || !colour)
        store_lane(s, cur_lane, n, j, &bytes);
    }
    dec.commit(c);
    if (!dec.at_end()) fail(ErrorCode::kCorrupt, awhat, "attribute block has bytes left over");
    if (colour) {
      uint64_t v[4];
      for (size_t i = 0; i < n; ++i) {
        for (int j = 0; j < 4; ++j) v[j] = col[j].u[i];
        colour_inverse(v, bytes.data() + i * 4);
      }
    }
  }
  if (!r.at_end()) fail(ErrorCode::kCorrupt, what, "bytes after the last attribute");
}

}  // namespace capz
