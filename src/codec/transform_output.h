// The POSW body of a transform-output stream (docs/FORMAT.md 8): the transform codec's block
// alone, length-prefixed. Writer and reader of that layout, in one place. Part of the decoder
// library.
#pragma once

#include <cstddef>
#include <cstdint>
#include <string>
#include <vector>

namespace capz {

std::vector<uint8_t> transform_only_positions(const std::vector<uint8_t>& codec_bytes);

struct CodecOnly {
  const uint8_t* data = nullptr;
  size_t size = 0;
};
// The codec block of such a body; throws kCorrupt naming `what` on a bad length or extra bytes.
CodecOnly split_transform_only(const uint8_t* data, size_t size, const std::string& what);

}  // namespace capz
