// Predictive coding of float channels (docs/format-drafts/analog.md A.4), as fpzip does:
// predict each sample from the previous ones in floating point, map prediction and sample to
// ordered integers (monotone in the value), code their difference (analog_entropy.h).
//
// Predictors (chosen per channel and window by the summed bit lengths of the residuals):
//   0: p = x[i-1]                       1: p = x[i-1] + (x[i-1] - x[i-2])
// computed in double (no fused operations), then rounded to float32 for kFloat32 channels;
// samples before the first are 0. kFloat32 uses 32-bit ordered patterns of the float, kFloat64
// the 64-bit ones, differences wrapping.
#pragma once

#include <cstddef>
#include <cstdint>
#include <vector>

#include "coding/entropy.h"

namespace capz {
namespace analog {

// How often (in samples) a trial coding checks its output against its limit.
constexpr size_t kTrialCheck = 256;

void encode_float_channel(const std::vector<double>& x, bool f32, IntEncoder::Cursor* enc);
// The two halves of encode_float_channel: the predictor kept (by the summed bit lengths), and
// the coding with a given predictor (the window codec decides once and codes twice).
// *bits (when given) receives the kept predictor's sum.
int choose_float_predictor(const std::vector<double>& x, bool f32, uint64_t* bits = nullptr);
// The summed bit lengths of the residuals of predictors 0 and 1 that choose_float_predictor
// compares (f32: every x is a float32 value).
void float_predictor_costs(const std::vector<double>& x, bool f32, uint64_t cost[2]);
// Stops, returning false, once enc->bytes_out() reaches `limit` (checked every kTrialCheck
// samples).
bool encode_float_channel(const std::vector<double>& x, bool f32, int predictor,
                          IntEncoder::Cursor* enc, size_t limit = SIZE_MAX);
// Decodes n samples into x (resized to n). format9: predictors 2-5 (FORMAT.md 11.9) are valid.
void decode_float_channel(size_t n, bool f32, IntDecoder::Cursor* dec, std::vector<double>* x,
                          bool format9 = false);

// FORMAT.md 11.9: the predictors of a 9.x stream (2: previous, 3: linear, 4: zero, 5: LPC),
// whose residuals code the 4 bits below the leading one through a model.
constexpr int kMaxFloatLpcOrder = 8;
constexpr int kMaxFloatLpcShift = 40;
constexpr int kFloatLpcPrecision = 15;  // |q| < 2^15
struct FloatPlan {
  int predictor = 0;  // 0..5
  int order = 0;      // predictor 5
  int shift = 0;
  int32_t q[kMaxFloatLpcOrder] = {};
};
// The predictor kept for a 9.x stream (by the summed bit lengths of the residuals, plus the
// LPC's side information), *bits its sum.
FloatPlan choose_float_plan9(const std::vector<double>& x, bool f32, uint64_t* bits);
bool encode_float_channel(const std::vector<double>& x, bool f32, const FloatPlan& plan,
                          IntEncoder::Cursor* enc, size_t limit = SIZE_MAX);

}  // namespace analog
}  // namespace capz
