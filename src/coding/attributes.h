// Lossless coding of one window of per-point attribute channels (PCD fields other than x y z:
// colour, intensity, normals, labels, ...); the byte layout is docs/FORMAT.md 13 (`ATTR`).
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

// True when some field is a candidate for predictor 9 (FORMAT.md 13.4: float32 normal_z after
// normal_x and normal_y, or a float32 count-3 normal* field): the encoder then writes a 6.0
// stream.
bool has_unit_candidate(const std::vector<AttrSpec>& specs);

// The ATTR payload after the window index: per attribute, its transform and data.
// valid: the window's gap mask (frames x points, from POSW / MASK), or nullptr for none (the
// decoder must be given the same). v6: a 6.x stream (FORMAT.md 13: predictor 9 and transforms 4
// and 5 may be used). v7 (with v6): a 7.x stream; with q, the window's POSW integers (frames x
// points x 3, as the decoder will have them at the valid samples), predictors 10 and 11 may be
// used (FORMAT.md 13.5); q nullptr: they are not (positions as transform output).
std::vector<uint8_t> encode_attributes(const std::vector<AttrSpec>& specs,
                                       const std::vector<std::vector<uint8_t>>& data,
                                       const uint8_t* valid, size_t frames, size_t points,
                                       size_t width, bool v6 = false, bool v7 = false,
                                       const int32_t* q = nullptr);

// Decodes what encode_attributes wrote into *out (one byte array per spec, resized). Throws
// Error(kCorrupt) naming `what` on a bad transform or predictor, a window larger than the
// payload can hold (checked before allocating), a truncated block or bytes left over.
// v6: the stream is 6.x (predictor 9, transforms 4 and 5 allowed; in a 5.x stream corrupt).
// v7 (with v6): the stream is 7.x (predictors 10 and 11 allowed, corrupt otherwise); q: the
// window's POSW integers (frames x points x 3), nullptr when it has none (then predictors 10
// and 11 are corrupt).
void decode_attributes(const uint8_t* data, size_t size, const std::vector<AttrSpec>& specs,
                       const uint8_t* valid, size_t frames, size_t points, size_t width,
                       std::vector<std::vector<uint8_t>>* out, const std::string& what,
                       bool v6 = false, bool v7 = false, const int32_t* q = nullptr);

}  // namespace capz
