// The .capz framing (docs/FORMAT.md sections 3, 4, 15): magic, version, CRC-checked
// chunks, and the HEAD and INDX payloads (META: coding/meta.h).
#pragma once

#include <cstddef>
#include <cstdint>
#include <string>
#include <vector>

#include "capz/take.h"
#include "capz/version.h"
#include "coding/quantiser.h"

namespace capz {

constexpr uint8_t kCapzMagic[9] = {0x89, 'c', 'a', 'p', 'z', 0x0D, 0x0A, 0x1A, 0x0A};
constexpr uint8_t kCapzMajor = kFormatWritten.major;  // capz/version.h; docs/FORMAT.md 17:
constexpr uint8_t kCapzMinor = kFormatWritten.minor;  // what each version added
constexpr size_t kFileHeaderBytes = 11;               // magic + major + minor (1.x - 3.x)
// Bytes of the file header of a stream of major version `major` (FORMAT.md 3): magic, major,
// minor, and from 4.0 on a u32 CRC-32C of those 11 bytes.
inline size_t file_header_bytes(int major) {
  return major >= 4 ? kFileHeaderBytes + 4 : kFileHeaderBytes;
}
constexpr size_t kChunkOverhead = 12;  // type + length + crc

// Appends magic and version `v` (and from 4.0 on the version's CRC).
void write_file_header(std::vector<uint8_t>* out, FormatVersion v = kFormatWritten);
// Appends one chunk: type (4 ASCII bytes), u32 length, payload, CRC-32C of type + payload.
void append_chunk(std::vector<uint8_t>* out, const char type[4],
                  const std::vector<uint8_t>& payload);

struct Chunk {
  std::string type;  // 4 characters
  const uint8_t* payload = nullptr;
  size_t size = 0;
  size_t offset = 0;  // file offset of the chunk's first byte
  size_t end = 0;     // file offset just past its CRC
};
// "NAME: chunk TYPE at byte OFFSET", the start of an error message about chunk c of stream NAME.
std::string chunk_what(const std::string& name, const Chunk& c);

// Checks magic (kNotOurFormat), from 4.0 on the header's CRC (kCorrupt), and version
// (kUnsupportedVersion); returns the minor version. The header is file_header_bytes(data[9])
// long.
int check_file_header(const uint8_t* data, size_t size, const std::string& name);
// Reads the chunk at `offset`: framing and CRC checked (kCorrupt naming the chunk and offset).
// `data` holds the stream's bytes from offset `base` on (base <= offset), `size` is where they
// end: the bytes of the chunk at `offset` must be there (its first 8 suffice when its length
// runs past `size`). Offsets in the result and in messages are stream offsets.
Chunk read_chunk(const uint8_t* data, size_t size, size_t offset, const std::string& name,
                 size_t base = 0);

struct StreamHeader {
  uint64_t frames = 0;
  uint32_t points = 0;
  uint32_t window_frames = 0;
  Format source_format = Format::kUnknown;
  PosMode mode = PosMode::kGrid;
  uint8_t codec = 0;
  bool lossless = false;
  // HEAD flags bit 1: positions are the transform's reconstruction, no grid and no bound layer
  // (docs/FORMAT.md 4.3); kg_target (percent) is then stored after the analog fields.
  bool transform_output = false;
  double kg_target = 0;
  double step = 0;
  double max_error = 0;
  uint32_t analog_channels = 0;
  uint32_t analog_samples_per_frame = 0;
  // HEAD flags bit 2 (docs/FORMAT.md 4.4): the take has rotations, G segments sampled R times
  // per point frame; both 0 without (both at least 1 with), and each window has a ROTW chunk.
  uint32_t rotation_segments = 0;
  uint32_t rotation_samples_per_frame = 0;
  // HEAD flags bit 3 ("Scans (format 1.1)" in docs/FORMAT.md): frames of their own point
  // counts; points is 0 and each window has an SCNW chunk instead of POSW and MASK.
  bool ragged = false;

  bool rotations() const { return rotation_segments > 0; }
  size_t windows() const {
    return frames == 0 ? 0 : static_cast<size_t>((frames + window_frames - 1) / window_frames);
  }
};
constexpr uint32_t kMaxWindowFrames = 8192;
// Most analog values a coded byte may stand for, in a stream of major version `major`: the
// format 1-3 coder spends at least a token per value (kMaxSymbolsPerByte); the 4.x coder codes a
// constant channel of a whole window in a few bytes (FORMAT.md 3.6), so its cap is 2^18.
size_t analog_values_per_byte(int major);  // HEAD window_frames is 1..this (FORMAT.md 4.1)
std::vector<uint8_t> encode_header(const StreamHeader& h);
StreamHeader decode_header(const Chunk& c, const std::string& name);
// Throws kCorrupt unless a file of `file_size` bytes can hold what `h` claims: one chunk per
// window at least, and no more coded values (samples, analog values) than
// kMaxSymbolsPerByte per byte. Frames are then at most file_size / kChunkOverhead *
// kMaxWindowFrames, so everything sized per frame (decode_meta's TRC/PCD lists) is bounded by
// the file. Call it before decode_meta.
void check_header_fits(const StreamHeader& h, size_t file_size, int major, const std::string& name);

struct IndexEntry {
  uint64_t offset = 0;
  uint64_t bytes = 0;
};
std::vector<uint8_t> encode_index(const std::vector<IndexEntry>& idx);
std::vector<IndexEntry> decode_index(const Chunk& c, const std::string& name);

}  // namespace capz
