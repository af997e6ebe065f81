#include "capz/metrics.h"

#include <algorithm>
#include <cmath>
#include <limits>

#include "capz/error.h"

namespace capz {

void ErrorAccumulator::add(size_t frames, size_t points, const double* a, const double* b,
                           const uint8_t* valid) {
  // The running figures in locals (registers), stored back at the end: the same operations in
  // the same order as on the members, which the stores would otherwise force to memory.
  double max_abs = s_.max_abs, sq = sq_, centred_sq = centred_sq_;
  // The block's largest squared error, its root taken once at the end: sqrt is correctly
  // rounded and monotonic, so sqrt(max d2) = max sqrt(d2) exactly.
  double max_d2 = 0;
  double lo[3] = {lo_[0], lo_[1], lo_[2]}, hi[3] = {hi_[0], hi_[1], hi_[2]};
  size_t samples = s_.samples;
  for (size_t f = 0; f < frames; ++f) {
    double c[3] = {0, 0, 0};
    size_t n = 0;
    for (size_t p = 0; p < points; ++p) {
      if (!valid[f * points + p]) continue;
      const double* x = a + (f * points + p) * 3;
      for (int k = 0; k < 3; ++k) c[k] += x[k];
      ++n;
    }
    if (n == 0) continue;
    for (double& v : c) v /= static_cast<double>(n);
    for (size_t p = 0; p < points; ++p) {
      if (!valid[f * points + p]) continue;
      const double* x = a + (f * points + p) * 3;
      const double* y = b + (f * points + p) * 3;
      double d2 = 0;
      for (int k = 0; k < 3; ++k) {
        double d = x[k] - y[k];
        d2 += d * d;
        max_abs = std::max(max_abs, std::fabs(d));
        double e = x[k] - c[k];
        centred_sq += e * e;
        lo[k] = std::min(lo[k], x[k]);
        hi[k] = std::max(hi[k], x[k]);
      }
      max_d2 = std::max(max_d2, d2);
      sq += d2;
      ++samples;
    }
  }
  s_.max_abs = max_abs;
  s_.max_error = std::max(s_.max_error, std::sqrt(max_d2));
  sq_ = sq;
  centred_sq_ = centred_sq;
  for (int k = 0; k < 3; ++k) lo_[k] = lo[k], hi_[k] = hi[k];
  s_.samples = samples;
}

ErrorStats ErrorAccumulator::finish() const {
  ErrorStats s = s_;
  if (s.samples == 0) return s;
  s.rmse = std::sqrt(sq_ / static_cast<double>(s.samples));
  s.kg_error = centred_sq_ > 0 ? 100.0 * std::sqrt(sq_ / centred_sq_) : (sq_ > 0 ? INFINITY : 0.0);
  double diag =
      std::sqrt((hi_[0] - lo_[0]) * (hi_[0] - lo_[0]) + (hi_[1] - lo_[1]) * (hi_[1] - lo_[1]) +
                (hi_[2] - lo_[2]) * (hi_[2] - lo_[2]));
  s.psnr = s.rmse > 0 ? 20.0 * std::log10(diag / s.rmse) : INFINITY;
  return s;
}

ErrorStats compare(size_t frames, size_t points, const double* a, const double* b,
                   const uint8_t* valid) {
  ErrorAccumulator acc;
  acc.add(frames, points, a, b, valid);
  return acc.finish();
}

void ErrorAccumulator::add_ragged(size_t frames, const size_t* offsets, const double* a,
                                  const double* b, const uint8_t* valid) {
  for (size_t f = 0; f < frames; ++f) {
    const size_t o = offsets[f] - offsets[0];
    add(1, offsets[f + 1] - offsets[f], a + o * 3, b + o * 3, valid + o);
  }
}

ErrorStats compare(const Take& a, const Take& b) {
  if (a.frames != b.frames || a.points != b.points || b.xyz.size() != a.xyz.size() ||
      a.frame_offsets != b.frame_offsets || a.xyz.size() != a.total_points() * 3 ||
      a.valid.size() != a.total_points())
    fail(ErrorCode::kInvalidParameter, a.source,
         "cannot compare takes of different shapes (" + std::to_string(a.frames) + "x" +
             (a.ragged() ? std::to_string(a.total_points()) + " points in all"
                         : std::to_string(a.points)) +
             " vs " + std::to_string(b.frames) + "x" +
             (b.ragged() ? std::to_string(b.total_points()) + " points in all"
                         : std::to_string(b.points)) +
             ")");
  ErrorStats s;
  if (a.ragged()) {
    ErrorAccumulator acc;
    acc.add_ragged(a.frames, a.frame_offsets.data(), a.xyz.data(), b.xyz.data(), a.valid.data());
    s = acc.finish();
  } else {
    s = compare(a.frames, a.points, a.xyz.data(), b.xyz.data(), a.valid.data());
  }
  if (b.valid.size() == a.valid.size())
    for (size_t i = 0; i < a.valid.size(); ++i)
      s.mask_mismatches += (a.valid[i] != 0) != (b.valid[i] != 0);
  return s;
}

double bpvf(size_t bytes, size_t frames, size_t points) {
  if (frames == 0 || points == 0) return 0;
  return 8.0 * static_cast<double>(bytes) /
         (static_cast<double>(frames) * static_cast<double>(points));
}

}  // namespace capz
