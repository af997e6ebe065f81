// The C3D residue's encoder (see c3d_residue.h; byte layout in docs/FORMAT.md 7, 14): the file's
// head and tail against the parameter section capz writes, and each window's frames against the
// frames it regenerates; the decoder is c3d_residue.cpp.
#include <algorithm>
#include <cmath>
#include <cstdlib>
#include <utility>

#include "capz/error.h"
#include "coding/bytes.h"
#include "io/c3d_internal.h"
#include "io/residue/c3d_residue.h"
#include "io/residue/c3d_residue_shared.h"
#include "io/residue/pack.h"
#include "io/residue/patch.h"
#include "io/residue/windows.h"

namespace capz {
namespace residue {

using namespace c3dr;

// ---- encoder ---------------------------------------------------------------------------------

C3DResidueEncoder::C3DResidueEncoder(const std::string& path) : in_(path) {
  const uint64_t size = in_.size();
  std::vector<uint8_t> head(static_cast<size_t>(std::min<uint64_t>(size, c3d::kBlock)));
  in_.read_at(0, head.data(), head.size());
  const size_t extent = c3d::header_extent(head.data(), head.size(), size);
  if (extent > head.size()) {
    head.resize(extent);
    in_.read_at(0, head.data(), extent);
  }
  c3d::DataLayout dl;
  c3d::read_header(head.data(), head.size(), size, path, &dl);
  lay_.processor = dl.nf.processor;
  lay_.float_storage = dl.float_storage;
  lay_.analog_unsigned = dl.analog_unsigned;
  lay_.scale = dl.scale;
  lay_.frames = dl.frames;
  lay_.points = dl.points;
  lay_.analog_values = dl.analog_values;
  lay_.per_frame = dl.per_frame;
  lay_.head_size = std::min<uint64_t>(dl.data_offset, size);
  const uint64_t frames_end = lay_.head_size + lay_.frame_bytes();
  // The rotation section (within the file: the reader counts only the frames it holds) is
  // regenerated when it follows the frames.
  if (dl.rot_per_frame > 0 && dl.rot_offset >= frames_end) {
    lay_.rotations = true;
    lay_.rot_per_frame = dl.rot_per_frame;
    lay_.rot_gap = dl.rot_offset - frames_end;
  }
  lay_.tail_size = size - frames_end - lay_.rot_gap - lay_.rotation_bytes();
}

std::vector<uint8_t> C3DResidueEncoder::window(const FrameBlock& block, bool exact) {
  check_block(lay_, block, in_.path());
  const size_t n = block.frames * lay_.per_frame;
  const size_t nr = lay_.rotations ? block.frames * lay_.rot_per_frame : 0;
  regen_.resize(n + nr);
  regenerate_c3d_frames(lay_, block, regen_.data());
  orig_at_ = lay_.head_size + block.first * lay_.per_frame;
  orig_size_ = n;
  if (nr > 0) {  // the frames' bytes, then their rotations' (read from the rotation section)
    regenerate_c3d_rotations(lay_, block, regen_.data() + n);
    orig_.resize(n + nr);
    if (block.file_bytes.size() == n && block.file_bytes_at == orig_at_)
      std::copy(block.file_bytes.begin(), block.file_bytes.end(), orig_.begin());
    else
      in_.read_at(orig_at_, orig_.data(), n);
    in_.read_at(
        lay_.head_size + lay_.frame_bytes() + lay_.rot_gap + block.first * lay_.rot_per_frame,
        orig_.data() + n, nr);
    orig_ptr_ = orig_.data();
  } else if (block.file_bytes.size() == n && block.file_bytes_at == orig_at_) {
    // The block's copy of the file's bytes when it carries them (FrameBlock::file_bytes), else
    // read here.
    orig_ptr_ = block.file_bytes.data();
  } else {
    orig_.resize(n);
    in_.read_at(orig_at_, orig_.data(), n);
    orig_ptr_ = orig_.data();
  }
  exact_orig_ = exact;
  if (!exact) {  // at a bound: absent samples' coordinates are not kept
    // Those that differ from the regenerated ones are dropped (the original's bytes copied to
    // orig_ first, when they are the block's).
    const size_t elem = elem_size(lay_);
    for (size_t f = 0; f < block.frames; ++f)
      for (size_t p = 0; p < lay_.points; ++p) {
        const size_t at = f * lay_.per_frame + p * 4 * elem;
        if (!block.valid[f * lay_.points + p] && word4_negative(lay_, orig_ptr_ + at) &&
            !std::equal(&regen_[at], &regen_[at] + 3 * elem, orig_ptr_ + at)) {
          ++dropped_;
          if (orig_ptr_ != orig_.data()) {
            orig_.assign(orig_ptr_, orig_ptr_ + n);
            orig_ptr_ = orig_.data();
          }
          std::copy_n(&regen_[at], 3 * elem, &orig_[at]);
        }
      }
  }
  std::vector<uint8_t> patch = diff_bytes(regen_.data(), orig_ptr_, n + nr);
  if (patch.empty()) return {};
  ByteWriter out;
  pack(patch, {}, out);
  return std::move(out.buffer());
}

std::vector<uint8_t> C3DResidueEncoder::file_part(const std::vector<C3DGroup>& groups) {
  // The head, the gap before the rotation section, the tail.
  const size_t head = static_cast<size_t>(lay_.head_size), gap = static_cast<size_t>(lay_.rot_gap);
  std::vector<uint8_t> rest(head + gap + static_cast<size_t>(lay_.tail_size));
  in_.read_at(0, rest.data(), head);
  in_.read_at(lay_.head_size + lay_.frame_bytes(), rest.data() + head, gap);
  in_.read_at(lay_.file_size() - lay_.tail_size, rest.data() + head + gap,
              static_cast<size_t>(lay_.tail_size));
  ByteWriter out;
  out.u8(kKindC3D);
  out.u8(static_cast<uint8_t>(lay_.processor));
  out.u8(static_cast<uint8_t>((lay_.float_storage ? 1 : 0) | (lay_.analog_unsigned ? 2 : 0) |
                              (lay_.rotations ? 4 : 0)));
  out.f64(lay_.scale);
  out.varint(lay_.frames);
  out.varint(lay_.points);
  out.varint(lay_.analog_values);
  out.varint(lay_.per_frame);
  out.varint(lay_.head_size);
  if (lay_.rotations) {
    out.varint(lay_.rot_gap);
    out.varint(lay_.rot_per_frame);
  }
  pack(rest, dictionary(groups, lay_.processor), out);
  return std::move(out.buffer());
}

FileResidue encode_c3d_residue(const std::string& path, FrameSource& frames, size_t block) {
  C3DResidueEncoder enc(path);
  FileResidue r;
  encode_windows(
      frames, block, [&](const FrameBlock& b) { return enc.window(b); }, &r);
  r.file_part = enc.file_part(groups_of(frames.header()));
  return r;
}

}  // namespace residue
}  // namespace capz
