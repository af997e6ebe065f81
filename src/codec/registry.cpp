#include "codec/registry.h"

#include "codec/pdct/pdct_encoder.h"
#include "codec/ts/ts_encoder.h"

namespace capz {

std::vector<const TransformCodec*> all_codecs() {
  // One line per codec, in the order of their ids (1 ts, 2 pdct).
  static const TsCodec ts;
  static const PdctCodec pdct;
  static const std::vector<const TransformCodec*> codecs = {&ts, &pdct};
  return codecs;
}

const TransformCodec* find_codec(const std::string& name) {
  for (const TransformCodec* c : all_codecs())
    if (name == c->name()) return c;
  return nullptr;
}

}  // namespace capz
