// capz — PCD residue: what a folder's frame files hold beyond the Take (issue 14, --lossless).
//
// Each frame file is compared, in memory, with what capz's PCD writer gives for the frame as
// read (io/pcd_frame_writer.h) in the frame's own encoding: the header (through the DATA line)
// and the body separately. A frame the writer reproduces costs its size, hash and one flags byte;
// a header of the folder's own form (comments, spacing, CRLF) shared by the frames is stored once
// (the file-level reference header); a body of the writer's length with a few different bytes
// (NaN payloads, a gap with a finite coordinate) is a byte patch plus any trailing bytes; anything
// else (ASCII number spellings, another LZF's compressed bytes) is the body packed with the
// writer's body as zstd's prefix dictionary. Byte layout: docs/FORMAT.md 7.3, 14.3.
#pragma once

#include <cstddef>
#include <cstdint>
#include <string>
#include <vector>

#include "capz/stream.h"
#include "capz/take.h"
#include "coding/bytes.h"
#include "core/hash.h"
#include "io/pcd_frame_writer.h"

namespace capz {
namespace residue {

// Bytes up to and including the line feed of the first line whose first word is DATA (the end
// of the file when that line has none); SIZE_MAX when there is no DATA line.
size_t pcd_header_end(const uint8_t* bytes, size_t n);

// The writer's frames for a take (header: the take's metadata with its PCD layout), by encoding:
// 0 ascii, 1 binary, 2 binary_compressed.
class PcdRegen {
 public:
  explicit PcdRegen(const Take& header);
  // Frame k of `block` regenerated in encoding `enc` into *out; *header_end: its header's bytes.
  void frame(const FrameBlock& block, size_t k, int enc, std::vector<uint8_t>* out,
             size_t* header_end);
  // The header of any frame in the take's own encoding (META's).
  std::string take_header() const;

 private:
  PcdFramePlan plans_[3];
  int take_enc_ = 1;
  std::vector<uint8_t> points_;
  std::vector<const uint8_t*> attrs_;
};

// 0, 1 or 2 for "ascii", "binary", "binary_compressed" (1 for anything else).
int pcd_encoding_code(const std::string& data);

class PCDResidueEncoder {
 public:
  explicit PCDResidueEncoder(const Take& header);
  // The file-level payload, given the first frame file's bytes.
  std::vector<uint8_t> file_part(const std::vector<uint8_t>& first_file);
  // Appends frame k of `block` to a window payload: `orig` is the frame file, `hash` its digest.
  void frame(const FrameBlock& block, size_t k, const std::vector<uint8_t>& orig,
             const Digest128& hash, ByteWriter& out);

 private:
  PcdRegen regen_;
  size_t frames_;
  std::vector<uint8_t> reference_;
  std::vector<uint8_t> bytes_;
};

class PCDResidueDecoder {
 public:
  // `header`: the decoded take's metadata. Throws Error(kCorrupt) naming `what` when the payload
  // is malformed or the frame count is not the take's.
  PCDResidueDecoder(const uint8_t* file_part, size_t size, const Take& header,
                    const std::string& what);
  // Rebuilds frame k of `block` from the next record of `in` into *out, its size and hash
  // checked: Error(kCorrupt) naming `what` and the frame file `name` when they differ.
  void frame(const FrameBlock& block, size_t k, ByteReader& in, const std::string& name,
             std::vector<uint8_t>* out);

 private:
  PcdRegen regen_;
  std::vector<uint8_t> reference_;
  std::string what_;
  std::vector<uint8_t> regen_bytes_;
};

}  // namespace residue
}  // namespace capz
