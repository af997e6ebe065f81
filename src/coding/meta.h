// META, the stream's metadata chunk (docs/FORMAT.md 5).
#pragma once

#include <cstdint>
#include <string>
#include <vector>

#include "capz/take.h"
#include "coding/container.h"

namespace capz {

// META: everything of the Take except positions, mask, analog values, rotation samples and the
// C3D per-sample words. decode_meta fills those fields of *take (frames/points, the analog
// layout and take->rotations' segments and samples per frame from the header must already be
// set and checked with check_header_fits; per-frame TRC/PCD lists are checked against them).
// With rotations (segments > 0) META ends with their rate and labels (FORMAT.md 4.3).
// has_sample_words tells whether C3DW chunks follow. ragged: the stream's HEAD has feature bit 3
// (its PCD layout is one of the two shapes "Ragged frames: HEAD and the window chunk" allows). With
// `dictionary` coding 3 (FORMAT.md 8.1) is offered too; meta_coding(payload) tells the one chosen.
std::vector<uint8_t> encode_meta(const Take& take, bool has_sample_words, bool dictionary = false);
// META in coding 0 (its fields as they are): no coding tried, for an encoder that only wants
// the size of the rest of a stream.
std::vector<uint8_t> encode_meta_raw(const Take& take, bool has_sample_words);
// The META payload encode_meta makes of these fields (decode_meta_fields' bytes).
std::vector<uint8_t> code_meta_fields(const std::vector<uint8_t>& fields, bool dictionary);
void decode_meta(const Chunk& c, const std::string& name, Take* take, bool* has_sample_words,
                 bool ragged = false);
// META's fields (the bytes its coding codes), decoded from any coding.
std::vector<uint8_t> decode_meta_fields(const Chunk& c, const std::string& name);
inline int meta_coding(const std::vector<uint8_t>& payload) {
  return payload.empty() ? -1 : payload[0];
}

}  // namespace capz
