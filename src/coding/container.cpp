// The container's reader (docs/FORMAT.md 3, 4, 17): the file header checked, chunks read and
// checked, HEAD and INDX decoded; the writer is container_encode.cpp.
#include "coding/container.h"

#include <cstring>

#include "capz/error.h"
#include "coding/bytes.h"
#include "coding/crc32c.h"
#include "coding/entropy.h"

namespace capz {

std::string chunk_what(const std::string& name, const Chunk& c) {
  return (name.empty() ? std::string() : name + ": ") + "chunk " + c.type + " at byte " +
         std::to_string(c.offset);
}

namespace {

// A stream of capz 0.1.0 or earlier (FORMAT.md 2): refused, with how to upgrade it.
[[noreturn]] void refuse_prerelease(const uint8_t* data, size_t size, const std::string& name) {
  const std::string version =
      size >= 11 ? " (format " + std::to_string(data[9]) + "." + std::to_string(data[10]) + ")"
                 : "";
  fail(ErrorCode::kUnsupportedVersion, name,
       "a pre-release capz stream" + version + "; this capz reads format " +
           std::to_string(kFormatNewestRead.major) +
           ".x: decompress it with capz 0.1.0 (git tag v0.1.0) and compress it again (see "
           "CHANGELOG.md)");
}

}  // namespace

StreamFeatures check_file_header(const uint8_t* data, size_t size, const std::string& name) {
  if (size >= 9 && std::memcmp(data, kPrereleaseMagic, 9) == 0) refuse_prerelease(data, size, name);
  if (size < 9 || std::memcmp(data, kCapzMagic, 9) != 0) {
    if (size >= 5 &&
        (std::memcmp(data + 1, "CAPZ", 4) == 0 || std::memcmp(data + 1, "capz", 4) == 0))
      fail(ErrorCode::kCorrupt, name, "damaged .capz magic (a text-mode transfer?)");
    fail(ErrorCode::kNotOurFormat, name, "not a .capz file (wrong magic)");
  }
  // The version bytes carry a CRC of their own, so a flipped major or minor byte is caught here,
  // not later by chunks that fail to decode. Every later version keeps this header.
  if (size < kFileHeaderBytes) fail(ErrorCode::kCorrupt, name, "truncated in the file header");
  if (crc32c(data, 11) != load_le32(data + 11))
    fail(ErrorCode::kCorrupt, name,
         "damaged file header: the version bytes (" + std::to_string(data[9]) + "." +
             std::to_string(data[10]) + ") fail their CRC");
  if (data[9] > kFormatNewestRead.major)
    fail(ErrorCode::kUnsupportedVersion, name,
         "format version " + std::to_string(data[9]) + "." + std::to_string(data[10]) +
             " is newer than this capz reads (" + std::to_string(kFormatNewestRead.major) + ".x)");
  if (data[9] < kFormatNewestRead.major)
    fail(ErrorCode::kCorrupt, name,
         "format major version " + std::to_string(data[9]) + " does not exist");
  StreamFeatures f;
  f.minor = data[10];
  return f;
}

bool known_chunk(const std::string& type) {
  static const char* const kTypes[] = {"HEAD", "META", "INDX", "POSW", "MASK", "C3DW",
                                       "ANLG", "ROTW", "ATTR", "HASH", "C3DR", "TRCR",
                                       "PCDR", "C3DP", "TRCP", "PCDP", "SCNW"};
  for (const char* t : kTypes)
    if (type == t) return true;
  return false;
}

void check_chunk_known(const Chunk& c, const StreamFeatures& f, const std::string& name) {
  if (known_chunk(c.type) || (!c.type.empty() && c.type[0] >= 'a' && c.type[0] <= 'z')) return;
  fail(ErrorCode::kUnsupportedVersion, name,
       "chunk " + c.type + " of format " + f.version() + " is not known to this decoder (reads " +
           std::to_string(kFormatNewestRead.major) + "." + std::to_string(kFormatNewestRead.minor) +
           "), at byte " + std::to_string(c.offset));
}

Chunk read_chunk(const uint8_t* data, size_t size, size_t offset, const std::string& name,
                 size_t base) {
  Chunk c;
  c.offset = offset;
  if (offset > size || size - offset < kChunkOverhead)
    fail(ErrorCode::kCorrupt, name,
         "truncated: chunk header at byte " + std::to_string(offset) +
             " runs past the end of the file");
  const uint8_t* p = data + (offset - base);
  for (int i = 0; i < 4; ++i) {
    if (p[i] < 0x20 || p[i] > 0x7E)
      fail(ErrorCode::kCorrupt, name, "byte " + std::to_string(offset) + " does not start a chunk");
    c.type.push_back(static_cast<char>(p[i]));
  }
  uint32_t len = static_cast<uint32_t>(p[4]) | static_cast<uint32_t>(p[5]) << 8 |
                 static_cast<uint32_t>(p[6]) << 16 | static_cast<uint32_t>(p[7]) << 24;
  if (len > size - offset - kChunkOverhead)
    fail(ErrorCode::kCorrupt, name,
         "truncated: " + chunk_what("", c) + " says " + std::to_string(len) +
             " bytes, the file has " + std::to_string(size - offset - kChunkOverhead));
  c.payload = p + 8;
  c.size = len;
  c.end = offset + kChunkOverhead + len;
  const uint8_t* q = p + 8 + len;
  uint32_t stored = static_cast<uint32_t>(q[0]) | static_cast<uint32_t>(q[1]) << 8 |
                    static_cast<uint32_t>(q[2]) << 16 | static_cast<uint32_t>(q[3]) << 24;
  if (crc32c_update(crc32c(p, 4), c.payload, len) != stored)
    fail(ErrorCode::kCorrupt, name, chunk_what("", c) + ": CRC mismatch (damaged file)");
  return c;
}

namespace {

// HEAD's feature bits 3 (ragged frames), 5 (points reordered) and 6 (octree frames) into h, each
// checked against the format and the other fields; bit 7 (a later minor version's) refused.
void decode_scan_flags(uint8_t flags, uint8_t mode, const StreamFeatures& f,
                       const std::string& what, StreamHeader* h) {
  for (int bit = 7; bit < 8; ++bit)  // FORMAT.md 17: a flag a later minor version adds
    if (flags >> bit & 1)
      fail(ErrorCode::kUnsupportedVersion, what,
           "feature bit " + std::to_string(bit) + " of format " + f.version() +
               " is not known to this decoder");
  h->ragged = (flags & 8) != 0;  // "Scans (format 1.1)": frames of their own point counts
  if (h->ragged && !f.ragged_frames())
    fail(ErrorCode::kCorrupt, what, "feature bit 3 (ragged frames) in a format 1.0 stream");
  // Mode 3 only lossless: every window raw ("Raw windows", format 1.1).
  if (h->ragged &&
      (h->points != 0 || (flags & 2) != 0 || h->codec != 0 || (mode == 3 && !(flags & 1))))
    fail(ErrorCode::kCorrupt, what,
         "ragged frames with points, a transform or position mode 3 without lossless");
  h->points_reordered = (flags & 32) != 0;  // "Scans (format 1.1)": points reordered
  if (h->points_reordered && !f.ragged_frames())
    fail(ErrorCode::kCorrupt, what, "feature bit 5 (points reordered) in a format 1.0 stream");
  if (h->points_reordered && (!h->ragged || (flags & 1) != 0))
    fail(ErrorCode::kCorrupt, what,
         "feature bit 5 (points reordered) without ragged frames or with lossless positions");
  h->octree_frames = (flags & 64) != 0;  // "Octree frames" (format 1.1)
  if (h->octree_frames && !h->points_reordered)
    fail(ErrorCode::kCorrupt, what, "feature bit 6 (octree frames) without points reordered");
}

// HEAD's feature bit 1 (transform output) into h, with its KG target read from r and checked;
// without it, the grid modes' step checked.
void decode_transform_output(ByteReader* r, uint8_t flags, uint8_t mode, const std::string& what,
                             StreamHeader* h) {
  h->transform_output = (flags & 2) != 0;
  if (h->transform_output) {  // FORMAT.md 4.3: the transform's reconstruction is the output
    h->kg_target = r->f64();
    if (flags & 1) fail(ErrorCode::kCorrupt, what, "transform output cannot be lossless");
    if (h->codec == 0)
      fail(ErrorCode::kCorrupt, what, "transform output without a transform codec");
    if (mode != 0 || h->step != 0 || h->max_error != 0)
      fail(ErrorCode::kCorrupt, what, "transform output with a grid mode, step or bound");
    if (h->points == 0) fail(ErrorCode::kCorrupt, what, "transform output without points");
    if (!(h->kg_target > 0 && std::isfinite(h->kg_target)))
      fail(ErrorCode::kCorrupt, what, "transform output: KG target is not a positive number");
  } else if ((mode == 0 || mode == 1 || mode == 4) && !(h->step > 0 && std::isfinite(h->step)))
    fail(ErrorCode::kCorrupt, what, "grid step is not a positive number");
}

// HEAD's frame_format of a .bin folder in a declared record ("Frame-file sources").
constexpr uint8_t kDeclaredBinFolder = 6;

// HEAD's feature bit 4 (a frame-file source, named after the fields above): the frame-file
// format read from r and checked (4, 5 or kDeclaredBinFolder), returned (fmt, which must be 0).
uint8_t decode_frame_file_source(ByteReader* r, uint8_t fmt, const StreamFeatures& f,
                                 const std::string& what) {
  if (!f.frame_file_sources())
    fail(ErrorCode::kCorrupt, what, "feature bit 4 (frame-file source) in a format 1.0 stream");
  if (fmt != 0)
    fail(ErrorCode::kCorrupt, what,
         "frame-file source with source format " + std::to_string(fmt) + " (must be 0)");
  fmt = r->u8();
  if (fmt != static_cast<uint8_t>(Format::kBinFolder) &&
      fmt != static_cast<uint8_t>(Format::kPLYFolder) && fmt != kDeclaredBinFolder)
    fail(ErrorCode::kCorrupt, what, "unknown frame-file format " + std::to_string(fmt));
  return fmt;
}

}  // namespace

StreamHeader decode_header(const Chunk& c, const std::string& name, const StreamFeatures& f) {
  const std::string what = chunk_what(name, c);
  ByteReader r(c.payload, c.size, what);
  StreamHeader h;
  h.frames = r.u64();
  h.points = r.u32();
  h.window_frames = r.u32();
  uint8_t fmt = r.u8(), mode = r.u8();
  h.codec = r.u8();
  uint8_t flags = r.u8();
  h.step = r.f64();
  h.max_error = r.f64();
  h.analog_channels = r.u32();
  h.analog_samples_per_frame = r.u32();
  if (fmt > 3) fail(ErrorCode::kCorrupt, what, "unknown source format " + std::to_string(fmt));
  if (mode > 4) fail(ErrorCode::kCorrupt, what, "unknown position mode " + std::to_string(mode));
  if (h.window_frames == 0 || h.window_frames > kMaxWindowFrames)
    fail(ErrorCode::kCorrupt, what,
         "window of " + std::to_string(h.window_frames) + " frames (1.." +
             std::to_string(kMaxWindowFrames) + ")");
  decode_scan_flags(flags, mode, f, what, &h);
  decode_transform_output(&r, flags, mode, what, &h);
  if (flags & 4) {  // FORMAT.md 4.4: the rotation layout
    h.rotation_segments = r.u32();
    h.rotation_samples_per_frame = r.u32();
    if (h.rotation_segments == 0 || h.rotation_samples_per_frame == 0)
      fail(ErrorCode::kCorrupt, what, "rotations with 0 segments or 0 samples per frame");
  }
  if (flags & 16) fmt = decode_frame_file_source(&r, fmt, f, what);
  if (h.frames > (uint64_t{1} << 40)) fail(ErrorCode::kCorrupt, what, "implausible frame count");
  if ((h.analog_channels == 0) != (h.analog_samples_per_frame == 0) && h.analog_channels != 0)
    fail(ErrorCode::kCorrupt, what, "analog channels without samples per frame");
  h.bin_record_declared = fmt == kDeclaredBinFolder;
  h.source_format = h.bin_record_declared ? Format::kBinFolder : static_cast<Format>(fmt);
  h.mode = static_cast<PosMode>(mode);
  h.lossless = (flags & 1) != 0;
  return h;
}

void check_header_fits(const StreamHeader& h, size_t file_size, const std::string& name) {
  const size_t windows = h.windows();
  if (windows > file_size / kChunkOverhead)
    fail(ErrorCode::kCorrupt, name,
         "HEAD claims " + std::to_string(windows) + " windows; the file cannot hold them");
  // No frames or no samples per frame count as one: the points, channels and segments still
  // size the lists decode_meta fills (labels the C3D parameters give are padded to the counts).
  auto at_least_1 = [](uint64_t v) { return static_cast<double>(std::max<uint64_t>(v, 1)); };
  const double frames = at_least_1(h.frames);
  const double samples = frames * h.points;
  const double analog = frames * at_least_1(h.analog_samples_per_frame) * h.analog_channels;
  const double rotations =
      frames * at_least_1(h.rotation_samples_per_frame) * h.rotation_segments * 17;
  if (samples > static_cast<double>(file_size) * kMaxSymbolsPerByte ||
      analog > static_cast<double>(file_size) * static_cast<double>(kMaxAnalogValuesPerByte) ||
      rotations > static_cast<double>(file_size) * kMaxSymbolsPerByte)
    fail(ErrorCode::kCorrupt, name, "HEAD claims more samples than the file can hold");
}

std::vector<IndexEntry> decode_index(const Chunk& c, const std::string& name) {
  ByteReader r(c.payload, c.size, chunk_what(name, c));
  uint64_t n = r.count(16, "window count");
  std::vector<IndexEntry> idx(static_cast<size_t>(n));
  for (auto& e : idx) {
    e.offset = r.u64();
    e.bytes = r.u64();
  }
  if (r.u32() != c.size) fail(ErrorCode::kCorrupt, chunk_what(name, c), "bad trailing length");
  return idx;
}

}  // namespace capz
