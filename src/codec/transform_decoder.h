// Decoder library (capz_decode): builds without PCL and without the transform encoders.
// The decode side of a transform codec (ts, pdct): what a reader needs to turn a codec payload
// back into the codec's reconstruction. The encode side (transform.h) pairs each of these with
// an encoder.
#pragma once

#include <cstddef>
#include <cstdint>
#include <vector>

namespace capz {

class TransformDecoder {
 public:
  virtual ~TransformDecoder() = default;
  // Stable numeric id stored in the bitstream (docs/FORMAT.md); never reuse a retired one.
  virtual uint8_t id() const = 0;
  virtual const char* name() const = 0;  // "ts", "pdct"

  // The reconstruction (frames x points x 3) of a payload written by the paired encoder for a
  // window of `frames` x `points`. Throws Error(kCorrupt) on any inconsistency; never reads past
  // `size`, never allocates more than the window needs.
  virtual void decode(const uint8_t* data, size_t size, size_t frames, size_t points,
                      std::vector<double>* recon) const = 0;
};

}  // namespace capz
