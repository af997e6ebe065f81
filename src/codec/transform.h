// Transform codecs (ts, pdct) plug in front of the container's bound layer through this
// interface. A transform predicts a whole window of positions; the bound layer then quantises
// the original on the user's grid and entropy-codes (original - prediction) on that grid, so
// the max-error bound holds whatever the transform did. With only a KG target (no max error),
// the bound layer may be skipped and the transform's reconstruction is the output.
#pragma once

#include <cstdint>
#include <map>
#include <string>
#include <vector>

#include "codec/transform_decoder.h"

namespace capz {

// A read-only view of a block of positions, as transform encoders see it.
// xyz: frames x points x 3 (frame-major, see take.h); valid: frames x points (1 = measured).
// Gap samples in xyz hold filled-in values chosen by the caller (never garbage, never NaN).
struct PositionsView {
  size_t frames = 0;
  size_t points = 0;
  const double* xyz = nullptr;
  const uint8_t* valid = nullptr;
};

struct TransformParams {
  double max_error = 0;  // per-coordinate bound in the take's units; 0 = none given
  // The bound layer's grid step (quantiser.h: q = round-half-away(x / grid)) when it is known;
  // 0 = not given (a codec may then assume grid_step_for_bound(max_error)). A transform whose
  // reconstruction lies on this grid leaves the bound layer nothing to code.
  double grid_step = 0;
  double kg_error = 0;  // KG error target in percent (see metrics.h); 0 = none given
  int clusters = 0;     // 0 = the codec's default, -1 = auto (search)
  // Codec-specific knobs from the CLI's repeated `--codec-opt key=value`; codecs document
  // their keys in docs/CLI.md and reject unknown ones with Error(kInvalidParameter).
  std::map<std::string, std::string> options;
};

// Positions (frames x points x 3) with gaps filled as the container fills them before a transform
// sees them (`in.valid` still marks the measured samples): a gap holds the point's last valid
// value, a leading gap its first valid one, a point never valid in the window 0.
std::vector<double> fill_gaps(size_t frames, size_t points, const double* xyz,
                              const uint8_t* valid);

// The encode side of a transform codec, paired with its decoder (transform_decoder.h), which
// holds the codec's id and name.
class TransformCodec {
 public:
  virtual ~TransformCodec() = default;
  virtual const TransformDecoder& decoder() const = 0;
  uint8_t id() const { return decoder().id(); }
  const char* name() const { return decoder().name(); }
  // decoder().decode(): what the closed loop and the encoder's self-check run.
  void decode(const uint8_t* data, size_t size, size_t frames, size_t points,
              std::vector<double>* recon) const {
    decoder().decode(data, size, frames, points, recon);
  }

  // Throws Error(kInvalidParameter) when params.options holds a key this codec does not know
  // or a value out of range (also params.clusters). Called before any encoding, so that a
  // mistyped --codec-opt is an error even under --codec auto, which skips a codec whose
  // encode() throws kInvalidParameter because it does not apply to the take.
  virtual void check_params(const TransformParams& params) const = 0;

  // Encodes one window. Appends the payload to *out and sets *recon (frames x points x 3) to
  // exactly what decode() will return for that payload (the closed loop depends on it).
  // `in.valid` marks measured samples; gap samples carry filled values and may be predicted
  // freely. Deterministic: the same input and params give the same bytes.
  virtual void encode(const PositionsView& in, const TransformParams& params,
                      std::vector<uint8_t>* out, std::vector<double>* recon) const = 0;
};

}  // namespace capz
