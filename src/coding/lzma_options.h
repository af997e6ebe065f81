// The liblzma options of a raw LZMA2 block as both its encoder (lzma_block_encode.cpp) and its
// decoder (lzma_block.cpp) set them (docs/FORMAT.md 2.6). Internal to the two.
#pragma once

#include <lzma.h>

#include "coding/lzma_block.h"

namespace capz {

// Preset 9e with the fixed kLzmaDictBytes dictionary, after `preset` when it is not empty.
lzma_options_lzma lzma2_options(LzmaPreset preset = {});

}  // namespace capz
