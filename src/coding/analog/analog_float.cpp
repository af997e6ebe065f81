// Float channels' decoder (docs/FORMAT.md 9.1): the predictor read, then each sample from its
// prediction and residual; the encoder's choice and coding are analog_float_encode.cpp.
#include "coding/analog/analog_float.h"

#include <algorithm>
#include <cmath>
#include <cstring>
#include <limits>

#include "coding/analog/analog_entropy.h"
#include "coding/analog/analog_lpc.h"
#include "coding/analog/analog_repr.h"

namespace capz {
namespace analog {

static_assert(kMaxFloatLpcOrder == 8, "the decoder's message names the largest order");

using namespace float9;

namespace {

double apply(double p, int64_t d, bool f32) {
  return apply_ordered_delta(p, d, f32);
}

}  // namespace

void decode_float_channel(size_t n, bool f32, IntDecoder::Cursor* dec, std::vector<double>* x) {
  int tok;
  const uint32_t kind = dec->get(kParamContext, &tok);
  if (kind < 2 || kind > 5) dec->corrupt("unknown analog float predictor");
  x->resize(n);
  FloatPlan plan;
  plan.predictor = static_cast<int>(kind);
  if (kind == 5) {
    plan.order = static_cast<int>(dec->get(kParamContext, &tok));
    if (plan.order < 1 || plan.order > kMaxFloatLpcOrder)
      dec->corrupt("analog float LPC order outside 1..8");
    plan.shift = static_cast<int>(dec->get(kParamContext, &tok));
    if (plan.shift > kMaxFloatLpcShift) dec->corrupt("analog float LPC shift above 40");
    for (int j = 0; j < plan.order; ++j) {
      const int32_t q = dec->get_signed(kCoefContext, &tok);
      if (q >= (1 << kFloatLpcPrecision) || q <= -(1 << kFloatLpcPrecision))
        dec->corrupt("analog float LPC coefficient out of range");
      plan.q[j] = q;
    }
  }
  const double scale = lpc_scale(plan);
  int prev_nb = 0;
  double* xs = x->data();
  for (size_t i = 0; i < n; ++i)
    xs[i] = apply(predict9(plan, scale, xs, i, f32), get_float_residual9(dec, &prev_nb), f32);
}

}  // namespace analog
}  // namespace capz
