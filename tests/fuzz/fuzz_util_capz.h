// For the .capz fuzz targets: a copy of a stream with every chunk's CRC recomputed, so mutated
// payloads reach the decoders behind the CRC check (a mutation almost never keeps a CRC valid).
#pragma once

#include <cstdint>
#include <vector>

#include "capz/codec.h"
#include "coding/container.h"
#include "coding/crc32c.h"

namespace capz_fuzz {

// What the .capz targets decode with: a memory limit of 256 MiB of decoded samples, so that a
// small input whose header asks for a huge take is refused (kMemoryLimit) rather than exhausting
// libFuzzer's 2 GB (a valid stream may ask 2^18 analog values per byte).
inline capz::DecompressOptions decode_options() {
  capz::DecompressOptions o;
  o.memory_limit = uint64_t{256} << 20;
  return o;
}

// Whether `whole`, decoded by decompress(), has the shape of a stream of `frames` frames
// (`ragged`: of their own point counts, `total` points in all): the same. A stream of one ragged
// frame (a single frame file the encoder coded with the scan coder) is the fixed take of one
// frame to decompress(), the frame source and describe() alike, as a reader gives one frame file.
inline bool decoded_shape_matches(size_t frames, bool ragged, size_t total,
                                  const capz::Take& whole) {
  return whole.frames == frames && whole.total_points() == total && whole.ragged() == ragged;
}

inline uint32_t le32(const uint8_t* p) {
  return static_cast<uint32_t>(p[0]) | static_cast<uint32_t>(p[1]) << 8 |
         static_cast<uint32_t>(p[2]) << 16 | static_cast<uint32_t>(p[3]) << 24;
}

// Walks the chunk framing (type, u32 length, payload, CRC) from the file header on, rewriting
// each CRC; stops at the first chunk that runs past the end.
inline std::vector<uint8_t> with_fixed_crcs(const uint8_t* data, size_t size) {
  std::vector<uint8_t> v(data, data + size);
  size_t off = capz::kFileHeaderBytes;
  while (off <= v.size() && v.size() - off >= capz::kChunkOverhead) {
    const uint32_t len = le32(&v[off + 4]);
    if (len > v.size() - off - capz::kChunkOverhead) break;
    uint32_t crc = capz::crc32c_update(capz::crc32c(&v[off], 4), &v[off + 8], len);
    for (int i = 0; i < 4; ++i) v[off + 8 + len + i] = static_cast<uint8_t>(crc >> (8 * i));
    off += capz::kChunkOverhead + len;
  }
  return v;
}

}  // namespace capz_fuzz
