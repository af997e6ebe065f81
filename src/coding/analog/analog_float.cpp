#include "coding/analog/analog_float.h"

#include <algorithm>
#include <cstring>
#include <limits>
#if defined(__SSE2__)
#include <emmintrin.h>
#endif

#include "coding/analog/analog_entropy.h"
#include "coding/analog/analog_repr.h"

namespace capz {
namespace analog {
namespace {

constexpr int kFloatPredictors = 2;

double predict(int kind, double a, double b, bool f32) {
  const double p = kind == 0 ? a : a + (a - b);
  return f32 ? round_to_float32(p) : p;
}

// Residual of sample v against prediction p in the channel's ordered integers.
int64_t residual(double v, double p, bool f32) {
  if (f32) return static_cast<int64_t>(ordered_f32(v)) - static_cast<int64_t>(ordered_f32(p));
  return static_cast<int64_t>(ordered_bits(bits_of(v)) - ordered_bits(bits_of(p)));
}
double apply(double p, int64_t d, bool f32) {
  return apply_ordered_delta(p, d, f32);
}

int bit_length(int64_t d) {
  const uint64_t u = zigzag64(d);
  return u == 0 ? 0 : 64 - __builtin_clzll(u);
}

#if defined(__SSE2__)
// Sortable form of the float32 values of two doubles (each a float32 value, or rounded to one
// as static_cast<float> does): s = ordered_f32 - 2^31 as int32, widened (exact).
inline __m128d sortable_f32(__m128d v) {
  const __m128i b = _mm_castps_si128(_mm_cvtpd_ps(v));
  return _mm_cvtepi32_pd(_mm_xor_si128(b, _mm_srli_epi32(_mm_srai_epi32(b, 31), 1)));
}
// Adds the bit lengths of the zig-zags of two residuals d (exact integers below 2^33 in
// magnitude): |2 d + 1/2| is the zig-zag u + 1/2, whose biased exponent - 1022 is u's bit
// length (0 for u = 0). The caller subtracts 1022 a residual.
inline __m128i add_bit_lengths(__m128i acc, __m128d d) {
  const __m128d mag = _mm_castsi128_pd(_mm_set1_epi64x(0x7FFFFFFFFFFFFFFF));
  const __m128d u = _mm_and_pd(_mm_add_pd(_mm_add_pd(d, d), _mm_set1_pd(0.5)), mag);
  return _mm_add_epi64(acc, _mm_srli_epi64(_mm_castpd_si128(u), 52));
}

// The summed bit lengths of both predictors' residuals for samples [2, n) of a float32
// channel (every x a float32 value), two samples a step; the same sums as the scalar loop:
// predictor 0 predicts x[i - 1] itself, predictor 1 rounds x[i - 1] + (x[i - 1] - x[i - 2])
// (finite, within 3 FLT_MAX) clamped to +-FLT_MAX to float32, as round_to_float32 does.
void float32_costs(const std::vector<double>& x, uint64_t cost[2]) {
  const size_t n = x.size();
  std::vector<double> sv(n);
  size_t i = 0;
  for (; i + 2 <= n; i += 2) _mm_storeu_pd(&sv[i], sortable_f32(_mm_loadu_pd(&x[i])));
  if (i < n) sv[i] = _mm_cvtsd_f64(sortable_f32(_mm_set_sd(x[i])));
  const __m128d hi = _mm_set1_pd(std::numeric_limits<float>::max()),
                lo = _mm_sub_pd(_mm_setzero_pd(), hi);
  __m128i acc0 = _mm_setzero_si128(), acc1 = _mm_setzero_si128();
  for (i = 2; i + 2 <= n; i += 2) {
    const __m128d a = _mm_loadu_pd(&x[i - 1]), b = _mm_loadu_pd(&x[i - 2]);
    const __m128d s = _mm_loadu_pd(&sv[i]);
    acc0 = add_bit_lengths(acc0, _mm_sub_pd(s, _mm_loadu_pd(&sv[i - 1])));
    const __m128d y = _mm_max_pd(_mm_min_pd(_mm_add_pd(a, _mm_sub_pd(a, b)), hi), lo);
    acc1 = add_bit_lengths(acc1, _mm_sub_pd(s, sortable_f32(y)));
  }
  uint64_t c0[2], c1[2];
  _mm_storeu_si128(reinterpret_cast<__m128i*>(c0), acc0);
  _mm_storeu_si128(reinterpret_cast<__m128i*>(c1), acc1);
  cost[0] += c0[0] + c0[1] - 1022 * (i - 2);
  cost[1] += c1[0] + c1[1] - 1022 * (i - 2);
  for (; i < n; ++i)
    for (int k = 0; k < kFloatPredictors; ++k)
      cost[k] += bit_length(residual(x[i], predict(k, x[i - 1], x[i - 2], true), true));
}
#endif

}  // namespace

void float_predictor_costs(const std::vector<double>& x, bool f32, uint64_t cost[2]) {
  const size_t n = x.size();
  cost[0] = cost[1] = 0;
#if defined(__SSE2__)
  const size_t scalar = f32 ? std::min<size_t>(n, 2) : n;
#else
  const size_t scalar = n;
#endif
  for (size_t i = 0; i < scalar; ++i) {
    const double a = i > 0 ? x[i - 1] : 0, b = i > 1 ? x[i - 2] : 0;
    for (int k = 0; k < kFloatPredictors; ++k)
      cost[k] += bit_length(residual(x[i], predict(k, a, b, f32), f32));
  }
#if defined(__SSE2__)
  if (scalar < n) float32_costs(x, cost);
#endif
}

int choose_float_predictor(const std::vector<double>& x, bool f32, uint64_t* bits) {
  uint64_t cost[kFloatPredictors];
  float_predictor_costs(x, f32, cost);
  const int k = cost[1] < cost[0] ? 1 : 0;
  if (bits) *bits = cost[k];
  return k;
}

// Flattened over a local copy of the cursor, as the integer channels' coding.
__attribute__((flatten)) bool encode_float_channel(const std::vector<double>& x, bool f32, int kind,
                                                   IntEncoder::Cursor* out, size_t limit) {
  IntEncoder::Cursor c = *out;
  IntEncoder::Cursor* enc = &c;
  const size_t n = x.size();
  enc->put(static_cast<uint32_t>(kind), kParamContext);
  int prev_nb = 0;
  for (size_t i0 = 0; i0 < n; i0 += kTrialCheck) {
    if (enc->bytes_out() >= limit) return false;
    const size_t i1 = std::min(n, i0 + kTrialCheck);
    for (size_t i = i0; i < i1; ++i) {
      const double a = i > 0 ? x[i - 1] : 0, b = i > 1 ? x[i - 2] : 0;
      put_float_residual(enc, &prev_nb, residual(x[i], predict(kind, a, b, f32), f32));
    }
  }
  *out = c;
  return true;
}

void encode_float_channel(const std::vector<double>& x, bool f32, IntEncoder::Cursor* enc) {
  encode_float_channel(x, f32, choose_float_predictor(x, f32), enc);
}

void decode_float_channel(size_t n, bool f32, IntDecoder::Cursor* dec, std::vector<double>* x) {
  int tok;
  const uint32_t kind = dec->get(kParamContext, &tok);
  if (kind >= kFloatPredictors) dec->corrupt("unknown analog float predictor");
  x->resize(n);
  int prev_nb = 0;
  double a = 0, b = 0;
  for (size_t i = 0; i < n; ++i) {
    const double v =
        apply(predict(static_cast<int>(kind), a, b, f32), get_float_residual(dec, &prev_nb), f32);
    (*x)[i] = v;
    b = a;
    a = v;
  }
}

}  // namespace analog
}  // namespace capz
