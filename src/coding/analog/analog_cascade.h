// Backward-adaptive cascade stage (docs/format-drafts/analog.md A.3.2): a sign-sign LMS filter
// on the LPC residual, as the NLMS stages of Monkey's Audio and OptimFROG. It costs no side
// information: encoder and decoder adapt the same integer weights from the same past values.
//
// With history h[0..kTaps) (h[0] the previous stage input) and weights w (units 2^-kShift):
//   p   = clamp((sum_j w[j] * h[j] + 2^(kShift-1)) >> kShift, -kMaxSample, kMaxSample)  (int64)
//   out = in - p
//   then w[j] += kStep * sgn(out) * sgn(h[j]), clamped to [-kMaxWeight, kMaxWeight], and the
//   history shifts in `in` clamped to [-kMaxSample, kMaxSample].
// All weights and history start at 0 at the start of each channel of each window.
#pragma once

#include <cstdint>

#include "coding/analog/analog_lpc.h"

namespace capz {
namespace analog {

class SignLms {
 public:
  static constexpr int kTaps = 16;
  static constexpr int kShift = 14;
  static constexpr int32_t kStep = 64;
  static constexpr int32_t kMaxWeight = 1 << 17;

  int64_t predict() const {
    int64_t s = 0;
    for (int j = 0; j < kTaps; ++j) s += static_cast<int64_t>(w_[j]) * h_[j];
    s = (s + (int64_t{1} << (kShift - 1))) >> kShift;
    return s > kMaxSample ? kMaxSample : s < -kMaxSample ? -kMaxSample : s;
  }
  // After coding: `in` was the stage input, `out` = in - predict().
  void update(int64_t in, int64_t out) {
    const int32_t d = out > 0 ? kStep : out < 0 ? -kStep : 0;
    if (d != 0)
      for (int j = 0; j < kTaps; ++j) {
        const int32_t g = h_[j] > 0 ? d : h_[j] < 0 ? -d : 0;
        int32_t w = w_[j] + g;
        w_[j] = w > kMaxWeight ? kMaxWeight : w < -kMaxWeight ? -kMaxWeight : w;
      }
    for (int j = kTaps - 1; j > 0; --j) h_[j] = h_[j - 1];
    h_[0] = static_cast<int32_t>(in > kMaxSample    ? kMaxSample
                                 : in < -kMaxSample ? -kMaxSample
                                                    : in);
  }

 private:
  int32_t w_[kTaps] = {};
  int32_t h_[kTaps] = {};
};

}  // namespace analog
}  // namespace capz
