// Inter-channel prediction stage (docs/format-drafts/analog.md A.3.2): the LPC residual of a
// channel predicted from the LPC residual of an earlier channel of the window at the same row
// (the channels of one force plate see the same load and the same disturbances).
//
//   r2[i] = r1[i] - clamp((beta * ref[i] + 2^(kCrossShift-1)) >> kCrossShift, -kMaxSample,
//   kMaxSample)
//
// The reference is one of the kMaxCrossDistance channels before (integer kinds only), chosen by
// the encoder with beta from least squares; distance 0 means no reference.
#pragma once

#include <cstddef>
#include <cstdint>
#include <vector>

#include "coding/analog/analog_lpc.h"

namespace capz {
namespace analog {

constexpr int kMaxCrossDistance = 8;
constexpr int kCrossShift = 12;
constexpr int32_t kMaxBeta = 1 << 15;  // |beta| < kMaxBeta

struct CrossParams {
  int distance = 0;  // 0 = none, else the reference is channel c - distance
  int32_t beta = 0;
};

// The sum of r[i]^2 over i in increasing order, in double: a reference's energy, computed once
// per channel for every later channel that may use it.
double reference_energy(const std::vector<int32_t>& r);

// refs[d - 1] is the LPC residual of channel c - d, or nullptr when that channel has none, and
// ref_energy[d - 1] its reference_energy (unused for nullptr). Chooses the reference that
// lowers the estimated bits of r1 most (by more than `min_gain_bits`).
CrossParams choose_cross(const std::vector<int32_t>& r1,
                         const std::vector<const std::vector<int32_t>*>& refs,
                         const std::vector<double>& ref_energy, double min_gain_bits = 32);

inline int64_t cross_predict(int32_t beta, int32_t ref) {
  int64_t p = (static_cast<int64_t>(beta) * ref + (int64_t{1} << (kCrossShift - 1))) >> kCrossShift;
  return p > kMaxSample ? kMaxSample : p < -kMaxSample ? -kMaxSample : p;
}

}  // namespace analog
}  // namespace capz
