// Decoder library (capz_decode): builds without PCL and without the transform encoders.
// The transform decoders a reader knows, by stored id (docs/FORMAT.md 4.1). A codec adds its
// decoder with one line in decoder_registry.cpp (and its encoder in registry.cpp).
#pragma once

#include <cstdint>
#include <vector>

#include "codec/transform_decoder.h"

namespace capz {

// nullptr when unknown; id 0 means "none".
const TransformDecoder* find_decoder(uint8_t id);
std::vector<const TransformDecoder*> all_decoders();

}  // namespace capz
