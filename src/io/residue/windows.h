// capz — the window loops every residue format shares: encoding a file's windows from a frame
// source, and rebuilding a file window by window.
#pragma once

#include <cstddef>
#include <cstdint>
#include <functional>
#include <string>
#include <vector>

#include "capz/stream.h"
#include "io/residue/pack.h"

namespace capz {
namespace residue {

// Reads every frame of `frames` in blocks of `block` and appends encode(block) to r->windows.
void encode_windows(FrameSource& frames, size_t block,
                    const std::function<std::vector<uint8_t>(const FrameBlock&)>& encode,
                    FileResidue* r);

// Reads every frame of `frames` in blocks of `block`; for each, rebuild(block, payload, &bytes)
// gives the block's original bytes, handed to write(). Throws Error(kCorrupt) naming `name`
// when the residue does not hold one window per block.
void rebuild_windows(const FileResidue& residue, FrameSource& frames, size_t block,
                     const std::function<void(const FrameBlock&, const std::vector<uint8_t>&,
                                              std::vector<uint8_t>*)>& rebuild,
                     const std::function<void(const uint8_t*, size_t)>& write,
                     const std::string& name);

}  // namespace residue
}  // namespace capz
