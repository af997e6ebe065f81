// ATTR's encoder (docs/FORMAT.md 13): per attribute, lanes of ordered integers with one of twelve
// predictors per lane (13.3; 9 completes a unit vector's component from two other elements,
// 13.4; 10 and 11 read the point's nearest earlier point in space, 13.5) and residuals coded
// under ATTR's contexts (attributes_entropy.h, 13.6), or LZMA2 of its byte planes or bytes, also
// of its valid points' values apart from its gap points' (13.7), whichever is smaller.
#include <algorithm>
#include <array>
#include <cmath>
#include <cstring>
#include <limits>
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

// Lane j of one attribute (frames x points x count elements of size bytes in `bytes`), one lane
// at a time so a window holds one lane of 64-bit values, not every field's.
void make_lane(const AttrSpec& s, bool colour, const std::vector<uint8_t>& bytes, size_t n,
               size_t j, Lane* l) {
  l->bits = lane_bits(s, colour, j);
  l->float_residuals = !colour && (s.type == 'F' || l->bits == 64);
  l->u.resize(n);
  if (colour) {
    uint16_t v[4];
    for (size_t i = 0; i < n; ++i) {
      colour_forward(bytes.data() + i * 4, v);
      l->u[i] = v[j];
    }
    return;
  }
  const size_t count = static_cast<size_t>(s.count), size = static_cast<size_t>(s.size);
  const uint8_t* at = bytes.data() + j * size;
  const size_t step = count * size;
  // The element size known to the compiler: one load an element instead of a loop of bytes.
  with_element_size(s.size, [&](auto bytes_per) {
    constexpr int kSize = decltype(bytes_per)::value;
    const int sz = kSize ? kSize : s.size;
    for (size_t i = 0; i < n; ++i)
      l->u[i] = to_ordered(load_le(at + i * step, sz), s.type, l->bits);
  });
}

// The predictor whose residuals have the smallest sum of bit lengths (ties: the lowest);
// 5..8 only with a gap mask that has gaps, 10 and 11 only with the points' nearest earlier
// points (near; valid then holds a mask, all set when the window has no gaps). In one frame of
// one row (a ragged window's fields) 2, 3 and 4 predict what 1 does (the previous value), 6, 7
// and 8 what 5 does (the previous valid value) and 11 what 10 does (no previous frame), so they
// are not walked: they tie, and the lower id wins a tie.
int choose_predictor(Lane& l, const uint8_t* valid, bool gaps, const uint32_t* near, size_t frames,
                     size_t N, size_t W, uint64_t* cost_out) {
  const uint64_t mask = mask_of(l.bits);
  uint64_t best_cost = ~uint64_t{0};
  int best = 0;
  const bool one_row = frames == 1 && W >= N;
  const int ids[] = {0, 1, 2, 3, 4, 5, 6, 7, 8, kNearPredictor, kNearChangePredictor};
  for (int id : ids) {
    if ((id >= 5 && id <= 8 && !gaps) || (id >= kNearPredictor && !near)) continue;
    if (one_row && ((id >= 2 && id <= 4) || (id >= 6 && id <= 8) || id == kNearChangePredictor))
      continue;
    uint64_t cost = 0;
    walk_lane(id, &l.u, valid, near, frames, N, W, mask, [&](uint64_t* v, uint64_t pred, bool) {
      cost += bit_length(zigzag64(signed_residual((*v - pred) & mask, l.bits)));
    });
    if (cost < best_cost) {
      best_cost = cost;
      best = id;
    }
  }
  *cost_out = best_cost;
  return best;
}

// The references predictor 9 may use for lane `j` of attribute `a` (FORMAT.md 13.4, how the
// encoder chooses): float32 normal_z after float32 normal_x and normal_y, or element 2 of a
// float32 count-3 field named normal*. False when there are none.
bool unit_candidate(const std::vector<AttrSpec>& specs, size_t a, size_t j, UnitRef refs[2]) {
  auto f32 = [](const AttrSpec& s) { return s.type == 'F' && s.size == 4; };
  const AttrSpec& s = specs[a];
  if (!f32(s) || is_colour_field(s)) return false;
  if (s.count == 3 && j == 2 && s.name.compare(0, 6, "normal") == 0) {
    refs[0] = {a, 0};
    refs[1] = {a, 1};
    return true;
  }
  if (s.count != 1 || s.name != "normal_z") return false;
  int found = 0;
  for (size_t b = 0; b < a; ++b)
    for (int k = 0; k < 2; ++k)
      if (specs[b].name == (k ? "normal_y" : "normal_x") && f32(specs[b]) && specs[b].count == 1) {
        refs[k] = {b, 0};
        found |= 1 << k;
      }
  return found == 3;
}

// Cost of a predictor-9 lane as choose_predictor counts it: residual bit lengths plus one bit
// per completable value (its sign).
uint64_t unit_cost(Lane& l, const std::vector<AttrSpec>& specs,
                   const std::vector<std::vector<uint8_t>>& data, const UnitRef refs[2]) {
  uint64_t cost = 0;
  walk_unit(&l.u, specs, data, refs, [&](uint64_t* v, float x, float y, bool completable) {
    const uint32_t sign = static_cast<uint32_t>(from_ordered(*v, 'F', 32) >> 31);
    const uint64_t pred = unit_prediction(x, y, completable, sign);
    cost += bit_length(zigzag64(signed_residual((*v - pred) & 0xFFFFFFFFu, 32))) +
            (completable ? 1 : 0);
  });
  return cost;
}

// Cost of a predictor-13 lane as choose_predictor counts it (valid: a mask, all set without
// gaps): the bit lengths of its run counts, misses and gap residuals. kLeastSymbolShare: the
// valid points a bit of the other predictors' symbols is counted for (FORMAT.md 16.4).
constexpr uint64_t kLeastSymbolShare = 160;
uint64_t ring_cost(Lane& l, const uint8_t* valid, const uint16_t* rings) {
  uint64_t cost = 0;
  ring_symbols(l, valid, rings, [&](int kind, uint64_t u) {
    cost += bit_length(kind == 2 ? zigzag64(static_cast<int64_t>(u)) : u);
  });
  return cost;
}

// What encode_predictive's lanes read beside their own values: every field's bytes (data), the
// points' validity (a mask, all set without gaps, in a ragged window), the nearest earlier points
// (7.3) and the ragged window's geometry.
struct LaneInputs {
  const std::vector<AttrSpec>& specs;
  const std::vector<std::vector<uint8_t>>& data;
  size_t a;  // the field
  const uint8_t* valid;
  bool gaps;
  const uint32_t* near;
  size_t frames, points, width;
  const RaggedFields* ragged;
};

// A lane's predictor (FORMAT.md 13), with what it writes beside its id.
struct LaneChoice {
  int pred = 0;
  UnitRef refs[2];
  QuantumParams qp;
  QuantumPoints qpoints;
};

// The least costly predictor of lane j (*lane) of field in.a.
LaneChoice choose_lane(const LaneInputs& in, bool colour, size_t j, Lane* lane) {
  Lane& l = *lane;  // (not const: the lane walkers are the decoder's too, which fill it)
  const AttrSpec& s = in.specs[in.a];
  const size_t n = in.frames * in.points;
  LaneChoice ch;
  uint64_t cost = 0;
  ch.pred = choose_predictor(l, in.valid, in.gaps, in.near, in.frames, in.points, in.width, &cost);
  if (!colour && unit_candidate(in.specs, in.a, j, ch.refs)) {
    const uint64_t u = unit_cost(l, in.specs, in.data, ch.refs);
    if (u < cost || (u == cost && ch.pred > kUnitPredictor)) ch.pred = kUnitPredictor;
  }
  // Predictor 12 (a ragged window's; valid then holds a mask, all set without gaps).
  uint64_t qcost = 0;
  if (in.ragged && !colour && ch.pred != kUnitPredictor &&
      choose_quantum(in.specs, in.data, in.a, l, in.valid, in.ragged->xyz, in.near, &ch.qp, &qcost,
                     &ch.qpoints, in.ragged) &&
      qcost < cost)
    ch.pred = kQuantumPredictor;
  // Predictor 13 (a ragged window's, on a key field's lane): the geometry's rings. Its runs
  // code a valid point that takes its prediction in no symbol, the others in one, which costs
  // about 1/160 bit at least (2.3's models at rate 7): counted against them.
  if (in.ragged && ring_lane(s, colour) &&
      ring_cost(l, in.valid, in.ragged->ring) <
          cost + static_cast<uint64_t>(std::count(in.valid, in.valid + n, 1)) / kLeastSymbolShare)
    ch.pred = kRingPredictor;
  return ch;
}

// Lane l under its choice: what the predictor writes beside its id into *w, its values into *c.
void encode_lane(IntEncoder::Cursor* c, ByteWriter* w, const LaneInputs& in, const LaneChoice& ch,
                 Lane* l) {
  LaneState st;
  if (ch.pred == kRingPredictor) {
    ring_symbols(*l, in.valid, in.ragged->ring, [&](int kind, uint64_t u) {
      if (kind == 2)
        put_int_residual(c, &st.mag[1], static_cast<int32_t>(static_cast<int64_t>(u)));
      else
        c->put(static_cast<uint32_t>(u), kind == 0 ? kRunContext : kMissContext);
    });
    return;
  }
  if (ch.pred == kQuantumPredictor) {
    write_quantum(w, ch.qp);
    encode_quantum_lane(c, ch.qp, in.specs, in.data, in.valid, in.ragged->xyz, in.near, ch.qpoints,
                        &st, *l, in.ragged);
    return;
  }
  if (ch.pred == kUnitPredictor) {
    for (const UnitRef& r : ch.refs) {
      w->varint(r.attribute);
      w->varint(r.element);
    }
    int q = 0;  // sign bit of the previous completable value
    walk_unit(&l->u, in.specs, in.data, ch.refs,
              [&](uint64_t* v, float x, float y, bool completable) {
                const uint32_t sign = static_cast<uint32_t>(from_ordered(*v, 'F', 32) >> 31);
                if (completable) {
                  c->put(sign, kSignContext + q);
                  q = static_cast<int>(sign);
                }
                const uint64_t p = unit_prediction(x, y, completable, sign);
                put_float_residual(c, &st.prev_nb[completable ? 0 : 1],
                                   signed_residual((*v - p) & 0xFFFFFFFFu, 32));
              });
    return;
  }
  const uint64_t mask = mask_of(l->bits);
  walk_lane(ch.pred, &l->u, in.valid, in.near, in.frames, in.points, in.width, mask,
            [&](uint64_t* v, uint64_t p, bool gap) {
              const int64_t r = signed_residual((*v - p) & mask, l->bits);
              if (l->float_residuals)
                put_float_residual(c, &st.prev_nb[gap], r);
              else
                put_int_residual(c, &st.mag[gap], static_cast<int32_t>(r));
            });
}

// One attribute, predictively (transforms 0 and 1): transform, predictors, size, block.
std::vector<uint8_t> encode_predictive(const std::vector<AttrSpec>& specs,
                                       const std::vector<std::vector<uint8_t>>& data, size_t a,
                                       const uint8_t* valid, bool gaps, const uint32_t* near,
                                       size_t frames, size_t points, size_t W,
                                       const RaggedFields* ragged) {
  const AttrSpec& s = specs[a];
  const size_t n = frames * points;
  const bool colour = is_colour_field(s);
  const LaneInputs in{specs, data, a, valid, gaps, near, frames, points, W, ragged};
  ByteWriter w;
  w.u8(colour ? 1 : 0);
  IntEncoder enc(kContexts);
  IntEncoder::Cursor c = enc.cursor();
  Lane l;
  for (size_t j = 0; j < lane_count(s, colour); ++j) {
    make_lane(s, colour, data[a], n, j, &l);
    const LaneChoice ch = choose_lane(in, colour, j, &l);
    w.u8(static_cast<uint8_t>(ch.pred));
    encode_lane(&c, &w, in, ch, &l);
  }
  enc.commit(c);
  const std::vector<uint8_t> block = enc.finish();
  w.varint(block.size());
  w.bytes(block);
  return std::move(w.buffer());
}

// LZMA2 of transform 2 (byte planes of elements of `size` bytes) or 3 (the bytes as they are).
std::vector<uint8_t> lzma_transform(uint8_t t, const std::vector<uint8_t>& b, size_t size) {
  return t == 2 ? lzma2_encode_fast(to_planes(b, size).data(), b.size())
                : lzma2_encode_fast(b.data(), b.size());
}

// The one LZMA transform (2 or 3) worth a full trial against a predictive coding of `pred`
// bytes, or 0 for none: each is tried on the first 1/kSampleShare of the elements and its size
// scaled to the whole; the smaller wins (its estimate in *est when not null), and none when the
// predictive coding is below kSkipRatio of that estimate. Fields under kSampleMin bytes: 0xFF
// (every transform tried), but from kRankMin bytes with elements of several bytes the smaller of 2
// and 3 by lzma2_quick_size of the whole field (no skip: it is then coded and compared). The sample
// is first sized by lzma2_quick_size; when the answer would be the same for any lzma2_encode_fast
// sizes between kQuickLow and kQuickHigh times the quick ones, it is taken, else the sample is
// coded again as the full trial would code it.
constexpr size_t kSampleShare = 8, kSampleMin = size_t{1} << 18, kRankMin = size_t{1} << 17;
constexpr double kSkipRatio = 0.9, kQuickLow = 0.8, kQuickHigh = 1.1;
uint8_t lzma_choice(const double est[2], size_t pred, double* smaller = nullptr) {
  const uint8_t t = est[1] < est[0] ? 3 : 2;
  if (smaller) *smaller = est[t - 2];
  return static_cast<double>(pred) < kSkipRatio * est[t - 2] ? 0 : t;
}
uint8_t lzma_worth_trying(const std::vector<uint8_t>& b, size_t size, size_t pred,
                          double* est_out = nullptr) {
  if (b.size() < kSampleMin && (size == 1 || b.size() < kRankMin)) return 0xFF;
  if (b.size() < kSampleMin) {  // the smaller of 2 and 3 coded quickly, whole, is tried
    const size_t planes = lzma2_quick_size(to_planes(b, size).data(), b.size());
    return lzma2_quick_size(b.data(), b.size()) < planes ? 3 : 2;
  }
  const size_t m = b.size() / kSampleShare / size * size;
  const std::vector<uint8_t> sample(b.begin(), b.begin() + static_cast<std::ptrdiff_t>(m));
  const std::vector<uint8_t> planes = to_planes(sample, size);
  const double scale = static_cast<double>(b.size()) / static_cast<double>(m);
  auto estimates = [&](bool quick, double est[2]) {
    for (uint8_t t = 2; t <= 3; ++t) {
      const std::vector<uint8_t>& in = t == 2 ? planes : sample;
      est[t - 2] = t == 3 && size == 1 ? est[0] + 1
                   : quick             ? static_cast<double>(lzma2_quick_size(in.data(), m)) * scale
                           : static_cast<double>(lzma2_encode_fast(in.data(), m).size()) * scale;
    }
  };
  double quick[2], low[2], high[2];
  estimates(true, quick);
  // The two ends of the band, and the two mixed ends that favour one transform or the other.
  for (int k = 0; k < 2; ++k) {
    low[k] = kQuickLow * quick[k];
    high[k] = kQuickHigh * quick[k];
  }
  const double favour2[2] = {low[0], high[1]}, favour3[2] = {high[0], low[1]};
  const uint8_t c = lzma_choice(quick, pred, est_out);
  if (lzma_choice(low, pred) == c && lzma_choice(high, pred) == c &&
      lzma_choice(favour2, pred) == c && (size == 1 || lzma_choice(favour3, pred) == c))
    return c;
  double est[2];
  estimates(false, est);
  return lzma_choice(est, pred, est_out);
}

// A ragged window's (one frame of n points) trial of predictors 10 and 11 before their
// neighbour search, the encoder's largest cost there: on the first eighth of the points (at
// least kNearTrialMin, at most kNearTrialMax), whether some field's coding with them is 3 % smaller
// than without them (the other predictors, 12 included, or LZMA of the byte planes), first by the
// predictors' cost sums, then by the coded bytes. Windows under twice kNearTrialMin are searched
// whole.
constexpr size_t kNearTrialMin = size_t{1} << 13, kNearTrialMax = size_t{1} << 15;
bool near_pays(const std::vector<AttrSpec>& specs, const std::vector<std::vector<uint8_t>>& data,
               const uint8_t* valid, bool gaps, const int32_t* q, size_t n,
               const RaggedFields& ragged) {
  const size_t m = std::min(std::max(n / 8, kNearTrialMin), kNearTrialMax);
  if (2 * m > n) return true;
  const std::vector<uint32_t> near = nearest_points(q, valid, 1, m);
  std::vector<std::vector<uint8_t>> heads;
  for (size_t a = 0; a < specs.size(); ++a) {
    const size_t bpp = static_cast<size_t>(specs[a].size) * static_cast<size_t>(specs[a].count);
    heads.emplace_back(data[a].begin(), data[a].begin() + static_cast<std::ptrdiff_t>(m * bpp));
  }
  Lane l;
  for (size_t a = 0; a < specs.size(); ++a) {
    const AttrSpec& s = specs[a];
    if (is_colour_field(s)) return true;
    bool helps = false;
    for (size_t j = 0; j < static_cast<size_t>(s.count) && !helps; ++j) {
      make_lane(s, false, heads[a], m, j, &l);
      uint64_t with = 0, without = 0, quantum = 0;
      choose_predictor(l, valid, gaps, near.data(), 1, m, m, &with);
      choose_predictor(l, valid, gaps, nullptr, 1, m, m, &without);
      QuantumParams qp;
      if (choose_quantum(specs, heads, a, l, valid, ragged.xyz, nullptr, &qp, &quantum))
        without = std::min(without, quantum);
      if (choose_quantum(specs, heads, a, l, valid, ragged.xyz, near.data(), &qp, &quantum))
        with = std::min(with, quantum);
      helps = static_cast<double>(with) < 0.97 * static_cast<double>(without);
    }
    if (!helps) continue;
    const size_t size = static_cast<size_t>(s.size);
    const size_t coded_with =
        encode_predictive(specs, heads, a, valid, gaps, near.data(), 1, m, m, &ragged).size();
    const size_t coded_without =
        std::min(encode_predictive(specs, heads, a, valid, gaps, nullptr, 1, m, m, &ragged).size(),
                 lzma_transform(2, heads[a], size).size());
    if (static_cast<double>(coded_with) < 0.97 * static_cast<double>(coded_without)) return true;
  }
  return false;
}

// near_pays, or with the ragged run's memory (FieldTrials::near) the answer of its last trial in
// the kNearRest windows after it.
bool near_answer(const std::vector<AttrSpec>& specs, const std::vector<std::vector<uint8_t>>& data,
                 const uint8_t* valid, bool gaps, const int32_t* q, size_t n,
                 const RaggedFields& ragged) {
  FieldTrials::Near* m = ragged.trials ? &ragged.trials->near : nullptr;
  if (m && m->rest > 0) {
    --m->rest;
    return m->pays;
  }
  const bool pays = near_pays(specs, data, valid, gaps, q, n, ragged);
  if (m) *m = FieldTrials::Near{kNearRest, pays};
  return pays;
}

// The run's memory of the LZMA trials (FieldTrials::lzma_rest) for `fields` fields, or null.
FieldTrials* lzma_memory(const RaggedFields* ragged, size_t fields) {
  FieldTrials* t = ragged ? ragged->trials : nullptr;
  if (t) t->lzma_rest.resize(fields, 0);
  return t;
}
// Whether field a's LZMA transforms are tried in this window.
bool lzma_tried(const FieldTrials* t, size_t a) {
  return !t || t->lzma_rest[a] == 0;
}
// The memory after field a's codings in this window (`tried` as lzma_tried said; ratio: the
// largest of the codings' FieldCoder::code ratios).
void lzma_after(FieldTrials* t, size_t a, bool tried, double ratio) {
  if (!t) return;
  uint8_t& rest = t->lzma_rest[a];
  rest = !tried ? static_cast<uint8_t>(rest - 1) : ratio < kLzmaRestRatio ? kLzmaRest : uint8_t{0};
}

}  // namespace

bool is_colour_field(const AttrSpec& s) {
  return s.size == 4 && s.count == 1 && (s.type == 'F' || s.type == 'U') &&
         (s.name == "rgb" || s.name == "rgba");
}

bool has_unit_candidate(const std::vector<AttrSpec>& specs) {
  UnitRef refs[2];
  for (size_t a = 0; a < specs.size(); ++a)
    if (unit_candidate(specs, a, specs[a].count == 3 ? 2 : 0, refs)) return true;
  return false;
}

namespace {

// What every field of one window is coded with: the gap mask (a mask all set under predictors
// 10 to 13 when the window has none), the neighbours of 7.3 (found once), the shape and the
// choices encode_attributes was given.
struct FieldCoder {
  const std::vector<AttrSpec>& specs;
  const uint8_t* valid;
  bool gaps;
  std::vector<uint8_t> all_valid;
  std::vector<uint32_t> near;
  size_t frames, points, W;
  const RaggedFields* ragged;
  bool estimate, estimate_split;

  FieldCoder(const std::vector<AttrSpec>& s, const std::vector<std::vector<uint8_t>>& data,
             const uint8_t* v, size_t f, size_t p, size_t width, const int32_t* q, bool est,
             const RaggedFields* rf, bool est_split)
      : specs(s),
        valid(v),
        frames(f),
        points(p),
        ragged(rf),
        estimate(est),
        estimate_split(est_split) {
    const size_t n = frames * points;
    W = width ? width : std::max<size_t>(points, 1);
    gaps = valid && std::find(valid, valid + n, 0) != valid + n;
    // 7.3: the neighbours, found once for every lane (under a mask all set when there is none).
    if ((q && points > 1) || ragged) {
      if (!valid) all_valid.assign(n, 1);
      valid = valid ? valid : all_valid.data();
    }
    if (q && points > 1 && (!ragged || near_answer(specs, data, valid, gaps, q, points, *ragged)))
      near = nearest_points(q, valid, frames, points);
  }

  // Field a of data, coded by its smallest transform; without `lzma` by the predictive transforms
  // alone. *ratio (when not null): the predictive coding's size over the smallest LZMA
  // transform's, coded or estimated (0 when none was tried).
  std::vector<uint8_t> code(const std::vector<std::vector<uint8_t>>& data, size_t a,
                            bool lzma = true, double* ratio = nullptr) const {
    const size_t n = frames * points;
    const AttrSpec& s = specs[a];
    const size_t bytes = n * static_cast<size_t>(s.size) * static_cast<size_t>(s.count);
    if (data[a].size() != bytes)
      fail(ErrorCode::kInternal, "attributes",
           "field " + s.name + " does not hold frames x points values");
    std::vector<uint8_t> best =
        encode_predictive(specs, data, a, valid, gaps, near.empty() ? nullptr : near.data(), frames,
                          points, W, ragged);
    // LZMA of the byte planes (2) and, for elements of several bytes, of the bytes as they are
    // (3); in a window with gaps and valid points, the same of the valid points' values with
    // the gap points' values apart (4, 5; FORMAT.md 6.2): the smallest wins.
    if (ratio) *ratio = 0;
    if (!lzma) return best;
    const size_t size = static_cast<size_t>(s.size), pred = best.size();
    double least = std::numeric_limits<double>::infinity();  // LZMA's smallest, coded or estimated
    std::vector<uint8_t> at_valid, at_gaps;
    // An unorganized cloud's window with predictors 10 and 11 (FORMAT.md 13.5) skips transforms
    // 4 and 5: measured on the LiDAR sequences of docs/BENCHMARKS.md, they then won on one of
    // five (by 1 % of the fields' bytes) for a third of the encode time.
    const bool unorganized_near = !near.empty() && W >= points;
    if (gaps && !unorganized_near &&
        std::any_of(valid, valid + n, [](uint8_t v) { return v != 0; }))
      split_by_mask(data[a], valid, n, size * static_cast<size_t>(s.count), &at_valid, &at_gaps);
    const uint8_t last = !at_valid.empty() ? (size > 1 ? 5 : 4) : (size > 1 ? 3 : 2);
    const bool split = !at_valid.empty();
    double est = least, est_split = least;
    const uint8_t tried = (estimate && !split) || estimate_split
                              ? lzma_worth_trying(data[a], size, pred, &est)
                              : 0xFF;
    // Of 4 and 5 (estimate_split): the one lzma_worth_trying takes for the valid values.
    const uint8_t tried_split =
        estimate_split && split ? lzma_worth_trying(at_valid, size, pred, &est_split) : 0xFF;
    if (tried == 0) least = est;
    if (tried_split == 0) least = std::min(least, est_split);
    for (uint8_t t = 2; bytes > 0 && t <= last; ++t) {
      if (t == 3 && size == 1) continue;
      if (t <= 3 && tried != 0xFF && t != tried) continue;
      if (t >= 4 && tried_split != 0xFF && t != tried_split + 2) continue;
      ByteWriter alt;
      alt.u8(t);
      size_t m = 0;  // the size field
      if (t <= 3) {
        const std::vector<uint8_t> z = lzma_transform(t, data[a], size);
        m = z.size();
        alt.varint(z.size());
        alt.bytes(z);
      } else {
        const std::vector<uint8_t> za =
            t == 4 ? lzma2_encode_fast(to_planes(at_valid, size).data(), at_valid.size())
                   : lzma2_encode_fast(at_valid.data(), at_valid.size());
        const std::vector<uint8_t> zb = lzma2_encode_fast(at_gaps.data(), at_gaps.size());
        ByteWriter body;
        body.varint(za.size());
        body.bytes(za);
        body.bytes(zb);
        m = body.size();
        alt.varint(body.size());
        alt.bytes(body.buffer());
      }
      least = std::min(least, static_cast<double>(m));
      if (alt.size() < best.size() && bytes <= kMaxSymbolsPerByte * m)
        best = std::move(alt.buffer());
    }
    if (ratio && least > 0) *ratio = static_cast<double>(pred) / least;
    return best;
  }
};

}  // namespace

std::vector<uint8_t> encode_attributes(const std::vector<AttrSpec>& specs,
                                       const std::vector<std::vector<uint8_t>>& data,
                                       const uint8_t* valid, size_t frames, size_t points,
                                       size_t width, const int32_t* q, bool estimate,
                                       const RaggedFields* ragged, bool estimate_split) {
  const FieldCoder coder(specs, data, valid, frames, points, width, q, estimate, ragged,
                         estimate_split);
  FieldTrials* trials = lzma_memory(ragged, specs.size());
  ByteWriter w;
  for (size_t a : coding_order(specs, ragged != nullptr)) {
    const bool lzma = lzma_tried(trials, a);
    double ratio = 0;
    w.bytes(coder.code(data, a, lzma, &ratio));
    lzma_after(trials, a, lzma, ratio);
  }
  return std::move(w.buffer());
}

bool quantise_field(const AttrSpec& s, double bound, std::vector<uint8_t>* bytes) {
  if (!(bound > 0) || s.type != 'F') return false;
  const double step = 2 * bound;
  bool moved = false;
  for (size_t k = 0; k + static_cast<size_t>(s.size) <= bytes->size();
       k += static_cast<size_t>(s.size)) {
    uint8_t* at = bytes->data() + k;
    if (s.size == 4) {
      float v;
      std::memcpy(&v, at, 4);
      if (!std::isfinite(v)) continue;
      const float q = static_cast<float>(std::round(static_cast<double>(v) / step) * step);
      if (q == v || std::fabs(static_cast<double>(q) - static_cast<double>(v)) > bound) continue;
      std::memcpy(at, &q, 4);
    } else {
      double v;
      std::memcpy(&v, at, 8);
      if (!std::isfinite(v)) continue;
      const double q = std::round(v / step) * step;
      if (q == v || std::fabs(q - v) > bound) continue;
      std::memcpy(at, &q, 8);
    }
    moved = true;
  }
  return moved;
}

std::vector<double> attribute_bounds(const PCDExtra& layout) {
  std::vector<double> bounds;
  if (layout.field_bounds.empty()) return bounds;
  for (size_t i = 0; i < layout.fields.size(); ++i) {
    const std::string& name = layout.fields[i].name;
    if (name == "x" || name == "y" || name == "z") continue;
    bounds.push_back(i < layout.field_bounds.size() ? layout.field_bounds[i] : 0.0);
  }
  return bounds;
}

std::vector<uint8_t> encode_attributes_within(const std::vector<AttrSpec>& specs,
                                              const std::vector<double>& bounds,
                                              std::vector<std::vector<uint8_t>>* data,
                                              const uint8_t* valid, size_t frames, size_t points,
                                              size_t width, const int32_t* q, bool estimate,
                                              const RaggedFields* ragged, bool estimate_split) {
  const FieldCoder coder(specs, *data, valid, frames, points, width, q, estimate, ragged,
                         estimate_split);
  FieldTrials* trials = lzma_memory(ragged, specs.size());
  ByteWriter w;
  for (size_t a : coding_order(specs, ragged != nullptr)) {
    const bool lzma = lzma_tried(trials, a);
    double ratio = 0, moved_ratio = 0;  // (FieldCoder::code's)
    std::vector<uint8_t> best = coder.code(*data, a, lzma, &ratio);
    const double bound = a < bounds.size() ? bounds[a] : 0;
    std::vector<uint8_t> moved;  // field a with its values quantised (FORMAT.md 16.4)
    if (bound > 0 && specs[a].type == 'F') moved = (*data)[a];
    if (!moved.empty() && quantise_field(specs[a], bound, &moved)) {
      (*data)[a].swap(moved);  // the later fields' predictors read field a as the decoder will
      std::vector<uint8_t> coded = coder.code(*data, a, lzma, &moved_ratio);
      if (coded.size() < best.size())
        best.swap(coded);
      else
        (*data)[a].swap(moved);  // exact, which is within any bound, and not larger
    }
    lzma_after(trials, a, lzma, std::max(ratio, moved_ratio));
    w.bytes(best);
  }
  return std::move(w.buffer());
}

}  // namespace capz
