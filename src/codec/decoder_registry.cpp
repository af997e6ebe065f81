// Decoder library (capz_decode): builds without PCL and without the transform encoders.
#include "codec/decoder_registry.h"

#include "codec/pdct/pdct_decoder.h"
#include "codec/ts/ts_decoder.h"

namespace capz {

std::vector<const TransformDecoder*> all_decoders() {
  // One line per codec; ids are stored in files and never reused (1 ts, 2 pdct).
  static const TsDecoder ts;
  static const PdctDecoder pdct;
  static const std::vector<const TransformDecoder*> decoders = {&ts, &pdct};
  return decoders;
}

const TransformDecoder* find_decoder(uint8_t id) {
  for (const TransformDecoder* d : all_decoders())
    if (d->id() == id) return d;
  return nullptr;
}

}  // namespace capz
