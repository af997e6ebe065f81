// capz — the C3D parameter section alone, as the .capz container stores it (a container
// internal, not part of the public API).
#pragma once

#include <cstddef>
#include <cstdint>
#include <string>
#include <vector>

#include "capz/take.h"

namespace capz {

// The C3D parameter section alone, in C3D's own byte layout (Intel processor type, blocks of
// 512 bytes, first 4 bytes = the section header). The .capz container stores C3D parameters in
// exactly this form; see docs/FORMAT.md. Throws Error(kUsage) when a parameter cannot be stored
// (a name, description or entry too long for the layout, a bad type or shape).
std::vector<uint8_t> encode_c3d_parameters(const C3DExtra& extra);
// Parses such a section into extra->groups (nothing else of *extra changes); throws
// Error(kCorrupt) naming `name` when the bytes are not a valid section.
void decode_c3d_parameters(const uint8_t* data, size_t size, const std::string& name,
                           C3DExtra* extra);

}  // namespace capz
