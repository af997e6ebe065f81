// Predictive coding of float channels (docs/format-drafts/analog.md A.4), as fpzip does:
// predict each sample from the previous ones in floating point, map prediction and sample to
// ordered integers (monotone in the value), code their difference (analog_entropy.h).
//
// Predictors (FORMAT.md 9.1, chosen per channel and window by an estimate of the coded bits):
//   2: p = x[i-1]   3: p = x[i-1] + (x[i-1] - x[i-2])   4: p = 0   5: LPC of order 1-8
// computed in double (no fused operations), then rounded to float32 for kFloat32 channels;
// samples before the first are 0 (ids 0 and 1 are not in format 1.0). kFloat32 uses 32-bit ordered
// patterns of the float, kFloat64 the 64-bit ones, differences wrapping.
#pragma once

#include <cmath>
#include <cstddef>
#include <cstdint>
#include <vector>

#include "coding/analog/analog_repr.h"
#include "coding/entropy.h"

namespace capz {
namespace analog {

// How often (in samples) a trial coding checks its output against its limit.
constexpr size_t kTrialCheck = 256;

// Decodes n samples into x (resized to n).
void decode_float_channel(size_t n, bool f32, IntDecoder::Cursor* dec, std::vector<double>* x);

// FORMAT.md 9.1: residuals code the 4 bits below the leading one through a model.
constexpr int kMaxFloatLpcOrder = 8;
constexpr int kMaxFloatLpcShift = 40;
constexpr int kFloatLpcPrecision = 15;  // |q| < 2^15
struct FloatPlan {
  int predictor = 2;  // 2..5
  int order = 0;      // predictor 5
  int shift = 0;
  int32_t q[kMaxFloatLpcOrder] = {};
};
// The predictor kept (by the summed bit lengths of the residuals, plus the
// LPC's side information), *bits its sum.
FloatPlan choose_float_plan9(const std::vector<double>& x, bool f32, uint64_t* bits);
bool encode_float_channel(const std::vector<double>& x, bool f32, const FloatPlan& plan,
                          IntEncoder::Cursor* enc, size_t limit = SIZE_MAX);

// What the encoder (analog_float_encode.cpp) and the decoder (analog_float.cpp) share: the
// residual against a prediction and the predictions themselves.
namespace float9 {

// Residual of sample v against prediction p in the channel's ordered integers.
inline int64_t residual(double v, double p, bool f32) {
  if (f32) return static_cast<int64_t>(ordered_f32(v)) - static_cast<int64_t>(ordered_f32(p));
  return static_cast<int64_t>(ordered_bits(bits_of(v)) - ordered_bits(bits_of(p)));
}

// FORMAT.md 9.1: the prediction of sample i (x[0 .. i) decoded) by a 9.x predictor.
inline double predict9(const FloatPlan& plan, double scale, const double* x, size_t i, bool f32) {
  const double a = i > 0 ? x[i - 1] : 0;
  double p;
  switch (plan.predictor) {
    case 2:
      return a;  // a float32 value already when f32
    case 3:
      p = a + (a - (i > 1 ? x[i - 2] : 0));
      break;
    case 4:
      return 0.0;
    default: {
      if (i < static_cast<size_t>(plan.order)) return a;
      double acc = 0;
      for (int j = 0; j < plan.order; ++j) acc += static_cast<double>(plan.q[j]) * x[i - 1 - j];
      p = acc * scale;
      if (!std::isfinite(p)) return a;
    }
  }
  return f32 ? round_to_float32(p) : p;
}

inline double lpc_scale(const FloatPlan& plan) {
  return std::ldexp(1.0, -plan.shift);
}

}  // namespace float9

}  // namespace analog
}  // namespace capz
