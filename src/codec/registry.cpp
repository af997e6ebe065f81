#include "codec/registry.h"

#include "codec/pdct/pdct_codec.h"
#include "codec/ts/ts_codec.h"

namespace capz {

std::vector<const TransformCodec*> all_codecs() {
  // One line per codec; ids are stored in files and never reused (1 ts, 2 pdct).
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

const TransformCodec* find_codec(uint8_t id) {
  for (const TransformCodec* c : all_codecs())
    if (c->id() == id) return c;
  return nullptr;
}

}  // namespace capz
