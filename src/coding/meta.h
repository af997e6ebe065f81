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
// With rotations (segments > 0) META ends with their rate and labels (FORMAT.md 5.6).
// has_sample_words tells whether C3DW chunks follow. With `dictionary` coding 3 (FORMAT.md 5.1,
// a stream of major 8 or above) is offered too; meta_coding(payload) tells the one chosen.
// decode_meta reads coding 3 only when the stream's `major` is 8 or above.
std::vector<uint8_t> encode_meta(const Take& take, bool has_sample_words, bool dictionary = false);
void decode_meta(const Chunk& c, const std::string& name, Take* take, bool* has_sample_words,
                 int major);
// META's fields (the bytes its coding codes), decoded from any coding.
std::vector<uint8_t> decode_meta_fields(const Chunk& c, const std::string& name, int major);
inline int meta_coding(const std::vector<uint8_t>& payload) {
  return payload.empty() ? -1 : payload[0];
}

}  // namespace capz
