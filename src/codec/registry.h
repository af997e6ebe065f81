// The transform codecs the container knows, by stored id and by CLI name (docs/FORMAT.md 3.1).
// A codec adds itself with one line in registry.cpp.
#pragma once

#include <cstdint>
#include <string>
#include <vector>

#include "codec/transform.h"

namespace capz {

// nullptr when unknown. Names are case-sensitive ("ts", "pdct"); id 0 means "none".
const TransformCodec* find_codec(const std::string& name);
const TransformCodec* find_codec(uint8_t id);
std::vector<const TransformCodec*> all_codecs();

}  // namespace capz
