// Decoder library (capz_decode): builds without PCL and without the transform encoders.
// pdct codec, decode side: a payload (docs/CODEC-PDCT.md) read and run through the closed loop
// of predict.h, the same loop the encoder (pdct_encoder.h) runs.
#pragma once

#include <cstddef>
#include <cstdint>
#include <vector>

#include "codec/transform_decoder.h"

namespace capz {

class PdctDecoder : public TransformDecoder {
 public:
  static constexpr uint8_t kId = 2;
  uint8_t id() const override { return kId; }
  const char* name() const override { return "pdct"; }
  void decode(const uint8_t* data, size_t size, size_t frames, size_t points,
              std::vector<double>* recon) const override;
};

}  // namespace capz
