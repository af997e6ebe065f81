// capz — C3D residue: what a C3D file holds beyond what its Take describes, so that the Take
// plus the residue give back the original file byte for byte (issue 14, --lossless).
//
// A C3D file is cut into three consecutive parts: the head (every byte before frame 0: the
// header block, the parameter section with its unused bytes and padding, any gap before the
// data), the frames the reader decoded (frames x per_frame bytes) and the tail (a truncated
// last frame, padding, trailing bytes). The head and the tail are kept whole, packed, in the
// file-level payload. The frames are regenerated from the decoded FrameBlocks with the writer's
// per-sample encoders (c3d_write.cpp) in the file's own processor form and storage; the
// per-window payload patches the bytes that regeneration gets wrong (gap samples whose
// coordinates or 4th word are not the writer's, 4th words beyond 16 bits, analog values past
// the whole channels, DEC values without an IEEE counterpart). It is empty for most files.
// Byte layout: docs/FORMAT.md 7, 14.
//
// Streaming: the encoder reads the original by ranges and holds one block of frames; the
// decoder holds the head and tail (small but for files with large trailing data) and one block.
#pragma once

#include <cstddef>
#include <cstdint>
#include <functional>
#include <string>
#include <vector>

#include "capz/stream.h"
#include "capz/take.h"
#include "core/input_file.h"
#include "io/residue/pack.h"

namespace capz {
namespace residue {

// How the decoded frames are stored, as the C3D reader found it.
struct C3DFrameLayout {
  int processor = 84;  // 84 Intel, 85 DEC, 86 MIPS
  bool float_storage = false;
  bool analog_unsigned = false;  // int16 analog read as 0..65535
  double scale = 1;              // the int16 coordinate step (c3d::DataLayout::scale)
  uint64_t frames = 0, points = 0;
  uint64_t analog_values = 0;  // decoded analog values per frame (samples x whole channels)
  uint64_t per_frame = 0;      // bytes per frame in the file (may hold undecoded analog values)
  uint64_t head_size = 0;      // bytes before frame 0
  uint64_t tail_size = 0;      // bytes after the last decoded frame
  uint64_t file_size() const { return head_size + frames * per_frame + tail_size; }
};

// Writes `block`'s frames (block.frames x lay.per_frame bytes at out) as the C3D writer would in
// the layout's processor form and storage: gaps as (0, 0, 0, -1), a valid sample's 4th word as
// camera << 8 | round(residual / scale) (0 when the block has no words), analog values past
// lay.analog_values as zeros. Throws Error(kInternal) when the block does not match the layout.
void regenerate_c3d_frames(const C3DFrameLayout& lay, const FrameBlock& block, uint8_t* out);

class C3DResidueEncoder {
 public:
  // Opens the file and reads its header and parameter section as the C3D reader does (the
  // reader's errors for a file it refuses).
  explicit C3DResidueEncoder(const std::string& path);
  const C3DFrameLayout& layout() const { return lay_; }
  // The per-window payload for the frames of `block` (as open_c3d_frames() reads them, or as a
  // lossless decode gives them back); empty when regeneration gets every byte right. Blocks may
  // come in any order. `exact` false (an archive at a bound): the coordinates of samples that
  // are gaps in the take and whose 4th word in the file is negative (absent to every reader)
  // are left as regenerated, not patched (docs/FORMAT.md 14.1).
  std::vector<uint8_t> window(const FrameBlock& block, bool exact = true);
  // Samples so far whose coordinates the file holds but, at a bound, were not kept: gaps in the
  // take, 4th word negative, coordinates other than the regenerated ones (SIMI writes real
  // coordinates with a residual of -1 for every sample).
  size_t dropped_coordinates() const { return dropped_; }
  // The file-level payload: layout, head and tail. `groups` (the parameter section as the Take
  // holds it) serve as zstd's prefix dictionary; the decoder must be given the same ones.
  std::vector<uint8_t> file_part(const std::vector<C3DGroup>& groups);
  // The file's bytes of the frames of the last window() with `exact` (nullptr: none, or the
  // last window was at a bound, where they are amended), original_size() of them from offset
  // original_at(): what a check of that window's rebuilt bytes compares against without
  // reading them again. They may be the block's own (FrameBlock::file_bytes): valid while it
  // is unchanged.
  const uint8_t* original() const { return exact_orig_ ? orig_ptr_ : nullptr; }
  size_t original_size() const { return orig_size_; }
  uint64_t original_at() const { return orig_at_; }

 private:
  InputFile in_;
  C3DFrameLayout lay_;
  std::vector<uint8_t> regen_, orig_;
  const uint8_t* orig_ptr_ = nullptr;  // orig_ or the block's file_bytes
  size_t orig_size_ = 0;
  uint64_t orig_at_ = 0;
  bool exact_orig_ = false;
  size_t dropped_ = 0;
};

class C3DResidueDecoder {
 public:
  // Parses a file-level payload. `file_size`: the original's size when the archive records it
  // (0: unknown), which bounds what the payload may unpack to and must match its layout.
  // Throws Error(kCorrupt) naming `name` when it is malformed.
  C3DResidueDecoder(const uint8_t* file_part, size_t size, const std::vector<C3DGroup>& groups,
                    const std::string& name, uint64_t file_size = 0);
  const C3DFrameLayout& layout() const { return lay_; }
  const std::vector<uint8_t>& head() const { return head_; }
  // The original bytes of block's frames, appended to *out. Blocks must come in order from
  // frame 0; `payload` is the window's payload (n = 0: none). Throws Error(kCorrupt).
  void window(const FrameBlock& block, const uint8_t* payload, size_t n, std::vector<uint8_t>* out);
  // The bytes after the frames; throws Error(kCorrupt) unless every frame was given.
  const std::vector<uint8_t>& tail() const;

 private:
  std::string name_;
  C3DFrameLayout lay_;
  std::vector<uint8_t> head_, tail_;
  uint64_t next_ = 0;
};

// The whole residue of the C3D at `path` in one call: frames read from `frames` (the file's own
// frame source, or any source giving the same frames) in blocks of `block`.
FileResidue encode_c3d_residue(const std::string& path, FrameSource& frames, size_t block);

// Rebuilds the original from `frames` (the decoded take, read in the encoder's blocks) and the
// residue, handing consecutive byte ranges to `write`: head, each window, tail.
// `file_size`: as C3DResidueDecoder's.
void rebuild_c3d(const FileResidue& residue, FrameSource& frames, size_t block,
                 const std::function<void(const uint8_t*, size_t)>& write, const std::string& name,
                 uint64_t file_size = 0);

}  // namespace residue
}  // namespace capz
