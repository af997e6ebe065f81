#include "coding/analog/analog_float.h"

#include <algorithm>
#include <cstring>

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

}  // namespace

int choose_float_predictor(const std::vector<double>& x, bool f32) {
  const size_t n = x.size();
  uint64_t cost[kFloatPredictors] = {0, 0};
  for (size_t i = 0; i < n; ++i) {
    const double a = i > 0 ? x[i - 1] : 0, b = i > 1 ? x[i - 2] : 0;
    for (int k = 0; k < kFloatPredictors; ++k)
      cost[k] += bit_length(residual(x[i], predict(k, a, b, f32), f32));
  }
  return cost[1] < cost[0] ? 1 : 0;
}

bool encode_float_channel(const std::vector<double>& x, bool f32, int kind, IntEncoder::Cursor* enc,
                          size_t limit) {
  const size_t n = x.size();
  enc->put(static_cast<uint32_t>(kind), kParamContext);
  int prev_nb = 0;
  for (size_t i0 = 0; i0 < n; i0 += 1024) {
    if (enc->bytes_out() >= limit) return false;
    const size_t i1 = std::min(n, i0 + 1024);
    for (size_t i = i0; i < i1; ++i) {
      const double a = i > 0 ? x[i - 1] : 0, b = i > 1 ? x[i - 2] : 0;
      put_float_residual(enc, &prev_nb, residual(x[i], predict(kind, a, b, f32), f32));
    }
  }
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
