// pdct codec: what its encoder (pdct_encoder.cpp) and decoder (pdct_decoder.cpp) share, one copy:
// the payload's version, flag bits and the contexts of its integer streams (docs/CODEC-PDCT.md).
// Decoder library (capz_decode): builds without PCL and without the transform encoders.
#pragma once

#include <cstddef>
#include <cstdint>
#include <vector>

#include "codec/pdct/predict.h"

namespace capz {
namespace pdct {

constexpr uint8_t kVersion = 1;
constexpr const char* kWhat = "pdct payload";
// Flags byte after the version.
constexpr uint8_t kFlagSeedOrder2 = 1;   // frame points: linear prediction (seed_order 2)
constexpr uint8_t kFlagLocalOrder2 = 2;  // local coordinates: 2 q~(f-1) - q~(f-2)
constexpr uint8_t kFlagGrid = 4;         // grid mode: a predictor block, no DCT
constexpr uint8_t kKnownFlags = 7;

// Integer streams: three blocks of the container's integer entropy coder (coding/entropy.h), each
// stored as varint(length) + block. Contexts (docs/CODEC-PDCT.md):
//   frame-point residuals: the axis (3 contexts); frame-0 residuals: the axis (3);
//   DCT coefficients: 5 frequency bands of the index l in its block (0 | 1-3 | 4-15 | 16-63 | 64+)
//   times 3 classes of the previous coefficient's token in the same block (0 | 1-2 | 3+): 15.
// Every stored integer is within +-2^30 (the encoder keeps each quantised value within
// 2^29, so differences fit too).

constexpr int kSeedContexts = 27, kFirstContexts = 3, kCoefContexts = 15;

inline int token_class(int tok) {
  return tok == 0 ? 0 : tok < 3 ? 1 : 2;
}

// Frame-point residual contexts: axis x class of the previous axis's token (same point and
// frame; 0 for x) x class of the same point and axis's token in the previous frame.
class SeedContexts {
 public:
  explicit SeedContexts(size_t frame_points) : last_(frame_points * 3, 0) {}
  int context(size_t k, int a) const {
    return a * 9 + (a == 0 ? 0 : token_class(prev_)) * 3 + token_class(last_[3 * k + a]);
  }
  void update(size_t k, int a, int tok) {
    prev_ = tok;
    last_[3 * k + a] = static_cast<uint8_t>(tok);
  }

 private:
  std::vector<uint8_t> last_;
  int prev_ = 0;
};

inline int coef_context(size_t l, int prev_token) {
  const int band = l == 0 ? 0 : l < 4 ? 1 : l < 16 ? 2 : l < 64 ? 3 : 4;
  const int prev = prev_token == 0 ? 0 : prev_token < 3 ? 1 : 2;
  return band * 3 + prev;
}

// Grid-mode residual contexts: kind x axis x class of the previous axis's token (same sample; 0 for
// x) x class of the same point and axis's token in the previous frame.
constexpr int kGridContexts = kPointPredictors * 27;

inline int grid_context(int kind, int a, int prev_tok, int last_frame_tok) {
  return kind * 27 + a * 9 + (a == 0 ? 0 : token_class(prev_tok)) * 3 + token_class(last_frame_tok);
}

}  // namespace pdct
}  // namespace capz
