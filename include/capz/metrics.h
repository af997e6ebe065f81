// capz — error and rate measures, computed over valid samples only (gaps are ignored).
#pragma once

#include <cstddef>
#include <cstdint>

#include "capz/take.h"

namespace capz {

struct ErrorStats {
  double max_error = 0;  // largest Euclidean distance between a sample and its reconstruction
  double max_abs = 0;    // largest per-coordinate absolute difference (what a grid bound bounds)
  double rmse = 0;       // sqrt(mean over valid samples of squared Euclidean distance)
  // Karni & Gotsman error in percent: 100 * ||A - A'||_F / ||A - E(A)||_F, where E(A) holds each
  // frame's centroid of the valid points (as in Luo et al. 2013 and Amjoun & Strasser 2007).
  double kg_error = 0;
  double psnr = 0;             // 20 log10(bbox diagonal / rmse), dB; infinite when rmse is 0
  size_t samples = 0;          // valid samples compared
  size_t mask_mismatches = 0;  // samples whose validity differs between the two takes
};

// Accumulates the measures over blocks of frames (e.g. one window at a time), so a long take
// is measured without a second full copy. a: original, b: reconstruction, both
// frames x points x 3; valid: frames x points (a's mask). Blocks are whole frames.
class ErrorAccumulator {
 public:
  void add(size_t frames, size_t points, const double* a, const double* b, const uint8_t* valid);
  // The same for frames of their own point counts (a ragged take or block): frame f holds the
  // points [offsets[f], offsets[f + 1]) counted from offsets[0], which a, b and valid start at.
  void add_ragged(size_t frames, const size_t* offsets, const double* a, const double* b,
                  const uint8_t* valid);
  ErrorStats finish() const;

 private:
  ErrorStats s_;
  double sq_ = 0, centred_sq_ = 0;
  double lo_[3] = {1e308, 1e308, 1e308}, hi_[3] = {-1e308, -1e308, -1e308};
};

// `a` is the original, `b` the reconstruction; both frames x points x 3 with a's mask (or
// ragged with the same frame offsets). Throws kInvalidParameter when the shapes differ.
ErrorStats compare(const Take& a, const Take& b);
ErrorStats compare(size_t frames, size_t points, const double* a, const double* b,
                   const uint8_t* valid);

// Bits per vertex per frame: 8 * bytes / (frames * points).
double bpvf(size_t bytes, size_t frames, size_t points);

}  // namespace capz
