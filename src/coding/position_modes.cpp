// The encoder's choice of a predictor per point (position_modes.h).
#include "coding/position_modes.h"

#include <algorithm>
#include <cmath>
#include <cstring>
#include <memory>
#include <new>
#include <utility>

#if defined(__SSE2__)
#include <emmintrin.h>
#endif

#include "capz/error.h"
#include "coding/bytes.h"
#include "coding/entropy.h"
#include "coding/neighbours.h"
#include "coding/predict.h"

namespace capz {
namespace {

// An allocator whose value-less construct leaves the value uninitialised: the estimate's
// per-window arrays are written in full before they are read, and zero-filling them first cost
// about 1% of a compress (several MB per window).
template <typename T>
struct UninitAllocator : std::allocator<T> {
  template <typename U>
  struct rebind {
    using other = UninitAllocator<U>;
  };
  UninitAllocator() = default;
  template <typename U>
  UninitAllocator(const UninitAllocator<U>&) {}
  template <typename U>
  void construct(U* p) {
    ::new (static_cast<void*>(p)) U;
  }
  template <typename U, typename... Args>
  void construct(U* p, Args&&... args) {
    ::new (static_cast<void*>(p)) U(std::forward<Args>(args)...);
  }
};
template <typename T>
using Scratch = std::vector<T, UninitAllocator<T>>;

// What the estimate conditions a residual on, per point, axis and predictor: the previous token
// of the same axis (capped at 3). (Conditioning on scheme 3's zero-run phase as well changed
// the chosen predictors' coded sizes by under 0.5% and cost about a fifth of the encode time.)
struct PrevState {
  static constexpr int kContexts = 4;
  uint8_t ta = 0;
  int context() const { return ta < 3 ? ta : 3; }
  void update(int tok) { ta = static_cast<uint8_t>(tok); }
};

// tok[k] = token_of(zigzag(r[k])) for k < n; returns the raw bits plus 4 of the tokens >= 15
// (Hist::raw).
inline uint32_t tokens_scalar(const int32_t* r, size_t n, uint8_t* tok) {
  uint32_t raw = 0;
  for (size_t k = 0; k < n; ++k) {
    int nbits;
    const int t = token_of(zigzag(r[k]), &nbits);
    if (t >= 15) raw += static_cast<uint32_t>(nbits) + 4;
    tok[k] = static_cast<uint8_t>(t);
  }
  return raw;
}
// The same as tokens_scalar, for n <= 4096. With SSE2, eight values at a time: for
// 1 <= u < 2^24 the float of u is exact, with exponent e = floor(log2 u) and first mantissa bit
// that of u below its top bit, so its bits >> 22 are 2 (127 + e) + that bit = 254 + the token
// for u >= 2; max(that - 254, min(u, 1)) is the token of every u < 2^24 (u = 0 converts to 0,
// u = 1 to 254). Blocks of eight with a value of 2^24 or more take the scalar path.
inline uint32_t tokens_of(const int32_t* r, size_t n, uint8_t* tok) {
  uint32_t raw = 0;
  size_t k = 0;
#if defined(__SSE2__)
  const __m128i zero = _mm_setzero_si128(), one = _mm_set1_epi16(1);
  const __m128i bias = _mm_set1_epi16(254), fourteen = _mm_set1_epi16(14);
  const __m128i three = _mm_set1_epi16(3);
  __m128i acc = zero;  // 16-bit lanes: each adds at most n / 8 values of at most 26
  for (; k + 8 <= n; k += 8) {
    const __m128i d0 = _mm_loadu_si128(reinterpret_cast<const __m128i*>(r + k));
    const __m128i d1 = _mm_loadu_si128(reinterpret_cast<const __m128i*>(r + k + 4));
    const __m128i u0 = _mm_xor_si128(_mm_slli_epi32(d0, 1), _mm_srai_epi32(d0, 31));  // zigzag
    const __m128i u1 = _mm_xor_si128(_mm_slli_epi32(d1, 1), _mm_srai_epi32(d1, 31));
    const __m128i big = _mm_or_si128(_mm_srli_epi32(u0, 24), _mm_srli_epi32(u1, 24));
    if (_mm_movemask_epi8(_mm_cmpeq_epi32(big, zero)) != 0xFFFF) {
      raw += tokens_scalar(r + k, 8, tok + k);
      continue;
    }
    const __m128i f0 = _mm_srli_epi32(_mm_castps_si128(_mm_cvtepi32_ps(u0)), 22);
    const __m128i f1 = _mm_srli_epi32(_mm_castps_si128(_mm_cvtepi32_ps(u1)), 22);
    const __m128i t = _mm_max_epi16(_mm_sub_epi16(_mm_packs_epi32(f0, f1), bias),
                                    _mm_min_epi16(_mm_packs_epi32(u0, u1), one));
    const __m128i escaped = _mm_cmpgt_epi16(t, fourteen);
    acc = _mm_add_epi16(acc, _mm_and_si128(escaped, _mm_add_epi16(_mm_srli_epi16(t, 1), three)));
    _mm_storel_epi64(reinterpret_cast<__m128i*>(tok + k), _mm_packus_epi16(t, t));  // t <= 47
  }
  alignas(16) uint32_t lanes[4];
  _mm_store_si128(reinterpret_cast<__m128i*>(lanes), _mm_madd_epi16(acc, one));
  raw += lanes[0] + lanes[1] + lanes[2] + lanes[3];
#endif
  return raw + tokens_scalar(r + k, n - k, tok + k);
}

// idx[k] = 16 min(tok[k], 3) + min(tok[k + 1], 15), k < n: the count index of the value of
// token tok[k + 1] after one of token tok[k] (PrevState's context). tok has room for 16 bytes
// past n.
inline void count_indices(uint8_t* tok, size_t n, uint8_t* idx) {
  size_t k = 0;
#if defined(__SSE2__)
  std::memset(tok + n + 1, 0, 15);
  const __m128i c3 = _mm_set1_epi8(3), c15 = _mm_set1_epi8(15);
  for (; k < n; k += 16) {
    const __m128i a = _mm_loadu_si128(reinterpret_cast<const __m128i*>(tok + k));
    const __m128i b = _mm_loadu_si128(reinterpret_cast<const __m128i*>(tok + k + 1));
    const __m128i i = _mm_or_si128(_mm_slli_epi16(_mm_min_epu8(a, c3), 4), _mm_min_epu8(b, c15));
    _mm_storeu_si128(reinterpret_cast<__m128i*>(idx + k), i);
  }
#endif
  for (; k < n; ++k)
    idx[k] = static_cast<uint8_t>(16 * std::min<int>(tok[k], 3) + std::min<int>(tok[k + 1], 15));
}

// Token histogram of one point's residuals under the contexts of State, for estimating its coded
// size: the conditional order-0 entropy of the tokens (capped at 15) plus their raw bits.
template <typename State>
struct Hist {
  using StateType = State;
  static constexpr int kContexts = State::kContexts;
  uint16_t count[kContexts][16];  // a window codes at most 8192 x 3 values of a point
  uint32_t raw;  // raw bits (plus 4 for the escape) of tokens >= 15; those of the others follow
                 // from their counts
  void clear() { std::memset(this, 0, sizeof *this); }
  // Adds residual r in state st (then updated); returns r's token.
  int add(int32_t r, State* st) {
    int nbits;
    const int tok = token_of(zigzag(r), &nbits);
    ++count[st->context()][tok < 15 ? tok : 15];
    if (tok >= 15) raw += static_cast<uint32_t>(nbits) + 4;
    st->update(tok);
    return tok;
  }
  // Adds res[a][f], a = 0..2, for the frames f in [from, to) with valid[f], as add() would for
  // each axis's sequence from state st[a] (then updated): the hot loop of the estimate. In
  // chunks of the valid frames (gathered when the chunk has gaps): the tokens of a chunk first
  // (tokens_of), then each value's count index from its token and the one before (the
  // context), then the counts. Each axis counts into its own table until the end, so the three
  // increments of a frame are independent (one shared table makes a chain through memory when
  // a count repeats, as in a zero run).
  void add_run3(const int32_t* const res[3], const uint8_t* valid, size_t from, size_t to,
                State st[3]) {
    static_assert(kContexts == 4, "the count index is 16 x min(previous token, 3) + token");
    constexpr size_t kChunk = 512;
    uint16_t c[3][kContexts * 16] = {};
    alignas(16) int32_t gathered[3][kChunk];
    alignas(16) uint8_t tok[3][kChunk + 16];  // [0]: the previous token; [1..n]: the chunk's
    alignas(16) uint8_t idx[3][kChunk + 16];
    uint8_t prev[3] = {static_cast<uint8_t>(st[0].context()), static_cast<uint8_t>(st[1].context()),
                       static_cast<uint8_t>(st[2].context())};
    for (size_t f = from; f < to;) {
      const int32_t* in[3];
      size_t n = std::min(kChunk, to - f);
      if (!std::memchr(valid + f, 0, n)) {
        for (int a = 0; a < 3; ++a) in[a] = res[a] + f;
        f += n;
      } else {
        n = 0;
        for (; f < to && n < kChunk; ++f)
          if (valid[f]) {
            for (int a = 0; a < 3; ++a) gathered[a][n] = res[a][f];
            ++n;
          }
        for (int a = 0; a < 3; ++a) in[a] = gathered[a];
      }
      for (int a = 0; a < 3; ++a) {
        tok[a][0] = prev[a];
        raw += tokens_of(in[a], n, &tok[a][1]);
        count_indices(tok[a], n, idx[a]);
        prev[a] = tok[a][n];
      }
      for (size_t k = 0; k < n; ++k) {
        ++c[0][idx[0][k]];
        ++c[1][idx[1][k]];
        ++c[2][idx[2][k]];
      }
    }
    uint16_t* all = &count[0][0];
    for (int k = 0; k < kContexts * 16; ++k)
      all[k] = static_cast<uint16_t>(all[k] + c[0][k] + c[1][k] + c[2][k]);
    for (int a = 0; a < 3; ++a) st[a].update(std::min<int>(prev[a], 3));
  }
  // Estimated bits, in 1/16 bit units.
  uint64_t bits16() const {
    double e = 0;
    uint64_t bits = raw;
    for (int c = 0; c < kContexts; ++c) {
      uint32_t n = 0;
      for (int k = 4; k < 15; ++k)
        bits += uint64_t{count[c][k]} * static_cast<uint64_t>((k - 4) / 2 + 1);
      for (int k = 0; k < 16; ++k)
        if (count[c][k]) {
          n += count[c][k];
          e -= count[c][k] * std::log2(static_cast<double>(count[c][k]));
        }
      if (n) e += static_cast<double>(n) * std::log2(static_cast<double>(n));
    }
    return static_cast<uint64_t>(e * 16) + bits * 16;
  }
};
using TokenHist = Hist<PrevState>;

struct CostCoder {
  const int32_t* q;
  size_t points;
  TokenHist* hist;   // per point
  PrevState* state;  // per point and axis, reset at the start
  int32_t operator()(size_t i, int32_t pred, int, int* tok) {
    const size_t k = i % (points * 3);
    *tok = hist[k / 3].add(wrap_sub(q[i], pred), &state[k]);
    return q[i];
  }
};

// Candidate reference points of every point p: up to kRefCandidates points r < p nearest to p
// at p's first valid frame of the window, among those valid there (squared distance of the
// integers, in double; ties to the larger r; neighbours.h). kNoPoint marks unused slots.
std::vector<uint32_t> ref_candidates(const int32_t* q, const uint8_t* valid, size_t frames,
                                     size_t points, size_t* per_point) {
  constexpr size_t kRefCandidates = 16;
  *per_point = kRefCandidates;
  return nearest_earlier(q, valid, frames, points, kRefCandidates,
                         [](const int32_t* a, const int32_t* b) {
                           double dd = 0;
                           for (int k = 0; k < 3; ++k) {
                             const double x = static_cast<double>(a[k]) - static_cast<double>(b[k]);
                             dd += x * x;
                           }
                           return dd;
                         });
}

// Residuals res[f] = x[f] - prediction, f = 1 .. frames - 1, of a trajectory x (one axis of one
// point, frames contiguous, gaps filled) under predictor `mode` (0-2, 7-9): predict_one with
// stride 1, its mode fixed at compile time for the loop.
// From frame max(6, period + 1) on, every rule of predict_one takes its full form: that part
// of the loop passes a constant frame number past it, so it runs without a test per frame (and
// vectorises).
constexpr size_t kLate = static_cast<size_t>(-1) / 2;  // stands for any frame f >= 6

// res[f] = x[f] - predict_smooth(f, x + f, 1) for f in [from, to), from >= 6 (its full form).
// With SSE2, four frames at a time where the five differences of each from q[f-1] are within
// 2^25 in magnitude: the weighted sum n then fits int32 (|n| <= 38 x 2^25), so
// q1 + sign(n) ((|n| + 15) / 30) is computed in 32-bit lanes, the unsigned division by 30 as
// (u x 0x88888889) >> 36, exact for every u < 2^32 (what compilers emit for u / 30). Groups with
// a larger difference take predict_smooth.
void smooth_residuals(const int32_t* x, size_t from, size_t to, int32_t* res) {
  size_t f = from;
#if defined(__SSE2__)
  const __m128i magic = _mm_set1_epi32(static_cast<int>(0x88888889u));
  const __m128i fifteen = _mm_set1_epi32(15), zero = _mm_setzero_si128();
  for (; f + 4 <= to; f += 4) {
    auto at = [&](size_t j) {
      return _mm_loadu_si128(reinterpret_cast<const __m128i*>(x + f - j));
    };
    const __m128i q1 = at(1);
    const __m128i d2 = _mm_sub_epi32(at(2), q1), d3 = _mm_sub_epi32(at(3), q1);
    const __m128i d4 = _mm_sub_epi32(at(4), q1), d5 = _mm_sub_epi32(at(5), q1);
    const __m128i d6 = _mm_sub_epi32(at(6), q1);
    auto mag = [](__m128i d) { return _mm_xor_si128(d, _mm_srai_epi32(d, 31)); };  // |d| or |d|-1
    const __m128i big = _mm_or_si128(_mm_or_si128(mag(d2), mag(d3)),
                                     _mm_or_si128(_mm_or_si128(mag(d4), mag(d5)), mag(d6)));
    if (_mm_movemask_epi8(_mm_cmpeq_epi32(_mm_srli_epi32(big, 25), zero)) != 0xFFFF) {
      for (size_t g = f; g < f + 4; ++g) res[g] = wrap_sub(x[g], predict_smooth(kLate, x + g, 1));
      continue;
    }
    // n = 14 d2 + 8 d3 + 2 d4 - 4 d5 - 10 d6
    const __m128i n = _mm_sub_epi32(
        _mm_add_epi32(_mm_add_epi32(_mm_sub_epi32(_mm_slli_epi32(d2, 4), _mm_slli_epi32(d2, 1)),
                                    _mm_slli_epi32(d3, 3)),
                      _mm_slli_epi32(d4, 1)),
        _mm_add_epi32(_mm_add_epi32(_mm_slli_epi32(d5, 2), _mm_slli_epi32(d6, 3)),
                      _mm_slli_epi32(d6, 1)));
    const __m128i s = _mm_srai_epi32(n, 31);
    const __m128i u = _mm_add_epi32(_mm_sub_epi32(_mm_xor_si128(n, s), s), fifteen);
    const __m128i p02 = _mm_mul_epu32(u, magic);
    const __m128i p13 = _mm_mul_epu32(_mm_srli_epi64(u, 32), magic);
    const __m128i q =
        _mm_or_si128(_mm_srli_epi64(p02, 36), _mm_slli_epi64(_mm_srli_epi64(p13, 36), 32));
    const __m128i pred = _mm_add_epi32(q1, _mm_sub_epi32(_mm_xor_si128(q, s), s));
    _mm_storeu_si128(reinterpret_cast<__m128i*>(res + f), _mm_sub_epi32(at(0), pred));
  }
#endif
  for (; f < to; ++f) res[f] = wrap_sub(x[f], predict_smooth(kLate, x + f, 1));
}

void predictor_residuals(int mode, const int32_t* x, size_t frames, size_t period, int32_t* res) {
  with_predictor(mode, [&](auto m) {
    const size_t steady = std::min(frames, std::max<size_t>(6, period + 1));
    size_t f = 1;
    for (; f < steady; ++f) res[f] = wrap_sub(x[f], predict_one(m, f, x + f, 1, nullptr, period));
    if (static_cast<int>(m) == kPredSmooth) return smooth_residuals(x, f, frames, res);
    for (; f < frames; ++f)
      res[f] = wrap_sub(x[f], predict_one(m, kLate, x + f, 1, nullptr, period));
  });
}

// The window's integers (gaps filled) and validity point by point, so the estimate reads each
// point's trajectory as contiguous runs, not one cache line per frame: x[(3 p + a) F + f],
// v[p F + f]. Transposed in blocks of 64 frames (the block of q stays in cache).
struct PointMajor {
  Scratch<int32_t> x;
  Scratch<uint8_t> v;
  PointMajor(const int32_t* q, const uint8_t* valid, size_t frames, size_t points)
      : x(frames * points * 3), v(frames * points) {
    const size_t F = frames, S = points * 3;
    for (size_t f0 = 0; f0 < F; f0 += 64) {
      const size_t f1 = std::min(F, f0 + 64);
      for (size_t p = 0; p < points; ++p)
        for (size_t f = f0; f < f1; ++f) v[p * F + f] = valid[f * points + p];
      // x is q transposed (x[k F + f] = q[f S + k], k = 3 p + a): with SSE2 in 4 x 4 tiles
      // (four frames of four consecutive k), the rest value by value.
      size_t k4 = 0, f4 = f0;
#if defined(__SSE2__)
      k4 = S / 4 * 4;
      f4 = f0 + (f1 - f0) / 4 * 4;
      for (size_t k = 0; k < k4; k += 4)
        for (size_t f = f0; f < f4; f += 4) {
          auto row = [&](size_t j) {
            return _mm_loadu_si128(reinterpret_cast<const __m128i*>(q + (f + j) * S + k));
          };
          const __m128i r0 = row(0), r1 = row(1), r2 = row(2), r3 = row(3);
          const __m128i t0 = _mm_unpacklo_epi32(r0, r1), t1 = _mm_unpacklo_epi32(r2, r3);
          const __m128i t2 = _mm_unpackhi_epi32(r0, r1), t3 = _mm_unpackhi_epi32(r2, r3);
          auto put = [&](size_t i, __m128i c) {
            _mm_storeu_si128(reinterpret_cast<__m128i*>(&x[(k + i) * F + f]), c);
          };
          put(0, _mm_unpacklo_epi64(t0, t1));
          put(1, _mm_unpackhi_epi64(t0, t1));
          put(2, _mm_unpacklo_epi64(t2, t3));
          put(3, _mm_unpackhi_epi64(t2, t3));
        }
      for (size_t k = 0; k < k4; ++k)  // the frames past the last tile
        for (size_t f = f4; f < f1; ++f) x[k * F + f] = q[f * S + k];
#endif
      for (size_t k = k4; k < S; ++k)
        for (size_t f = f0; f < f1; ++f) x[k * F + f] = q[f * S + k];
    }
  }
};

// Residuals of every sample under the previous (e[0]) and linear (e[1]) predictors, frames
// 1.. of the window, point-major as PointMajor::x; frame 0 entries are 0.
void base_residuals(const PointMajor& pm, size_t frames, size_t points, Scratch<int32_t> e[2]) {
  for (int b = 0; b < 2; ++b) {
    e[b].resize(frames * points * 3);
    for (size_t k = 0; k < points * 3; ++k) {
      int32_t* out = &e[b][k * frames];
      out[0] = 0;
      predictor_residuals(b == 0 ? kPredPrevious : kPredLinear, &pm.x[k * frames], frames, 0, out);
    }
  }
}

// Adds to h the residuals of point p under base residuals e (point-major) plus reference r's
// deviation, over frames 1.. of the window (the reference predictors 5/6), through `res`
// (3 x frames) as scratch.
template <typename H>
void ref_cost(const Scratch<int32_t>& e, const PointMajor& pm, size_t frames, size_t p, size_t r,
              H* h, std::vector<int32_t>* res) {
  const uint8_t* vr = &pm.v[r * frames];
  const int32_t* in[3];
  for (size_t a = 0; a < 3; ++a) {
    const int32_t* ep = &e[(p * 3 + a) * frames];
    const int32_t* er = &e[(r * 3 + a) * frames];
    int32_t* out = res->data() + a * frames;
    for (size_t f = 1; f < frames; ++f)  // without a branch, so the loop vectorises
      out[f] = wrap_sub(ep[f], static_cast<int32_t>(static_cast<uint32_t>(er[f]) &
                                                    (0u - static_cast<uint32_t>(vr[f] != 0))));
    in[a] = out;
  }
  typename H::StateType st[3];
  h->add_run3(in, &pm.v[p * frames], 1, frames, st);
}

// Sum of bit_cost(c[k] - cr[k] & m[k]) over k in [0, len): the rank loop of RankSamples. With
// SSE2, four values at a time: bit_cost of a zigzagged u != 0 is its bit length + 1, that of
// its high half + 16 when the high half is not 0, else that of its low half; a value v < 2^16
// converts to float exactly, with exponent field 126 + bitlen(v) = 125 + bit_cost (v >= 1; 0
// has field 0, which the saturating subtraction keeps at 0). The same integer as the scalar
// loop's sum.
uint64_t masked_bit_costs(const int32_t* c, const int32_t* cr, const int32_t* m, size_t len) {
  size_t k = 0;
  uint64_t bits = 0;
#if defined(__SSE2__)
  const __m128i lo16 = _mm_set1_epi32(0xFFFF), bias = _mm_set1_epi32(125);
  const __m128i sixteen = _mm_set1_epi32(16), zero = _mm_setzero_si128();
  auto bitlen16 = [&](__m128i v) {  // v < 2^16 in every lane
    const __m128i e = _mm_srli_epi32(_mm_castps_si128(_mm_cvtepi32_ps(v)), 23);
    return _mm_subs_epu16(e, bias);
  };
  __m128i acc = zero;
  for (; k + 4 <= len; k += 4) {
    const __m128i d = _mm_sub_epi32(_mm_loadu_si128(reinterpret_cast<const __m128i*>(c + k)),
                                    _mm_loadu_si128(reinterpret_cast<const __m128i*>(cr + k)));
    __m128i u = _mm_xor_si128(_mm_slli_epi32(d, 1), _mm_srai_epi32(d, 31));  // zigzag
    u = _mm_and_si128(u, _mm_loadu_si128(reinterpret_cast<const __m128i*>(m + k)));
    const __m128i hi = _mm_srli_epi32(u, 16);
    const __m128i lo_len = bitlen16(_mm_and_si128(u, lo16));
    const __m128i hi_len = _mm_add_epi32(bitlen16(hi), sixteen);
    const __m128i hi_zero = _mm_cmpeq_epi32(hi, zero);
    acc = _mm_add_epi32(
        acc, _mm_or_si128(_mm_and_si128(hi_zero, lo_len), _mm_andnot_si128(hi_zero, hi_len)));
  }
  alignas(16) uint32_t lanes[4];
  _mm_store_si128(reinterpret_cast<__m128i*>(lanes), acc);  // each lane <= 32 * len / 4
  bits = uint64_t{lanes[0]} + lanes[1] + lanes[2] + lanes[3];
#endif
  for (; k < len; ++k) bits += bit_cost(wrap_sub(c[k], cr[k]) & m[k]);
  return bits;
}

// The base residuals e[0], e[1] of every point on the frames 1, 1 + step, ... that rank the
// reference candidates, point by point (so a pair's rank reads two short contiguous runs, not
// one cache line per frame): per point, per sampled frame, the three values of each base, 0
// for a gap, and a mask of -1 where the point is valid (0 where not), repeated per axis.
struct RankSamples {
  size_t n = 0;           // sampled frames
  Scratch<int32_t> e[2];  // [point][sample][axis]
  Scratch<int32_t> mask;  // [point][sample][axis]
  RankSamples(const Scratch<int32_t> base[2], const PointMajor& pm, size_t frames, size_t points,
              size_t step) {
    n = frames > 1 ? (frames - 2) / step + 1 : 0;
    for (int b = 0; b < 2; ++b) e[b].resize(points * n * 3);
    mask.resize(points * n * 3);
    for (size_t p = 0; p < points; ++p) {
      for (size_t j = 0; j < n; ++j) {
        const size_t f = 1 + j * step;
        const bool v = pm.v[p * frames + f] != 0;
        for (size_t a = 0; a < 3; ++a) mask[(p * n + j) * 3 + a] = v ? -1 : 0;
        for (int b = 0; b < 2; ++b)
          for (size_t a = 0; a < 3; ++a)
            e[b][(p * n + j) * 3 + a] = v ? base[b][(p * 3 + a) * frames + f] : 0;
      }
    }
  }
  // Rank of reference r for point p under base b: the summed bit lengths of p's residuals (its
  // base residual minus r's where r is valid) on the sampled frames where p is valid.
  uint64_t rank(int b, size_t p, size_t r) const {
    return masked_bit_costs(&e[b][p * n * 3], &e[b][r * n * 3], &mask[p * n * 3], n * 3);
  }
};

// The window's period for predictors 8/9, or 0 when none is worth trying. Differences
// q[f] - q[f-T] are costed (bit_cost, averaged) on a sample of points and frames for each T in
// [2, min(F / 2, 256)], first on at most 4 points x 8 frames, then the 8 best T again on 16 x 32;
// the frames before T count at the cost of q[f] - q[f-1]. The T with the lowest total is kept
// if it is under 0.8 times that of q[f] - q[f-1] over the window (a motion that repeats, e.g. a
// looped animation).
size_t find_period(const int32_t* q, const uint8_t* valid, size_t frames, size_t points) {
  if (frames < 4 || points == 0) return 0;
  const size_t stride = points * 3;
  const double F = static_cast<double>(frames);
  auto total = [&](size_t T, size_t np, size_t nf, double base) {  // estimated window bits
    const size_t pstep = (points + np - 1) / np, fstep = std::max<size_t>(1, (frames - T) / nf);
    uint64_t bits = 0, n = 0;
    for (size_t f = T; f < frames; f += fstep)
      for (size_t p = 0; p < points; p += pstep) {
        if (!valid[f * points + p] || !valid[(f - T) * points + p]) continue;
        const int32_t* c = q + f * stride + p * 3;
        for (int a = 0; a < 3; ++a) bits += bit_cost(wrap_sub(c[a], *(c + a - T * stride)));
        n += 3;
      }
    const double avg = n ? static_cast<double>(bits) / static_cast<double>(n) : 1e30;
    return avg * (F - static_cast<double>(T)) + base * static_cast<double>(T);
  };
  const size_t top = std::min<size_t>(frames / 2, 256);
  std::vector<std::pair<double, size_t>> coarse;
  const double base_coarse = total(1, 4, 8, 0) / (F - 1);
  for (size_t T = 2; T <= top; ++T) coarse.emplace_back(total(T, 4, 8, base_coarse), T);
  const size_t keep = std::min<size_t>(8, coarse.size());
  std::partial_sort(coarse.begin(), coarse.begin() + static_cast<std::ptrdiff_t>(keep),
                    coarse.end());
  const double base = total(1, 16, 32, 0) / (F - 1);
  size_t best = 0;
  double best_total = 0.8 * base * F;
  for (size_t k = 0; k < keep; ++k) {
    const double c = total(coarse[k].second, 16, 32, base);
    if (c < best_total) best_total = c, best = coarse[k].second;
  }
  return best;
}

// Frame 0's share of every point's estimate (the `last` rule), the same for every non-transform
// predictor, into first[p]; fills q's gaps: frame 0's by the walk, later ones with the previous
// frame's integers.
void frame0_share(const WindowInts& w, const int32_t* t, ResidualContexts& ctx,
                  std::vector<int32_t>* q, std::vector<TokenHist>* first) {
  const size_t F = w.frames, N = w.points, S = N * 3;
  std::vector<PrevState> est(N * 3);
  const std::vector<uint8_t> mm(N, static_cast<uint8_t>(kPredPrevious));
  for (TokenHist& h : *first) h.clear();
  CostCoder c0{q->data(), N, first->data(), est.data()};
  walk_window(1, N, w.valid.data(), mm.data(), nullptr, t, q->data(), ctx, c0);
  if (N == 0) return;  // a take without points (analog only): nothing to fill
  int32_t* x = q->data();
  for (size_t f = 1; f < F; ++f) {
    if (!std::memchr(&w.valid[f * N], 0, N)) continue;  // no gap in the frame
    for (size_t p = 0; p < N; ++p)
      if (!w.valid[f * N + p])
        std::copy(&x[(f - 1) * S + p * 3], &x[(f - 1) * S + p * 3 + 3], &x[f * S + p * 3]);
  }
}

// Predictors 0-2, with scheme 3 also smooth (7) and, when the window repeats with a period, 8
// and 9: each point's cheapest into best[p] / c->modes[p]. q: the window's integers, gaps
// filled.
void choose_temporal(const WindowInts& w, const std::vector<int32_t>& q, const PointMajor& pm,
                     const std::vector<TokenHist>& first, int scheme, std::vector<uint64_t>* best,
                     ModeChoice* c) {
  const size_t F = w.frames, N = w.points;
  if (scheme >= 3) c->period = find_period(q.data(), w.valid.data(), F, N);
  const size_t period = c->period;
  const int nm = scheme < 3 ? 3 : period ? 6 : 4;
  static constexpr uint8_t kIds[6] = {kPredPrevious, kPredLinear, kPredQuadratic,
                                      kPredSmooth,   kPredPeriod, kPredPeriodPrevious};
  // Point by point: the point's trajectory per axis is a contiguous array (PointMajor), so
  // each predictor's residuals are one simple loop over frames and the estimate's state
  // stays in registers (the same histograms as a frame-by-frame walk: counts are sums, and
  // the state of each predictor, point and axis sees the same sequence).
  std::vector<int32_t> res(3 * F);
  for (size_t p = 0; p < N; ++p) {
    const int32_t* xs = &pm.x[p * 3 * F];
    const uint8_t* vs = &pm.v[p * F];
    for (int m = 0; m < nm; ++m) {
      TokenHist h = first[p];
      for (size_t a = 0; a < 3; ++a)
        predictor_residuals(kIds[m], &xs[a * F], F, period, &res[a * F]);
      const int32_t* r3[3] = {&res[0], &res[F], &res[2 * F]};
      PrevState st[3];
      h.add_run3(r3, vs, 1, F, st);
      const uint64_t cost = h.bits16();
      if (cost < (*best)[p]) (*best)[p] = cost, c->modes[p] = kIds[m];
    }
  }
}

// The transform predictors 3/4, estimated by walks (their frame-0 rule and gap fill differ).
void choose_transform(const WindowInts& w, const std::vector<int32_t>& q, const int32_t* t,
                      ResidualContexts& ctx, std::vector<uint64_t>* best, ModeChoice* c) {
  const size_t F = w.frames, N = w.points;
  std::vector<int32_t> qt = q;
  std::vector<TokenHist> hist(N);
  std::vector<PrevState> est(N * 3);
  for (int m = kPredTransform; m <= kPredTransformLinear; ++m) {
    const std::vector<uint8_t> mm(N, static_cast<uint8_t>(m));
    for (TokenHist& h : hist) h.clear();
    std::fill(est.begin(), est.end(), PrevState());
    CostCoder cc{qt.data(), N, hist.data(), est.data()};
    walk_window(F, N, w.valid.data(), mm.data(), nullptr, t, qt.data(), ctx, cc);
    for (size_t p = 0; p < N; ++p) {
      const uint64_t cost = hist[p].bits16();
      if (cost < (*best)[p]) (*best)[p] = cost, c->modes[p] = static_cast<uint8_t>(m);
    }
  }
}

// Predictor 10 (FORMAT.md 8.3), estimated as choose_temporal estimates 0-9: per point, the
// residuals of each axis in axis order (the walk codes the lead axis first, which changes only
// the `tb` of its contexts, which the estimate does not model).
void choose_ray(const WindowInts& w, const PointMajor& pm, const std::vector<TokenHist>& first,
                RayKind ray, std::vector<uint64_t>* best, ModeChoice* c) {
  const size_t F = w.frames, N = w.points;
  std::vector<int32_t> res(3 * F);
  for (size_t p = 0; p < N; ++p) {
    const int32_t* xs = &pm.x[p * 3 * F];
    const int32_t* ax[3] = {xs, xs + F, xs + 2 * F};
    for (size_t f = 1; f < F; ++f) {
      const int32_t cprev[3] = {ax[0][f - 1], ax[1][f - 1], ax[2][f - 1]};
      const int l = ray_lead(ray, cprev);
      for (int a = 0; a < 3; ++a)
        res[a * F + f] =
            wrap_sub(ax[a][f], a == l ? cprev[l] : ray_predict(ray, cprev[a], cprev[l], ax[l][f]));
    }
    TokenHist h = first[p];
    const int32_t* r3[3] = {&res[0], &res[F], &res[2 * F]};
    PrevState st[3];
    h.add_run3(r3, &pm.v[p * F], 1, F, st);
    const uint64_t cost = h.bits16();
    if (cost < (*best)[p]) (*best)[p] = cost, c->modes[p] = kPredRay;
  }
}

// The two best (reference, base) pairs of point p by RankSamples::rank over its K candidates
// cand[0..K) (UINT32_MAX ends the list early); fin_b[j] = -1 where fewer were found.
constexpr int kFinalists = 2;
void rank_references(const RankSamples& samples, const uint32_t* cand, size_t K, size_t p,
                     size_t fin_r[kFinalists], int fin_b[kFinalists]) {
  uint64_t rank[kFinalists] = {UINT64_MAX, UINT64_MAX};
  for (int j = 0; j < kFinalists; ++j) fin_r[j] = 0, fin_b[j] = -1;
  for (size_t k = 0; k < K && cand[k] != UINT32_MAX; ++k)
    for (int b = 0; b < 2; ++b) {
      const size_t r = cand[k];
      const uint64_t cost = samples.rank(b, p, r);
      for (int j = 0; j < kFinalists; ++j)
        if (cost < rank[j]) {
          for (int m = kFinalists - 1; m > j; --m)
            rank[m] = rank[m - 1], fin_r[m] = fin_r[m - 1], fin_b[m] = fin_b[m - 1];
          rank[j] = cost, fin_r[j] = r, fin_b[j] = b;
          break;
        }
    }
}

// Reference predictors 5/6. Candidate pairs (reference, base) are ranked by the summed bit
// lengths of their residuals on every `step`-th frame (RankSamples); the full estimate of the
// two best then competes with the point's best predictor so far. e: base_residuals of q.
void choose_references(const WindowInts& w, const std::vector<int32_t>& q, const PointMajor& pm,
                       const Scratch<int32_t> e[2], const std::vector<TokenHist>& first,
                       std::vector<uint64_t>* best, ModeChoice* c) {
  const size_t F = w.frames, N = w.points;
  size_t K;
  const std::vector<uint32_t> cand = ref_candidates(q.data(), w.valid.data(), F, N, &K);
  const size_t step = F >= 512 ? 8 : F >= 256 ? 4 : F >= 64 ? 2 : 1;
  const RankSamples samples(e, pm, F, N, step);
  std::vector<int32_t> res(3 * F);  // scratch of the estimates: a point's residuals by axis
  for (size_t p = 1; p < N; ++p) {
    size_t fin_r[kFinalists];
    int fin_b[kFinalists];
    rank_references(samples, &cand[p * K], K, p, fin_r, fin_b);
    for (int j = 0; j < kFinalists && fin_b[j] >= 0; ++j) {
      TokenHist h = first[p];
      ref_cost(e[fin_b[j]], pm, F, p, fin_r[j], &h, &res);
      const uint64_t cost = h.bits16();
      if (cost < (*best)[p]) {
        (*best)[p] = cost;
        c->modes[p] = static_cast<uint8_t>(fin_b[j] == 0 ? kPredRefPrevious : kPredRefLinear);
        c->ref[p] = static_cast<uint32_t>(fin_r[j]);
      }
    }
  }
}

// Predictor per point: the cheapest by an estimate of coded bits over the window. Fills q's
// gaps (windows of 2 frames or more). t: the transform prediction, or nullptr.
}  // namespace

ModeChoice choose_modes(const WindowInts& w, const int32_t* t, int scheme, ResidualContexts& ctx,
                        std::vector<int32_t>* q, RayKind ray) {
  const size_t F = w.frames, N = w.points;
  ModeChoice c;
  c.modes.assign(N, 0);
  c.ref.assign(N, 0);
  if (F <= 1) {
    if (t) std::fill(c.modes.begin(), c.modes.end(), static_cast<uint8_t>(kPredTransform));
    return c;
  }
  std::vector<uint64_t> best(N, UINT64_MAX);
  std::vector<TokenHist> first(N);
  frame0_share(w, t, ctx, q, &first);
  const PointMajor pm(q->data(), w.valid.data(), F, N);
  Scratch<int32_t> e[2];
  const bool refs = scheme >= 2 && F > 2 && N > 1;
  if (refs) base_residuals(pm, F, N, e);
  choose_temporal(w, *q, pm, first, scheme, &best, &c);
  if (t) choose_transform(w, *q, t, ctx, &best, &c);
  if (refs) choose_references(w, *q, pm, e, first, &best, &c);
  if (ray != RayKind::kNone && scheme >= 3) choose_ray(w, pm, first, ray, &best, &c);
  return c;
}

}  // namespace capz
