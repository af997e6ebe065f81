// Coding of one window's streams (docs/FORMAT.md 3.3 - 3.6): positions as integers, the gap
// mask, C3D per-sample words and analog channels. Each encode_* returns a chunk payload; each
// decode_* parses one, throwing Error(kCorrupt) naming `what` on any inconsistency.
#pragma once

#include <cstddef>
#include <cstdint>
#include <string>
#include <vector>

#include "coding/quantiser.h"

namespace capz {

class TransformCodec;
struct TransformParams;

// Integers of one window. q: frames x points x 3 (gap samples: anything, filled on coding);
// lo: the low 32 bits in mode kFloat64, else empty. valid: frames x points.
struct WindowInts {
  size_t frames = 0, points = 0;
  std::vector<int32_t> q;
  std::vector<uint32_t> lo;
  std::vector<uint8_t> valid;
};

// The codec's view of the grid (used to map its reconstruction to integer predictions).
struct GridInfo {
  PosMode mode = PosMode::kGrid;
  double step = 0;  // kGrid: x = q * step
};

// POSW payload after the window index and has_mask byte: codec bytes, modes, residuals.
// `codec_payload` is what the transform codec wrote (empty if none), `tpred` its prediction on
// the grid (frames x points x 3, empty if none).
// `scheme` is the coding generation (FORMAT.md 3.3): 3 (format 3.x: smooth and period
// predictors, 448 residual contexts), what capz writes; 2 (format 2.x: reference predictors, 84
// contexts) and 1 (format 1.x) for reading old streams and for their tests.
constexpr int kPositionScheme = 3;
// The scheme of a stream of format major version `major`.
inline int position_scheme(int major) {
  return major >= 3 ? 3 : major == 2 ? 2 : 1;
}
std::vector<uint8_t> encode_positions(const WindowInts& w,
                                      const std::vector<uint8_t>& codec_payload,
                                      const std::vector<int32_t>& tpred, bool float64,
                                      int scheme = kPositionScheme);
// Parses what encode_positions wrote from `r`'s current position to the end of the payload.
// `codec_payload` receives the codec bytes; `make_tpred` is called with them to produce the
// transform prediction when any point's predictor needs it (it throws if there is no codec).
struct PositionsPayload {
  const uint8_t* codec_bytes = nullptr;
  size_t codec_size = 0;
  const uint8_t* modes = nullptr;
  size_t modes_size = 0;
  const uint8_t* residuals = nullptr;
  size_t residuals_size = 0;
};
PositionsPayload split_positions(const uint8_t* data, size_t size, const std::string& what);
// Decodes into w (frames, points, valid set by the caller). tpred may be empty if no codec.
// `scheme`: position_scheme(major) of the stream.
void decode_positions(const PositionsPayload& pp, const std::vector<int32_t>& tpred, bool float64,
                      int scheme, WindowInts* w, const std::string& what);
// Predictor modes of a payload.
std::vector<uint8_t> decode_modes(const PositionsPayload& pp, size_t points, int scheme,
                                  const std::string& what);

// Gap mask: frames x points, 1 = valid. Runs per point (3.4).
std::vector<uint8_t> encode_mask(const uint8_t* valid, size_t frames, size_t points);
void decode_mask(const uint8_t* data, size_t size, size_t frames, size_t points, uint8_t* valid,
                 const std::string& what);

// C3D residual (file units) and camera bytes of a window, frames x points each (3.5), with the
// window's gap mask `valid` (1 = valid). residual_on_grid (from residuals_on_grid()): every valid
// sample's residual is float32(k * point_scale) exactly and every gap's is -1 (mode 0).
// frame_flags: a repeat flag per frame (modes 2 and 3, since 3.1); false writes the 3.0 modes.
std::vector<uint8_t> encode_c3d_words(const float* residual, const uint8_t* camera,
                                      const uint8_t* valid, size_t count, size_t points,
                                      double point_scale, bool residual_on_grid,
                                      bool frame_flags = true);
void decode_c3d_words(const uint8_t* data, size_t size, const uint8_t* valid, size_t count,
                      size_t points, double point_scale, float* residual, uint8_t* camera,
                      const std::string& what);
bool residuals_on_grid(const std::vector<float>& residual, const std::vector<uint8_t>& valid,
                       double point_scale);

// Analog samples of a window: rows x channels, row-major doubles (3.6). Kind per channel is
// chosen over the whole take by analog_kinds() so every window agrees.
std::vector<uint8_t> analog_kinds(const std::vector<double>& values, int channels);
// The same decision accumulated over consecutive blocks of whole rows (count values): start
// from `channels` kinds of 0 (integers) and feed the blocks in order.
void update_analog_kinds(const double* values, size_t count, int channels,
                         std::vector<uint8_t>* kinds);
std::vector<uint8_t> encode_analog(const double* rows, size_t nrows, int channels,
                                   const std::vector<uint8_t>& kinds);
void decode_analog(const uint8_t* data, size_t size, size_t nrows, int channels, double* rows,
                   const std::string& what);

}  // namespace capz
