// The C3D residue (see c3d_residue.h; byte layout in docs/FORMAT.md 7, 14): what its encoder and
// decoder share (c3d_residue_shared.h), the frames regenerated, and the decoder; the encoder is
// c3d_residue_encode.cpp.
#include "io/residue/c3d_residue.h"

#include <algorithm>
#include <cmath>
#include <cstdlib>
#include <utility>

#include "capz/error.h"
#include "coding/bytes.h"
#include "io/c3d_internal.h"
#include "io/residue/c3d_residue_shared.h"
#include "io/residue/pack.h"
#include "io/residue/patch.h"
#include "io/residue/windows.h"

namespace capz {
namespace residue {

namespace c3dr {

size_t elem_size(const C3DFrameLayout& lay) {
  return lay.float_storage ? 4 : 2;
}

// Intel-form numbers of `elem` bytes (what encode_c3d_frames writes) to `processor`'s form, in
// place.
void to_processor_form(int processor, size_t elem, uint8_t* p, size_t n) {
  if (processor == c3d::kIntel) return;
  for (size_t i = 0; i + elem <= n; i += elem) {
    uint8_t* q = p + i;
    if (processor == c3d::kMips)
      std::reverse(q, q + elem);
    else if (elem == 4)  // DEC: int16 is little-endian as Intel's; floats are VAX F
      c3d::float_to_dec(c3d::get_f32le(q), q);
  }
}
void to_processor_form(const C3DFrameLayout& lay, uint8_t* p, size_t n) {
  to_processor_form(lay.processor, elem_size(lay), p, n);
}

// The parameter section as the writer encodes it, numbers in the file's processor form: most of
// the head's bytes, so zstd finds them as matches. Empty when the writer refuses the groups.
std::vector<uint8_t> dictionary(std::vector<C3DGroup> groups, int processor) {
  for (auto& g : groups)
    for (auto& p : g.params)
      if (p.type == 2 || p.type == 4)
        to_processor_form(processor, p.type == 4 ? 4 : 2, p.data.data(), p.data.size());
  std::vector<uint8_t> out;
  try {
    out = c3d::encode_parameter_section(groups);
  } catch (const Error&) {
    return {};
  }
  out[3] = static_cast<uint8_t>(processor);
  if (processor != c3d::kMips) return out;
  // MIPS: every entry's next-entry offset (after its name) is big-endian too.
  for (size_t p = 4; p + 2 <= out.size();) {
    const size_t name = static_cast<size_t>(std::abs(static_cast<int8_t>(out[p])));
    const size_t at = p + 2 + name;
    if (name == 0 || at + 2 > out.size()) break;
    const size_t off = out[at] | (out[at + 1] << 8);
    std::swap(out[at], out[at + 1]);
    if (off == 0) break;
    p = at + off;
  }
  return out;
}

// kInternal on the encoding side (the caller's blocks are wrong), kCorrupt on the decoding side
// (the residue's layout does not fit the decoded take).
void check_block(const C3DFrameLayout& lay, const FrameBlock& b, const std::string& name,
                 ErrorCode code) {
  const bool words = !b.residual.empty();
  const uint64_t rotations =
      lay.rotations ? b.frames * (lay.rot_per_frame / c3d::kRotationBytes) : 0;
  if (b.points != lay.points || b.first > lay.frames || b.frames > lay.frames - b.first ||
      b.xyz.size() != b.frames * b.points * 3 || b.valid.size() != b.frames * b.points ||
      (words && (b.residual.size() != b.valid.size() || b.camera_mask.size() != b.valid.size())) ||
      b.analog.size() != b.frames * lay.analog_values ||
      (lay.rotations && (b.rotation_matrices.size() != rotations * 16 ||
                         b.rotation_reliability.size() != rotations)))
    fail(code, name,
         "C3D residue: block of frames " + std::to_string(b.first) + "+" +
             std::to_string(b.frames) + " does not match the file's " + std::to_string(lay.frames) +
             " frames x " + std::to_string(lay.points) + " points");
}

// True when the 4th word of the sample at `q` (the file's bytes, processor form) has its sign
// bit set: a sample every reader takes as absent. Intel and DEC store an int16 little-endian;
// an IEEE float (Intel) has its sign in its last byte, a VAX F float (DEC) in bit 15 of its first
// little-endian 16-bit word; MIPS is big-endian.
bool word4_negative(const C3DFrameLayout& lay, const uint8_t* q) {
  const size_t elem = elem_size(lay);
  const uint8_t* w = q + 3 * elem;
  if (lay.processor == c3d::kMips) return (w[0] & 0x80) != 0;
  if (elem == 2 || lay.processor == c3d::kDec) return (w[1] & 0x80) != 0;
  return (w[3] & 0x80) != 0;
}

}  // namespace c3dr

using namespace c3dr;

void regenerate_c3d_frames(const C3DFrameLayout& lay, const FrameBlock& b, uint8_t* out) {
  check_block(lay, b, "");
  c3d::C3DFilePlan plan;
  plan.float_storage = lay.float_storage;
  plan.scale = lay.scale;
  plan.have_res = !b.residual.empty();
  plan.frames = b.frames;
  plan.points = lay.points;
  plan.analog_total = lay.analog_values;
  plan.per_frame = (lay.points * 4 + lay.analog_values) * elem_size(lay);
  const size_t n = b.frames * lay.per_frame;
  const float* res = plan.have_res ? b.residual.data() : nullptr;
  const uint8_t* cam = plan.have_res ? b.camera_mask.data() : nullptr;
  if (plan.per_frame == lay.per_frame) {
    c3d::encode_c3d_frames(plan, b.frames, b.xyz.data(), b.valid.data(), res, cam, b.analog.data(),
                           out);
  } else {  // frames hold analog values the reader skips: regenerated as zeros
    std::vector<uint8_t> tmp(b.frames * plan.per_frame);
    c3d::encode_c3d_frames(plan, b.frames, b.xyz.data(), b.valid.data(), res, cam, b.analog.data(),
                           tmp.data());
    std::fill(out, out + n, 0);
    for (size_t f = 0; f < b.frames; ++f)
      std::copy_n(tmp.data() + f * plan.per_frame, plan.per_frame, out + f * lay.per_frame);
  }
  to_processor_form(lay, out, n);
}

void regenerate_c3d_rotations(const C3DFrameLayout& lay, const FrameBlock& b, uint8_t* out) {
  check_block(lay, b, "");
  const size_t n = b.frames * lay.rot_per_frame;
  c3d::encode_c3d_rotations(b.rotation_matrices.data(), b.rotation_reliability.data(),
                            n / c3d::kRotationBytes, out);
  to_processor_form(lay.processor, 4, out, n);
}

// ---- decoder ---------------------------------------------------------------------------------

C3DResidueDecoder::C3DResidueDecoder(const uint8_t* data, size_t size,
                                     const std::vector<C3DGroup>& groups, const std::string& name,
                                     uint64_t file_size)
    : name_(name) {
  const std::string what = name + ": C3D residue";
  ByteReader in(data, size, what);
  if (in.u8() != kKindC3D) fail(ErrorCode::kCorrupt, what, "not a C3D residue");
  lay_.processor = in.u8();
  const uint8_t flags = in.u8();
  lay_.float_storage = flags & 1;
  lay_.analog_unsigned = flags & 2;
  lay_.rotations = flags & 4;
  lay_.scale = in.f64();
  lay_.frames = in.varint();
  lay_.points = in.varint();
  lay_.analog_values = in.varint();
  lay_.per_frame = in.varint();
  lay_.head_size = in.varint();
  if (lay_.rotations) {
    lay_.rot_gap = in.varint();
    lay_.rot_per_frame = in.varint();
  }
  const uint64_t sample_bytes = (lay_.points * 4 + lay_.analog_values) * elem_size(lay_);
  if (lay_.processor < c3d::kIntel || lay_.processor > c3d::kMips || flags > 7 ||
      !(std::isfinite(lay_.scale) && lay_.scale > 0) || lay_.points > 65535 ||
      lay_.analog_values > 65535 || lay_.per_frame < sample_bytes ||
      lay_.per_frame % elem_size(lay_) != 0 || lay_.per_frame > uint64_t{65535} * 5 * 4 ||
      (lay_.per_frame > 0 && lay_.frames > (uint64_t{1} << 62) / lay_.per_frame) ||
      (lay_.rotations &&
       (lay_.rot_per_frame == 0 || lay_.rot_per_frame % c3d::kRotationBytes != 0 ||
        lay_.rot_per_frame > uint64_t{65535} * 65535 * c3d::kRotationBytes ||
        lay_.frames > (uint64_t{1} << 62) / (lay_.per_frame + lay_.rot_per_frame))))
    fail(ErrorCode::kCorrupt, what, "impossible frame layout");
  std::vector<uint8_t> rest =
      unpack(in, dictionary(groups, lay_.processor), file_size ? file_size : UINT64_MAX);
  if (!in.at_end()) fail(ErrorCode::kCorrupt, what, "bytes left after the payload");
  if (lay_.head_size > rest.size() || lay_.rot_gap > rest.size() - lay_.head_size)
    fail(ErrorCode::kCorrupt, what, "head longer than the bytes stored");
  lay_.tail_size = rest.size() - lay_.head_size - lay_.rot_gap;
  if (file_size && lay_.file_size() != file_size)
    fail(ErrorCode::kCorrupt, what,
         "layout gives " + std::to_string(lay_.file_size()) + " bytes, the original had " +
             std::to_string(file_size));
  const auto gap_at = rest.begin() + static_cast<long>(lay_.head_size);
  const auto tail_at = gap_at + static_cast<long>(lay_.rot_gap);
  head_.assign(rest.begin(), gap_at);
  gap_.assign(gap_at, tail_at);
  tail_.assign(tail_at, rest.end());
}

void C3DResidueDecoder::rebuild_block(const FrameBlock& block, const uint8_t* payload, size_t n,
                                      const std::string& what) {
  check_block(lay_, block, name_, ErrorCode::kCorrupt);
  const size_t frames = block.frames * lay_.per_frame;
  const size_t bytes = frames + (lay_.rotations ? block.frames * lay_.rot_per_frame : 0);
  scratch_.resize(bytes);
  regenerate_c3d_frames(lay_, block, scratch_.data());
  if (lay_.rotations) regenerate_c3d_rotations(lay_, block, scratch_.data() + frames);
  if (n > 0) {
    ByteReader in(payload, n, what);
    // A patch holds at most every byte plus two varints a run.
    std::vector<uint8_t> patch = unpack(in, {}, 16 * uint64_t{bytes} + 64);
    if (!in.at_end()) fail(ErrorCode::kCorrupt, what, "bytes left after the patch");
    apply_patch(patch, scratch_.data(), bytes, what.c_str());
  }
}

void C3DResidueDecoder::window(const FrameBlock& block, const uint8_t* payload, size_t n,
                               std::vector<uint8_t>* out) {
  const std::string what = name_ + ": C3D residue window at frame " + std::to_string(block.first);
  if (block.first != next_)
    fail(ErrorCode::kCorrupt, what, "expected frame " + std::to_string(next_) + " next");
  rebuild_block(block, payload, n, what);
  const size_t frames = block.frames * lay_.per_frame;
  out->insert(out->end(), scratch_.begin(), scratch_.begin() + static_cast<long>(frames));
  next_ += block.frames;
}

const std::vector<uint8_t>& C3DResidueDecoder::gap() const {
  if (!lay_.rotations || (next_ != lay_.frames && lay_.per_frame > 0))
    fail(ErrorCode::kCorrupt, name_,
         "C3D residue: the rotation section's gap asked for before the frames were rebuilt");
  return gap_;
}

void C3DResidueDecoder::rotation_window(const FrameBlock& block, const uint8_t* payload, size_t n,
                                        std::vector<uint8_t>* out) {
  const std::string what =
      name_ + ": C3D residue rotations at frame " + std::to_string(block.first);
  if (!lay_.rotations || block.first != next_rot_)
    fail(ErrorCode::kCorrupt, what, "expected frame " + std::to_string(next_rot_) + " next");
  rebuild_block(block, payload, n, what);
  const size_t frames = block.frames * lay_.per_frame;
  out->insert(out->end(), scratch_.begin() + static_cast<long>(frames), scratch_.end());
  next_rot_ += block.frames;
}

const std::vector<uint8_t>& C3DResidueDecoder::tail() const {
  const uint64_t done = lay_.rotations ? next_rot_ : next_;
  if (done != lay_.frames || (lay_.rotations && lay_.per_frame > 0 && next_ != lay_.frames))
    fail(ErrorCode::kCorrupt, name_,
         "C3D residue: " + std::to_string(done) + " of " + std::to_string(lay_.frames) +
             " frames rebuilt before the tail");
  return tail_;
}

// ---- whole-file helpers ----------------------------------------------------------------------

namespace c3dr {
const std::vector<C3DGroup>& groups_of(const Take& t) {
  static const std::vector<C3DGroup> kNone;
  return t.c3d ? t.c3d->groups : kNone;
}
}  // namespace c3dr

void rebuild_c3d(const FileResidue& residue, FrameSource& frames, size_t block,
                 const std::function<void(const uint8_t*, size_t)>& write, const std::string& name,
                 uint64_t file_size) {
  C3DResidueDecoder dec(residue.file_part.data(), residue.file_part.size(),
                        groups_of(frames.header()), name, file_size);
  if (frames.header().frames != dec.layout().frames)
    fail(ErrorCode::kCorrupt, name,
         "C3D residue for " + std::to_string(dec.layout().frames) + " frames, the take has " +
             std::to_string(frames.header().frames));
  // One pass over the windows giving each one's frames (window) or rotations (rotation_window).
  using Part =
      void (C3DResidueDecoder::*)(const FrameBlock&, const uint8_t*, size_t, std::vector<uint8_t>*);
  auto pass = [&](Part part) {
    rebuild_windows(
        residue, frames, block,
        [&](const FrameBlock& b, const std::vector<uint8_t>& w, std::vector<uint8_t>* out) {
          (dec.*part)(b, w.data(), w.size(), out);
        },
        write, name);
  };
  write(dec.head().data(), dec.head().size());
  pass(&C3DResidueDecoder::window);
  if (dec.layout().rotations) {  // a second pass for the rotation section
    write(dec.gap().data(), dec.gap().size());
    pass(&C3DResidueDecoder::rotation_window);
  }
  write(dec.tail().data(), dec.tail().size());
}

}  // namespace residue
}  // namespace capz
