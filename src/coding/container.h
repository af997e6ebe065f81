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
#include "coding/stream_features.h"

namespace capz {

// Format 1.x (FORMAT.md 2): "\x89CAPZ\r\n\x1a\n". The pre-release formats 1.0-9.3 (capz 0.1.0
// and earlier) began with "\x89capz\r\n\x1a\n"; such a stream is refused (kUnsupportedVersion).
constexpr uint8_t kCapzMagic[9] = {0x89, 'C', 'A', 'P', 'Z', 0x0D, 0x0A, 0x1A, 0x0A};
constexpr uint8_t kPrereleaseMagic[9] = {0x89, 'c', 'a', 'p', 'z', 0x0D, 0x0A, 0x1A, 0x0A};
constexpr uint8_t kCapzMajor = kFormatWritten.major;  // capz/version.h
constexpr uint8_t kCapzMinor = kFormatWritten.minor;
constexpr size_t kFileHeaderBytes = 15;  // magic, major, minor, CRC-32C of those 11 bytes
constexpr size_t kChunkOverhead = 12;    // type + length + crc

// Appends the file header of a stream of format kCapzMajor.minor: kCapzMinor, or
// kFormatScans.minor for a stream of ragged frames.
void write_file_header(std::vector<uint8_t>* out, uint8_t minor = kCapzMinor);
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

// Checks magic (kNotOurFormat; a pre-release stream kUnsupportedVersion with how to upgrade it),
// the header's CRC (kCorrupt) and version (kUnsupportedVersion for a major other than 1); returns
// the stream's features. `size` bytes are at `data` (kFileHeaderBytes make the header).
StreamFeatures check_file_header(const uint8_t* data, size_t size, const std::string& name);
// Throws kUnsupportedVersion unless a decoder of this format knows chunk c's type or may skip it
// (FORMAT.md 2: a type whose first letter is lower case is ancillary), naming stream `name`, the
// chunk, the stream's version and its offset.
void check_chunk_known(const Chunk& c, const StreamFeatures& f, const std::string& name);
// Whether `type` is a chunk type of format 1.0.
bool known_chunk(const std::string& type);
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
  // HEAD flags bit 5 ("Scans (format 1.1)"): each frame's points are in the encoder's order,
  // not the source's (--point-order any); requires ragged and not lossless.
  bool points_reordered = false;
  // HEAD flags bit 6 ("Octree frames", format 1.1): the SCNW payloads may hold octree frames;
  // requires points_reordered.
  bool octree_frames = false;

  // HEAD's frame_format 6 ("Frame-file sources"): a .bin folder (source_format kBinFolder) in a
  // declared record, META's fields after x y z.
  bool bin_record_declared = false;

  bool rotations() const { return rotation_segments > 0; }
  // HEAD flags bit 4 ("Scans (format 1.1)"): the source is a PLY or .bin folder (source_format
  // kPLYFolder or kBinFolder), written as HEAD's appended frame_format.
  bool frame_file_source() const {
    return source_format == Format::kPLYFolder || source_format == Format::kBinFolder;
  }
  size_t windows() const {
    return frames == 0 ? 0 : static_cast<size_t>((frames + window_frames - 1) / window_frames);
  }
};
constexpr uint32_t kMaxWindowFrames = 8192;
// Most analog values a coded byte may stand for: the analog coder codes a constant channel of a
// whole window in a few bytes (FORMAT.md ANLG), so the cap is 2^18.
constexpr size_t kMaxAnalogValuesPerByte = size_t{1} << 18;
std::vector<uint8_t> encode_header(const StreamHeader& h);
// f: the stream's features (a HEAD flag bit that 1.0 does not define is kUnsupportedVersion).
StreamHeader decode_header(const Chunk& c, const std::string& name, const StreamFeatures& f = {});
// Throws kCorrupt unless a file of `file_size` bytes can hold what `h` claims: one chunk per
// window at least, and no more coded values (samples, analog values) than
// kMaxSymbolsPerByte per byte. Frames are then at most file_size / kChunkOverhead *
// kMaxWindowFrames, so everything sized per frame (decode_meta's TRC/PCD lists) is bounded by
// the file. Call it before decode_meta.
void check_header_fits(const StreamHeader& h, size_t file_size, const std::string& name);

struct IndexEntry {
  uint64_t offset = 0;
  uint64_t bytes = 0;
};
std::vector<uint8_t> encode_index(const std::vector<IndexEntry>& idx);
std::vector<IndexEntry> decode_index(const Chunk& c, const std::string& name);

}  // namespace capz
