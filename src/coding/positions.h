// Positions of one window as integers (docs/FORMAT.md 8): a predictor per point chosen by an
// estimate of its coded size, then every sample's residual entropy-coded. encode_positions
// returns a POSW payload (after the window index and has_mask byte); split_positions and
// decode_positions parse one, throwing Error(kCorrupt) naming `what` on any inconsistency.
#pragma once

#include <cstddef>
#include <cstdint>
#include <string>
#include <vector>

#include "coding/predict.h"

namespace capz {

// Integers of one window. q: frames x points x 3 (gap samples: anything, filled on coding);
// lo: the low 32 bits in mode kFloat64, else empty. valid: frames x points.
struct WindowInts {
  size_t frames = 0, points = 0;
  std::vector<int32_t> q;
  std::vector<uint32_t> lo;
  std::vector<uint8_t> valid;
};

// POSW payload after the window index and has_mask byte: codec bytes, modes, residuals.
// `codec_payload` is what the transform codec wrote (empty if none), `tpred` its prediction on
// the grid (frames x points x 3, empty if none).
// `ray`: whether (and on what integers) predictor 10 may be chosen (FORMAT.md 7.1; kNone but
// in a stream of mode 0, 1, 2 or 4 whose take the encoder's scan found on rays).
std::vector<uint8_t> encode_positions(const WindowInts& w,
                                      const std::vector<uint8_t>& codec_payload,
                                      const std::vector<int32_t>& tpred, bool float64,
                                      RayKind ray = RayKind::kNone);
// encode_positions' payload with its residual block cut to the bytes of its raw bits (the
// residuals' bits below their tokens, FORMAT.md 2.3; the tokens' range-coded bytes left out): no
// larger than encode_positions' payload, and cheaper (nothing entropy-coded). Not a stream to
// decode: a size bound (EncoderTuning::positions_bound). With `ray` (but in mode 3) it is
// encode_positions' own payload.
std::vector<uint8_t> encode_positions_bound(const WindowInts& w,
                                            const std::vector<uint8_t>& codec_payload,
                                            const std::vector<int32_t>& tpred, bool float64,
                                            RayKind ray = RayKind::kNone);
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
// `ray`: ray_kind(mode) of the stream (predictor 10 is corrupt where it is kNone).
void decode_positions(const PositionsPayload& pp, const std::vector<int32_t>& tpred, bool float64,
                      WindowInts* w, const std::string& what, RayKind ray = RayKind::kNone);
// Predictor modes of a payload.
std::vector<uint8_t> decode_modes(const PositionsPayload& pp, size_t points,
                                  const std::string& what, RayKind ray = RayKind::kNone);

}  // namespace capz
