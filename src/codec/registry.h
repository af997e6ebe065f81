// The transform codecs the encoder knows, by CLI name (docs/FORMAT.md 4.1). A codec adds itself
// with one line in registry.cpp; its decoder goes in decoder_registry.cpp.
#pragma once

#include <string>
#include <vector>

#include "codec/transform.h"

namespace capz {

// nullptr when unknown. Names are case-sensitive ("ts", "pdct").
const TransformCodec* find_codec(const std::string& name);
std::vector<const TransformCodec*> all_codecs();

}  // namespace capz
