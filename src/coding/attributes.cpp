// ATTR (docs/FORMAT.md 5.3, 6.1, 7.3): per attribute, lanes of ordered integers with one of nine
// predictors per lane (ten in a 6.x stream: 9 completes a unit vector's component from two
// other elements; twelve in a 7.x stream: 10 and 11 read the point's nearest earlier point in
// space) and residuals through the analog coder's entropy stage (4.2.5), or LZMA2 of
// its byte planes or bytes (in a 6.x stream also of its valid points' values apart from its gap
// points', 6.2), whichever is smaller.
#include "coding/attributes.h"

#include <algorithm>
#include <array>
#include <cmath>
#include <cstring>

#include "capz/error.h"
#include "coding/analog/analog_entropy.h"
#include "coding/bytes.h"
#include "coding/entropy.h"
#include "coding/lzma_block.h"
#include "coding/neighbours.h"

namespace capz {

namespace {

constexpr int kPredictors = 9;  // ids 0..8 (5.3); 9 (6.1) is handled apart
constexpr int kUnitPredictor = 9;
constexpr int kNearPredictor = 10;        // 7.3: the nearest earlier point's value
constexpr int kNearChangePredictor = 11;  // 7.3: its change since the previous frame, carried over
constexpr int kSignContext = analog::kParamContext;  // 81, 82: unused elsewhere in ATTR

// One lane: frames x points ordered values of `bits` bits.
struct Lane {
  int bits = 8;
  bool float_residuals = false;  // F elements and 64-bit lanes: float residual coding
  std::vector<uint64_t> u;
};

uint64_t mask_of(int bits) {
  return bits >= 64 ? ~uint64_t{0} : (uint64_t{1} << bits) - 1;
}

uint64_t load_le(const uint8_t* p, int size) {
  uint64_t v = 0;
  for (int i = 0; i < size; ++i) v |= static_cast<uint64_t>(p[i]) << (8 * i);
  return v;
}
void store_le(uint8_t* p, int size, uint64_t v) {
  for (int i = 0; i < size; ++i) p[i] = static_cast<uint8_t>(v >> (8 * i));
}

// Element bits <-> ordered lane value (FORMAT.md 5.3).
uint64_t to_ordered(uint64_t v, char type, int bits) {
  const uint64_t top = uint64_t{1} << (bits - 1);
  if (type == 'I') return v ^ top;
  if (type == 'F') return (v & top) ? (~v & mask_of(bits)) : (v | top);
  return v;
}
uint64_t from_ordered(uint64_t u, char type, int bits) {
  const uint64_t top = uint64_t{1} << (bits - 1);
  if (type == 'I') return u ^ top;
  if (type == 'F') return (u & top) ? (u & ~top) : (~u & mask_of(bits));
  return u;
}

// LOCO-I's median predictor, on values of a lane (a + b - c taken modulo 2^bits).
uint64_t med(uint64_t a, uint64_t b, uint64_t c, uint64_t mask) {
  const uint64_t lo = std::min(a, b), hi = std::max(a, b);
  if (c >= hi) return lo;
  if (c <= lo) return hi;
  return (a + b - c) & mask;
}

// S: the spatial prediction of point p of one frame (`row` its values; 0 at point 0).
uint64_t spatial(const uint64_t* row, size_t p, size_t W, uint64_t mask) {
  const size_t col = p % W;
  const bool has_left = col > 0, has_up = p >= W;
  if (has_left && has_up) return med(row[p - 1], row[p - W], row[p - W - 1], mask);
  if (has_left) return row[p - 1];
  if (has_up) return row[p - W];
  return 0;
}

// The prediction of u[f][p]: cur is frame f, prev frame f - 1 (nullptr in the window's first).
uint64_t predict(int id, const uint64_t* cur, const uint64_t* prev, size_t p, size_t W,
                 uint64_t mask) {
  switch (id) {
    case 0:
      return 0;
    case 1:
      if (p > 0) return cur[p - 1];
      return prev ? prev[0] : 0;
    case 2:
      if (prev) return prev[p];
      if (p > 0) return cur[p - 1];
      return 0;
    case 3:
      return spatial(cur, p, W, mask);
    default:
      if (!prev) return spatial(cur, p, W, mask);
      return (prev[p] + spatial(cur, p, W, mask) - spatial(prev, p, W, mask)) & mask;
  }
}

int64_t signed_residual(uint64_t r, int bits) {
  if (bits >= 64) return static_cast<int64_t>(r);
  const uint64_t top = uint64_t{1} << (bits - 1);
  return (r & top) ? static_cast<int64_t>(r) - static_cast<int64_t>(uint64_t{1} << bits)
                   : static_cast<int64_t>(r);
}

uint32_t bit_length(uint64_t u) {
  return u == 0 ? 0 : 64u - static_cast<uint32_t>(__builtin_clzll(u));
}

size_t lane_count(const AttrSpec& s, bool colour) {
  return colour ? 4 : static_cast<size_t>(s.count);
}

int lane_bits(const AttrSpec& s, bool colour, size_t j) {
  if (colour) return (j == 1 || j == 2) ? 9 : 8;
  return 8 * s.size;
}

// YCoCg-R of one packed colour (bytes B G R A): Y, Co + 255, Cg + 255, A.
void colour_forward(const uint8_t* e, uint16_t out[4]) {
  const int B = e[0], G = e[1], R = e[2], A = e[3];
  const int co = R - B;
  const int t = B + (co >> 1);
  const int cg = G - t;
  out[0] = static_cast<uint16_t>(t + (cg >> 1));
  out[1] = static_cast<uint16_t>(co + 255);
  out[2] = static_cast<uint16_t>(cg + 255);
  out[3] = static_cast<uint16_t>(A);
}
void colour_inverse(const uint64_t in[4], uint8_t* e) {
  const int y = static_cast<int>(in[0]);
  const int co = static_cast<int>(in[1]) - 255;
  const int cg = static_cast<int>(in[2]) - 255;
  const int t = y - (cg >> 1);
  const int G = cg + t;
  const int B = t - (co >> 1);
  const int R = B + co;
  e[0] = static_cast<uint8_t>(B);
  e[1] = static_cast<uint8_t>(G);
  e[2] = static_cast<uint8_t>(R);
  e[3] = static_cast<uint8_t>(in[3]);
}

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
  for (size_t i = 0; i < n; ++i)
    l->u[i] = to_ordered(load_le(bytes.data() + (i * count + j) * size, s.size), s.type, l->bits);
}

// Lane j of a plain attribute into its bytes (sized n x count x size).
void store_lane(const AttrSpec& s, const Lane& l, size_t n, size_t j, std::vector<uint8_t>* bytes) {
  const size_t count = static_cast<size_t>(s.count), size = static_cast<size_t>(s.size);
  for (size_t i = 0; i < n; ++i)
    store_le(bytes->data() + (i * count + j) * size, s.size, from_ordered(l.u[i], s.type, l.bits));
}

// The prediction of a valid point under predictors 5..8 (FORMAT.md 5.3) and 10, 11 (7.3, n the
// point's nearest earlier point, kNoPoint for none): only valid points count; `last` is the
// lane's previous valid value.
uint64_t predict_masked(int id, const uint64_t* cur, const uint64_t* prev, const uint8_t* vcur,
                        const uint8_t* vprev, size_t p, size_t W, uint64_t mask, uint64_t last,
                        uint32_t n) {
  const bool has_prev = prev && vprev[p];
  if (id >= kNearPredictor) {
    if (n == kNoPoint || !vcur[n]) return id == kNearPredictor || !has_prev ? last : prev[p];
    if (id == kNearPredictor || !has_prev || !vprev[n]) return cur[n];
    return (cur[n] + prev[p] - prev[n]) & mask;
  }
  const bool has_left = p % W > 0 && vcur[p - 1];
  switch (id) {
    case 5:
      return last;
    case 6:
      return has_prev ? prev[p] : last;
    case 7: {
      const bool has_up = p >= W && vcur[p - W];
      if (has_left && has_up && p % W > 0 && vcur[p - W - 1])
        return med(cur[p - 1], cur[p - W], cur[p - W - 1], mask);
      if (has_left) return cur[p - 1];
      if (has_up) return cur[p - W];
      return last;
    }
    default:
      if (has_prev && has_left && vprev[p - 1]) return (prev[p] + cur[p - 1] - prev[p - 1]) & mask;
      return has_prev ? prev[p] : last;
  }
}

// Walks lane `u` (frames x N values) in coding order under predictor `id`, calling
// step(&value, prediction, gap) for each value: the encoder reads the value, the decoder sets
// it. valid: the window's gap mask (frames x N), used by predictors 5..8, 10 and 11; near: the
// nearest earlier point of each point (FORMAT.md 7.3), used by 10 and 11.
template <typename Step>
void walk_lane(int id, std::vector<uint64_t>* lane, const uint8_t* valid, const uint32_t* near,
               size_t frames, size_t N, size_t W, uint64_t mask, Step&& step) {
  uint64_t last = 0, last_gap = 0;
  const bool masked = id >= 5;
  for (size_t f = 0; f < frames; ++f) {
    uint64_t* cur = lane->data() + f * N;
    const uint64_t* prev = f ? cur - N : nullptr;
    const uint8_t* vcur = masked ? valid + f * N : nullptr;
    const uint8_t* vprev = masked && f ? vcur - N : nullptr;
    for (size_t p = 0; p < N; ++p) {
      if (!masked) {
        step(&cur[p], predict(id, cur, prev, p, W, mask), false);
      } else if (!vcur[p]) {
        step(&cur[p], last_gap, true);
        last_gap = cur[p];
      } else {
        step(&cur[p],
             predict_masked(id, cur, prev, vcur, vprev, p, W, mask, last,
                            id >= kNearPredictor ? near[p] : kNoPoint),
             false);
        last = cur[p];
      }
    }
  }
}

// The predictor whose residuals have the smallest sum of bit lengths (ties: the lowest);
// 5..8 only with a gap mask that has gaps, 10 and 11 only with the points' nearest earlier
// points (near; valid then holds a mask, all set when the window has no gaps).
int choose_predictor(Lane& l, const uint8_t* valid, bool gaps, const uint32_t* near, size_t frames,
                     size_t N, size_t W, uint64_t* cost_out) {
  const uint64_t mask = mask_of(l.bits);
  uint64_t best_cost = ~uint64_t{0};
  int best = 0;
  const int ids[] = {0, 1, 2, 3, 4, 5, 6, 7, 8, kNearPredictor, kNearChangePredictor};
  for (int id : ids) {
    if ((id >= 5 && id <= 8 && !gaps) || (id >= kNearPredictor && !near)) continue;
    uint64_t cost = 0;
    walk_lane(id, &l.u, valid, near, frames, N, W, mask, [&](uint64_t* v, uint64_t pred, bool) {
      cost += bit_length(analog::zigzag64(signed_residual((*v - pred) & mask, l.bits)));
    });
    if (cost < best_cost) {
      best_cost = cost;
      best = id;
    }
  }
  *cost_out = best_cost;
  return best;
}

// A float32 element referenced by predictor 9 (FORMAT.md 6.1): element `element` of attribute
// `attribute`, as its bytes (frames x points x count elements).
struct UnitRef {
  size_t attribute = 0, element = 0;
};

float load_f32(const std::vector<uint8_t>& bytes, size_t i, size_t count, size_t k) {
  const uint32_t u = static_cast<uint32_t>(load_le(bytes.data() + (i * count + k) * 4, 4));
  float v;
  std::memcpy(&v, &u, 4);
  return v;
}
uint32_t f32_bits(float v) {
  uint32_t u;
  std::memcpy(&u, &v, 4);
  return u;
}

// Predictor 9's prediction of one value from x and y: completable (both finite): the ordered
// float32 of sqrt(max((1 - x*x) - y*y, 0)) with sign bit `sign`; otherwise the ordered bits of
// x when x is not finite, else of y. The squares of float32 values are exact in binary64, so a
// fused multiply-add gives the same t.
uint64_t unit_prediction(float x, float y, bool completable, uint32_t sign) {
  if (!completable) return to_ordered(f32_bits(std::isfinite(x) ? y : x), 'F', 32);
  const double dx = x, dy = y;
  const double t = (1.0 - dx * dx) - dy * dy;
  const float m = static_cast<float>(std::sqrt(t > 0 ? t : 0.0));
  return to_ordered(f32_bits(m) | (sign << 31), 'F', 32);
}

// The references predictor 9 may use for lane `j` of attribute `a` (FORMAT.md 6.1, how the
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

// Walks a predictor-9 lane in coding order: step(&value, x, y, completable) per value, x and y
// the referenced elements (decoded before this lane).
template <typename Step>
void walk_unit(std::vector<uint64_t>* lane, const std::vector<AttrSpec>& specs,
               const std::vector<std::vector<uint8_t>>& data, const UnitRef refs[2], Step&& step) {
  const std::vector<uint8_t>& ba = data[refs[0].attribute];
  const std::vector<uint8_t>& bb = data[refs[1].attribute];
  const size_t ca = static_cast<size_t>(specs[refs[0].attribute].count);
  const size_t cb = static_cast<size_t>(specs[refs[1].attribute].count);
  for (size_t i = 0; i < lane->size(); ++i) {
    const float x = load_f32(ba, i, ca, refs[0].element);
    const float y = load_f32(bb, i, cb, refs[1].element);
    step(&(*lane)[i], x, y, std::isfinite(x) && std::isfinite(y));
  }
}

// Cost of a predictor-9 lane as choose_predictor counts it: residual bit lengths plus one bit
// per completable value (its sign).
uint64_t unit_cost(Lane& l, const std::vector<AttrSpec>& specs,
                   const std::vector<std::vector<uint8_t>>& data, const UnitRef refs[2]) {
  uint64_t cost = 0;
  walk_unit(&l.u, specs, data, refs, [&](uint64_t* v, float x, float y, bool completable) {
    const uint32_t sign = static_cast<uint32_t>(from_ordered(*v, 'F', 32) >> 31);
    const uint64_t pred = unit_prediction(x, y, completable, sign);
    cost += bit_length(analog::zigzag64(signed_residual((*v - pred) & 0xFFFFFFFFu, 32))) +
            (completable ? 1 : 0);
  });
  return cost;
}

// Entropy state of one lane: for valid points and (predictors 5..8) for gap points.
struct LaneState {
  analog::Magnitude mag[2];
  int prev_nb[2] = {0, 0};
};

// Byte planes of n elements of s bytes: byte 0 of every element, then byte 1, ...
std::vector<uint8_t> to_planes(const std::vector<uint8_t>& b, size_t s) {
  const size_t n = s ? b.size() / s : 0;
  std::vector<uint8_t> out(b.size());
  for (size_t k = 0; k < s; ++k)
    for (size_t i = 0; i < n; ++i) out[k * n + i] = b[i * s + k];
  return out;
}
std::vector<uint8_t> from_planes(const std::vector<uint8_t>& planes, size_t s) {
  const size_t n = s ? planes.size() / s : 0;
  std::vector<uint8_t> out(planes.size());
  for (size_t k = 0; k < s; ++k)
    for (size_t i = 0; i < n; ++i) out[i * s + k] = planes[k * n + i];
  return out;
}

// The elements (bpp bytes a point) of the valid points, then of the gap points, each in frame
// and point order (FORMAT.md 6.2), and back.
void split_by_mask(const std::vector<uint8_t>& b, const uint8_t* valid, size_t n, size_t bpp,
                   std::vector<uint8_t>* at_valid, std::vector<uint8_t>* at_gaps) {
  at_valid->clear();
  at_gaps->clear();
  for (size_t i = 0; i < n; ++i) {
    std::vector<uint8_t>* to = valid[i] ? at_valid : at_gaps;
    to->insert(to->end(), b.begin() + static_cast<long>(i * bpp),
               b.begin() + static_cast<long>((i + 1) * bpp));
  }
}
void merge_by_mask(const std::vector<uint8_t>& at_valid, const std::vector<uint8_t>& at_gaps,
                   const uint8_t* valid, size_t n, size_t bpp, std::vector<uint8_t>* b) {
  b->resize(n * bpp);
  size_t iv = 0, ig = 0;
  for (size_t i = 0; i < n; ++i) {
    const uint8_t* from = valid[i] ? at_valid.data() + (iv++) * bpp : at_gaps.data() + (ig++) * bpp;
    std::memcpy(b->data() + i * bpp, from, bpp);
  }
}

// One attribute, predictively (transforms 0 and 1): transform, predictors, size, block.
// v6: a 6.x stream (predictor 9 allowed).
std::vector<uint8_t> encode_predictive(const std::vector<AttrSpec>& specs,
                                       const std::vector<std::vector<uint8_t>>& data, size_t a,
                                       const uint8_t* valid, bool gaps, const uint32_t* near,
                                       size_t frames, size_t points, size_t W, bool v6) {
  const AttrSpec& s = specs[a];
  const std::vector<uint8_t>& bytes = data[a];
  const size_t n = frames * points;
  const bool colour = is_colour_field(s);
  ByteWriter w;
  w.u8(colour ? 1 : 0);
  IntEncoder enc(analog::kAnalogContexts);
  IntEncoder::Cursor c = enc.cursor();
  Lane l;
  for (size_t j = 0; j < lane_count(s, colour); ++j) {
    make_lane(s, colour, bytes, n, j, &l);
    uint64_t cost = 0;
    int pred = choose_predictor(l, valid, gaps, near, frames, points, W, &cost);
    UnitRef refs[2];
    if (v6 && !colour && unit_candidate(specs, a, j, refs)) {
      const uint64_t u = unit_cost(l, specs, data, refs);
      if (u < cost || (u == cost && pred > kUnitPredictor)) pred = kUnitPredictor;
    }
    w.u8(static_cast<uint8_t>(pred));
    LaneState st;
    if (pred == kUnitPredictor) {
      for (const UnitRef& r : refs) {
        w.varint(r.attribute);
        w.varint(r.element);
      }
      int q = 0;  // sign bit of the previous completable value
      walk_unit(&l.u, specs, data, refs, [&](uint64_t* v, float x, float y, bool completable) {
        const uint32_t sign = static_cast<uint32_t>(from_ordered(*v, 'F', 32) >> 31);
        if (completable) {
          c.put(sign, kSignContext + q);
          q = static_cast<int>(sign);
        }
        const uint64_t p = unit_prediction(x, y, completable, sign);
        analog::put_float_residual(&c, &st.prev_nb[completable ? 0 : 1],
                                   signed_residual((*v - p) & 0xFFFFFFFFu, 32));
      });
      continue;
    }
    const uint64_t mask = mask_of(l.bits);
    walk_lane(pred, &l.u, valid, near, frames, points, W, mask,
              [&](uint64_t* v, uint64_t p, bool gap) {
                const int64_t r = signed_residual((*v - p) & mask, l.bits);
                if (l.float_residuals)
                  analog::put_float_residual(&c, &st.prev_nb[gap], r);
                else
                  analog::put_residual(&c, &st.mag[gap], static_cast<int32_t>(r));
              });
  }
  enc.commit(c);
  const std::vector<uint8_t> block = enc.finish();
  w.varint(block.size());
  w.bytes(block);
  return std::move(w.buffer());
}

// Predictor 9's references of lane j of attribute a, read and checked (FORMAT.md 6.1).
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

// The nearest earlier point of every point of the window (FORMAT.md 7.3): exact squared
// distances of the POSW integers q (frames x points x 3) at the point's first valid frame.
std::vector<uint32_t> nearest_points(const int32_t* q, const uint8_t* valid, size_t frames,
                                     size_t points) {
  return nearest_earlier(q, valid, frames, points, 1, exact_distance);
}

}  // namespace

std::vector<AttrSpec> attribute_specs(const std::vector<PCDField>& fields) {
  std::vector<AttrSpec> out;
  for (const PCDField& f : fields)
    if (f.name != "x" && f.name != "y" && f.name != "z") out.push_back(f);
  return out;
}

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

std::vector<uint8_t> encode_attributes(const std::vector<AttrSpec>& specs,
                                       const std::vector<std::vector<uint8_t>>& data,
                                       const uint8_t* valid, size_t frames, size_t points,
                                       size_t width, bool v6, bool v7, const int32_t* q) {
  const size_t n = frames * points;
  const size_t W = width ? width : std::max<size_t>(points, 1);
  const bool gaps = valid && std::find(valid, valid + n, 0) != valid + n;
  // 7.3: the neighbours, found once for every lane (under a mask all set when there is none).
  std::vector<uint8_t> all_valid;
  std::vector<uint32_t> near;
  if (v7 && q && points > 1) {
    if (!valid) all_valid.assign(n, 1);
    valid = valid ? valid : all_valid.data();
    near = nearest_points(q, valid, frames, points);
  }
  ByteWriter w;
  for (size_t a = 0; a < specs.size(); ++a) {
    const AttrSpec& s = specs[a];
    const size_t bytes = n * static_cast<size_t>(s.size) * static_cast<size_t>(s.count);
    if (data[a].size() != bytes)
      fail(ErrorCode::kInternal, "attributes",
           "field " + s.name + " does not hold frames x points values");
    std::vector<uint8_t> best = encode_predictive(
        specs, data, a, valid, gaps, near.empty() ? nullptr : near.data(), frames, points, W, v6);
    // LZMA of the byte planes (2) and, for elements of several bytes, of the bytes as they are
    // (3); in a 6.x window with gaps and valid points, the same of the valid points' values
    // with the gap points' values apart (4, 5; FORMAT.md 6.2): the smallest wins.
    const size_t size = static_cast<size_t>(s.size);
    std::vector<uint8_t> at_valid, at_gaps;
    // An unorganized cloud's window with predictors 10 and 11 (FORMAT.md 7.3) skips transforms
    // 4 and 5: measured on the LiDAR sequences of docs/BENCHMARKS.md, they then won on one of
    // five (by 1 % of the fields' bytes) for a third of the encode time.
    const bool unorganized_near = !near.empty() && W >= points;
    if (v6 && gaps && !unorganized_near &&
        std::any_of(valid, valid + n, [](uint8_t v) { return v != 0; }))
      split_by_mask(data[a], valid, n, size * static_cast<size_t>(s.count), &at_valid, &at_gaps);
    const uint8_t last = !at_valid.empty() ? (size > 1 ? 5 : 4) : (size > 1 ? 3 : 2);
    for (uint8_t t = 2; bytes > 0 && t <= last; ++t) {
      if (t == 3 && size == 1) continue;
      ByteWriter alt;
      alt.u8(t);
      size_t m = 0;  // the size field
      if (t <= 3) {
        const std::vector<uint8_t> z =
            t == 2 ? lzma2_encode_fast(to_planes(data[a], size).data(), bytes)
                   : lzma2_encode_fast(data[a].data(), bytes);
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
      if (alt.size() < best.size() && bytes <= kMaxSymbolsPerByte * m)
        best = std::move(alt.buffer());
    }
    w.bytes(best);
  }
  return std::move(w.buffer());
}

// A field coded by LZMA2 (transforms 2-5, FORMAT.md 5.3, 6.2): its n points' bytes into *out.
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
  // 4, 5 (FORMAT.md 6.2): the valid points' values, then the gap points'.
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
void read_lane_predictors(ByteReader* in, const std::vector<AttrSpec>& specs, size_t a, bool colour,
                          bool v6, bool v7, bool have_q, const std::string& awhat,
                          std::vector<int>* pred, std::vector<std::array<UnitRef, 2>>* refs) {
  for (size_t j = 0; j < pred->size(); ++j) {
    const uint8_t id = in->u8();
    const bool near_id = id == kNearPredictor || id == kNearChangePredictor;
    if (id >= kPredictors && !(v6 && id == kUnitPredictor && !colour) && !(v7 && near_id))
      fail(ErrorCode::kCorrupt, awhat, "unknown predictor " + std::to_string(id));
    if (near_id && !have_q)
      fail(ErrorCode::kCorrupt, awhat,
           "predictor " + std::to_string(id) + " in a window without position integers");
    (*pred)[j] = id;
    if (id == kUnitPredictor) read_unit_refs(in, specs, a, j, (*refs)[j].data(), awhat);
  }
}

void decode_attributes(const uint8_t* data, size_t size, const std::vector<AttrSpec>& specs,
                       const uint8_t* valid, size_t frames, size_t points, size_t width,
                       std::vector<std::vector<uint8_t>>* out, const std::string& what, bool v6,
                       bool v7, const int32_t* q) {
  ByteReader r(data, size, what);
  const size_t n = frames * points;
  const size_t W = width ? width : std::max<size_t>(points, 1);
  out->assign(specs.size(), std::vector<uint8_t>());
  std::vector<uint8_t> all_valid;  // no mask given: every point valid (made when first needed)
  std::vector<uint32_t> near;      // 7.3: nearest earlier points (found when first needed)
  Lane l, col[4];
  for (size_t a = 0; a < specs.size(); ++a) {
    const AttrSpec& s = specs[a];
    const std::string awhat = what + " field " + s.name;
    const uint8_t t = r.u8();
    if (t > (v6 ? 5 : 3) || (t == 1 && (s.size != 4 || s.count != 1)))
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
    read_lane_predictors(&r, specs, a, colour, v6, v7, q != nullptr, awhat, &pred, &refs);
    const uint64_t m = r.count(1, "block size");
    if (n != 0 && lanes > kMaxSymbolsPerByte * m / n)
      fail(ErrorCode::kCorrupt, awhat, "field larger than its block can hold");
    const uint8_t* block = r.bytes(static_cast<size_t>(m));
    const bool uses_near = std::any_of(pred.begin(), pred.end(), [](int id) {
      return id == kNearPredictor || id == kNearChangePredictor;
    });
    if (!valid && all_valid.empty() &&
        (uses_near ||
         std::any_of(pred.begin(), pred.end(), [](int id) { return id >= 5 && id <= 8; })))
      all_valid.assign(n, 1);
    const uint8_t* mask_of_window = valid ? valid : all_valid.data();
    if (uses_near && near.empty()) near = nearest_points(q, mask_of_window, frames, points);
    IntDecoder dec(block, static_cast<size_t>(m), analog::kAnalogContexts, awhat);
    IntDecoder::Cursor c = dec.cursor();
    bytes.assign(n * bpp, 0);
    for (size_t j = 0; j < lanes; ++j) {
      Lane& cur_lane = colour ? col[j] : l;
      cur_lane.bits = lane_bits(s, colour, j);
      cur_lane.float_residuals = !colour && (s.type == 'F' || cur_lane.bits == 64);
      cur_lane.u.assign(n, 0);
      const uint64_t mask = mask_of(cur_lane.bits);
      LaneState st;
      if (pred[j] == kUnitPredictor) {
        int last_sign = 0;
        walk_unit(&cur_lane.u, specs, *out, refs[j].data(),
                  [&](uint64_t* v, float x, float y, bool completable) {
                    uint32_t sign = 0;
                    if (completable) {
                      int tok;
                      sign = c.get(kSignContext + last_sign, &tok);
                      if (sign > 1) fail(ErrorCode::kCorrupt, awhat, "bad sign symbol");
                      last_sign = static_cast<int>(sign);
                    }
                    const uint64_t p = unit_prediction(x, y, completable, sign);
                    const int64_t res =
                        analog::get_float_residual(&c, &st.prev_nb[completable ? 0 : 1]);
                    *v = (p + static_cast<uint64_t>(res)) & 0xFFFFFFFFu;
                  });
        store_lane(s, cur_lane, n, j, &bytes);
        continue;
      }
      walk_lane(pred[j], &cur_lane.u, mask_of_window, near.data(), frames, points, W, mask,
                [&](uint64_t* v, uint64_t p, bool gap) {
                  const int64_t res = cur_lane.float_residuals
                                          ? analog::get_float_residual(&c, &st.prev_nb[gap])
                                          : analog::get_residual(&c, &st.mag[gap]);
                  *v = (p + static_cast<uint64_t>(res)) & mask;
                });
      if (!colour) store_lane(s, cur_lane, n, j, &bytes);
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
