// The container's writer (docs/FORMAT.md 3, 4, 17): the file header, a chunk with its CRC, HEAD
// and INDX; the reader is container.cpp.
#include <cstring>
#include <string>

#include "capz/error.h"
#include "coding/bytes.h"
#include "coding/container.h"
#include "coding/crc32c.h"

namespace capz {

void write_file_header(std::vector<uint8_t>* out, uint8_t minor) {
  out->insert(out->end(), kCapzMagic, kCapzMagic + 9);
  out->push_back(kCapzMajor);
  out->push_back(minor);
  ByteWriter w;
  w.u32(crc32c(out->data() + out->size() - 11, 11));
  out->insert(out->end(), w.buffer().begin(), w.buffer().end());
}

void append_chunk(std::vector<uint8_t>* out, const char type[4],
                  const std::vector<uint8_t>& payload) {
  if (payload.size() > 0xFFFFFFFFull)
    throw Error(ErrorCode::kInternal, std::string("chunk ") + std::string(type, 4) +
                                          " larger than 4 GiB; use smaller windows");
  ByteWriter w;
  w.bytes(reinterpret_cast<const uint8_t*>(type), 4);
  w.u32(static_cast<uint32_t>(payload.size()));
  uint32_t crc = crc32c_update(0, reinterpret_cast<const uint8_t*>(type), 4);
  crc = crc32c_update(crc, payload.data(), payload.size());
  out->insert(out->end(), w.buffer().begin(), w.buffer().end());
  out->insert(out->end(), payload.begin(), payload.end());
  ByteWriter t;
  t.u32(crc);
  out->insert(out->end(), t.buffer().begin(), t.buffer().end());
}

// ---------------------------------------------------------------------------------------------
std::vector<uint8_t> encode_header(const StreamHeader& h) {
  ByteWriter w;
  w.u64(h.frames);
  w.u32(h.points);
  w.u32(h.window_frames);
  // "Scans (format 1.1)": a frame-file source is named by the appended frame_format, its
  // source_format byte 0, so that decoders without feature bit 4 refuse it by name.
  w.u8(h.frame_file_source() ? 0 : static_cast<uint8_t>(h.source_format));
  w.u8(static_cast<uint8_t>(h.mode));
  w.u8(h.codec);
  w.u8(static_cast<uint8_t>((h.lossless ? 1 : 0) | (h.transform_output ? 2 : 0) |
                            (h.rotations() ? 4 : 0) | (h.ragged ? 8 : 0) |
                            (h.frame_file_source() ? 16 : 0) | (h.points_reordered ? 32 : 0) |
                            (h.octree_frames ? 64 : 0)));
  w.f64(h.step);
  w.f64(h.max_error);
  w.u32(h.analog_channels);
  w.u32(h.analog_samples_per_frame);
  if (h.transform_output) w.f64(h.kg_target);
  if (h.rotations()) {  // FORMAT.md 4.4
    w.u32(h.rotation_segments);
    w.u32(h.rotation_samples_per_frame);
  }
  if (h.frame_file_source())  // 6: a .bin folder in a declared record
    w.u8(h.bin_record_declared ? uint8_t{6} : static_cast<uint8_t>(h.source_format));
  return std::move(w.buffer());
}

// ---------------------------------------------------------------------------------------------
std::vector<uint8_t> encode_index(const std::vector<IndexEntry>& idx) {
  ByteWriter w;
  w.varint(idx.size());
  for (const auto& e : idx) {
    w.u64(e.offset);
    w.u64(e.bytes);
  }
  w.u32(static_cast<uint32_t>(w.size() + 4));  // lets a reader find INDX from the file's end
  return std::move(w.buffer());
}

}  // namespace capz
