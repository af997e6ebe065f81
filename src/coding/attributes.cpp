// ATTR (docs/FORMAT.md 5.3): lanes of ordered integers, one of five predictors per lane,
// residuals through the analog coder's entropy stage (4.2.5).
#include "coding/attributes.h"

#include <algorithm>
#include <cstring>

#include "capz/error.h"
#include "coding/analog/analog_entropy.h"
#include "coding/bytes.h"
#include "coding/entropy.h"

namespace capz {

namespace {

constexpr int kPredictors = 5;

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

// The predictor whose residuals have the smallest sum of bit lengths (ties: the lowest).
int choose_predictor(const Lane& l, size_t frames, size_t N, size_t W) {
  const uint64_t mask = mask_of(l.bits);
  uint64_t best_cost = ~uint64_t{0};
  int best = 0;
  for (int id = 0; id < kPredictors; ++id) {
    uint64_t cost = 0;
    for (size_t f = 0; f < frames; ++f) {
      const uint64_t* cur = l.u.data() + f * N;
      const uint64_t* prev = f ? cur - N : nullptr;
      for (size_t p = 0; p < N; ++p) {
        const int64_t r =
            signed_residual((cur[p] - predict(id, cur, prev, p, W, mask)) & mask, l.bits);
        cost += bit_length(analog::zigzag64(r));
      }
    }
    if (cost < best_cost) {
      best_cost = cost;
      best = id;
    }
  }
  return best;
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

std::vector<uint8_t> encode_attributes(const std::vector<AttrSpec>& specs,
                                       const std::vector<std::vector<uint8_t>>& data, size_t frames,
                                       size_t points, size_t width) {
  const size_t n = frames * points;
  const size_t W = width ? width : std::max<size_t>(points, 1);
  ByteWriter w;
  for (size_t a = 0; a < specs.size(); ++a) {
    if (data[a].size() != n * specs[a].size * specs[a].count)
      fail(ErrorCode::kInternal, "attributes",
           "field " + specs[a].name + " does not hold frames x points values");
    w.u8(is_colour_field(specs[a]) ? 1 : 0);
  }
  IntEncoder enc(analog::kAnalogContexts);
  IntEncoder::Cursor c = enc.cursor();
  Lane l;
  for (size_t a = 0; a < specs.size(); ++a) {
    const bool colour = is_colour_field(specs[a]);
    for (size_t j = 0; j < lane_count(specs[a], colour); ++j) {
      make_lane(specs[a], colour, data[a], n, j, &l);
      const int pred = choose_predictor(l, frames, points, W);
      w.u8(static_cast<uint8_t>(pred));
      const uint64_t mask = mask_of(l.bits);
      analog::Magnitude mag;
      int prev_nb = 0;
      for (size_t f = 0; f < frames; ++f) {
        const uint64_t* cur = l.u.data() + f * points;
        const uint64_t* prev = f ? cur - points : nullptr;
        for (size_t p = 0; p < points; ++p) {
          const int64_t r =
              signed_residual((cur[p] - predict(pred, cur, prev, p, W, mask)) & mask, l.bits);
          if (l.float_residuals)
            analog::put_float_residual(&c, &prev_nb, r);
          else
            analog::put_residual(&c, &mag, static_cast<int32_t>(r));
        }
      }
    }
  }
  enc.commit(c);
  w.bytes(enc.finish());
  return std::move(w.buffer());
}

void decode_attributes(const uint8_t* data, size_t size, const std::vector<AttrSpec>& specs,
                       size_t frames, size_t points, size_t width,
                       std::vector<std::vector<uint8_t>>* out, const std::string& what) {
  ByteReader r(data, size, what);
  const size_t n = frames * points;
  const size_t W = width ? width : std::max<size_t>(points, 1);
  std::vector<uint8_t> colour(specs.size());
  size_t L = 0;
  for (size_t a = 0; a < specs.size(); ++a) {
    const uint8_t t = r.u8();
    if (t > 1 || (t == 1 && (specs[a].size != 4 || specs[a].count != 1)))
      fail(ErrorCode::kCorrupt, what,
           "bad transform " + std::to_string(t) + " of field " + specs[a].name);
    colour[a] = t;
    L += lane_count(specs[a], t == 1);
  }
  // Every value costs at least 1/2900 byte of the payload: check before allocating.
  if (n != 0 && L > kMaxSymbolsPerByte * size / n)
    fail(ErrorCode::kCorrupt, what, "attribute window larger than its chunk can hold");
  std::vector<int> pred(L);
  for (size_t k = 0; k < L; ++k) {
    const uint8_t id = r.u8();
    if (id >= kPredictors)
      fail(ErrorCode::kCorrupt, what, "unknown attribute predictor " + std::to_string(id));
    pred[k] = id;
  }
  IntDecoder dec(data + r.offset(), r.remaining(), analog::kAnalogContexts, what);
  IntDecoder::Cursor c = dec.cursor();
  out->resize(specs.size());
  Lane l, col[4];
  size_t k = 0;
  for (size_t a = 0; a < specs.size(); ++a) {
    const AttrSpec& s = specs[a];
    std::vector<uint8_t>& bytes = (*out)[a];
    bytes.assign(n * static_cast<size_t>(s.size) * static_cast<size_t>(s.count), 0);
    for (size_t j = 0; j < lane_count(s, colour[a] == 1); ++j, ++k) {
      Lane& cur_lane = colour[a] ? col[j] : l;
      cur_lane.bits = lane_bits(s, colour[a] == 1, j);
      cur_lane.float_residuals = !colour[a] && (s.type == 'F' || cur_lane.bits == 64);
      cur_lane.u.resize(n);
      const uint64_t mask = mask_of(cur_lane.bits);
      analog::Magnitude mag;
      int prev_nb = 0;
      for (size_t f = 0; f < frames; ++f) {
        uint64_t* cur = cur_lane.u.data() + f * points;
        const uint64_t* prev = f ? cur - points : nullptr;
        for (size_t p = 0; p < points; ++p) {
          const int64_t res = cur_lane.float_residuals ? analog::get_float_residual(&c, &prev_nb)
                                                       : analog::get_residual(&c, &mag);
          cur[p] = (predict(pred[k], cur, prev, p, W, mask) + static_cast<uint64_t>(res)) & mask;
        }
      }
      if (!colour[a]) store_lane(s, cur_lane, n, j, &bytes);
    }
    if (colour[a]) {
      uint64_t v[4];
      for (size_t i = 0; i < n; ++i) {
        for (int j = 0; j < 4; ++j) v[j] = col[j].u[i];
        colour_inverse(v, bytes.data() + i * 4);
      }
    }
  }
  dec.commit(c);
  if (!dec.at_end()) fail(ErrorCode::kCorrupt, what, "attribute block has bytes left over");
}

}  // namespace capz
