// Lossless coding of one window of per-point attribute channels (PCD fields other than x y z:
// colour, intensity, normals, labels, ...); the byte layout is docs/FORMAT.md 5.3 (`ATTR`).
// Every element comes back bit for bit (NaN payloads, -0.0, padding bytes included).
//
// Input: per attribute (take.h PointAttribute: type F/U/I, size, count), the window's bytes,
// frames x points x count elements of `size` bytes, little-endian. `width` is the frames' WIDTH
// (an organized cloud's row length; `points` for an unorganized one), used by the spatial
// predictors.
#pragma once

#include <cstddef>
#include <cstdint>
#include <string>
#include <vector>

#include "capz/take.h"

namespace capz {

// One attribute's type, as META's PCD layout gives it (name, type, size, count).
using AttrSpec = PCDField;

// The attributes of a PCD layout: its fields other than x y z, in order.
std::vector<AttrSpec> attribute_specs(const std::vector<PCDField>& fields);

// True for the fields the encoder codes through the colour transform (size 4, count 1, named
// rgb or rgba).
bool is_colour_field(const AttrSpec& s);

// The ATTR payload after the window index: transforms, predictors, entropy-coded block.
std::vector<uint8_t> encode_attributes(const std::vector<AttrSpec>& specs,
                                       const std::vector<std::vector<uint8_t>>& data, size_t frames,
                                       size_t points, size_t width);

// Decodes what encode_attributes wrote into *out (one byte array per spec, resized). Throws
// Error(kCorrupt) naming `what` on a bad transform or predictor, a window larger than the
// payload can hold (checked before allocating), a truncated block or bytes left over.
void decode_attributes(const uint8_t* data, size_t size, const std::vector<AttrSpec>& specs,
                       size_t frames, size_t points, size_t width,
                       std::vector<std::vector<uint8_t>>* out, const std::string& what);

}  // namespace capz
