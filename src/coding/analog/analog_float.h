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

#include <cstddef>
#include <cstdint>
#include <vector>

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

}  // namespace analog
}  // namespace capz
