// Decoder library (capz_decode): builds without PCL and without the transform encoders.
// ts codec, decode side: a payload (docs/CODEC-TS.md) read into the quantised model
// (ts_model.h, the layout encoder and decoder share) and reconstructed.
#pragma once

#include <cstddef>
#include <cstdint>
#include <vector>

#include "codec/transform_decoder.h"

namespace capz {

class TsDecoder : public TransformDecoder {
 public:
  static constexpr uint8_t kId = 1;
  uint8_t id() const override { return kId; }
  const char* name() const override { return "ts"; }
  void decode(const uint8_t* data, size_t size, size_t frames, size_t points,
              std::vector<double>* recon) const override;
};

}  // namespace capz
