// The PCD residue (see pcd_residue.h; layout in docs/FORMAT.md 7.3, 14.3): the header, the
// regeneration of frame files and the decoder; the encoder is pcd_residue_encode.cpp.
#include "io/residue/pcd_residue.h"

#include <cctype>
#include <cstring>

#include "capz/error.h"
#include "io/residue/pack.h"
#include "io/residue/patch.h"
#include "io/residue/pcd_ascii.h"
#include "io/residue/pcd_residue_shared.h"

namespace capz {
namespace residue {

namespace {

using namespace pcdr;

constexpr uint64_t kMaxReference = uint64_t{1} << 21;
constexpr uint64_t kMaxFrame = uint64_t{1} << 40;

}  // namespace

PCDResidueDecoder::PCDResidueDecoder(const uint8_t* file_part, size_t size, const Take& header,
                                     const std::string& what)
    : regen_(header), what_(what) {
  ByteReader in(file_part, size, what + ": PCDR");
  if (in.u8() != regen_.kind())
    fail(ErrorCode::kCorrupt, what, "PCDR: the residue of another frame format");
  if (in.varint() != header.frames)
    fail(ErrorCode::kCorrupt, what, "PCDR: frame count differs from the take's");
  const std::string h = regen_.take_header();
  reference_ = unpack(in, std::vector<uint8_t>(h.begin(), h.end()), kMaxReference);
  if (!in.at_end()) fail(ErrorCode::kCorrupt, what, "PCDR: bytes left over");
  if (regen_.kind() == 4 && !reference_.empty())
    fail(ErrorCode::kCorrupt, what, "PCDR: a reference header for .bin frames");
}

void PCDResidueDecoder::frame(const FrameBlock& block, size_t k, ByteReader& in,
                              const std::string& name, std::vector<uint8_t>* out) {
  const uint64_t size = in.varint();
  if (size > kMaxFrame)
    fail(ErrorCode::kCorrupt, what_, "PCDP: frame file " + name + " of an absurd size");
  Digest128 hash;
  for (uint8_t& x : hash) x = in.u8();
  const uint8_t flags = in.u8();
  const int enc = flags & 3, hmode = (flags >> 2) & 3, bmode = (flags >> 4) & 3;
  const bool liblzf = (flags >> 6) & 1;
  // FORMAT.md 14.3; "Lossless frame-file streams": PLY and .bin frames have no LZF, .bin frames
  // no header and no ascii body.
  const uint8_t kind = regen_.kind();
  if (enc >= regen_.encodings() || hmode == 3 || (bmode == 3 && (enc != 0 || kind == 4)) ||
      (liblzf && (enc != 2 || kind != 3)) || (kind == 4 && hmode != 0) || (flags >> 7) != 0)
    fail(ErrorCode::kCorrupt, what_, "PCDP: bad flags for frame file " + name);
  size_t rh = 0;
  regen_.frame(block, k, enc, &regen_bytes_, &rh,
               liblzf ? LzfVariant::kLiblzf13 : LzfVariant::kCapz);
  const std::vector<uint8_t>& g = regen_bytes_;
  const size_t rb = g.size() - rh;
  out->clear();
  if (hmode == 0) {
    out->assign(g.begin(), g.begin() + static_cast<long>(rh));
  } else if (hmode == 1) {
    *out = reference_;
  } else {
    *out = unpack(in, slice(g, 0, rh), size);
  }
  if (bmode == 0) {
    out->insert(out->end(), g.begin() + static_cast<long>(rh), g.end());
  } else if (bmode == 1) {
    const std::vector<uint8_t> patch = unpack(in, {}, 16 * static_cast<uint64_t>(rb) + 64);
    const size_t at = out->size();
    out->insert(out->end(), g.begin() + static_cast<long>(rh), g.end());
    apply_patch(patch, out->data() + at, rb, (what_ + ": PCDP patch of " + name).c_str());
    const std::vector<uint8_t> tail = unpack(in, {}, size);
    out->insert(out->end(), tail.begin(), tail.end());
  } else if (bmode == 2) {
    const std::vector<uint8_t> body = unpack(in, slice(g, rh, g.size()), size);
    out->insert(out->end(), body.begin(), body.end());
  } else {
    decode_ascii_body(regen_.plan(0), regen_.points().data(), block.frame_points(k), in, size,
                      what_ + ": PCDP frame file " + name, out);
  }
  if (out->size() != size)
    fail(ErrorCode::kCorrupt, what_,
         "frame file " + name + " rebuilds to " + std::to_string(out->size()) +
             " bytes, the archive records " + std::to_string(size));
  const Digest128 got = hash128(out->data(), out->size());
  if (got != hash)
    fail(ErrorCode::kCorrupt, what_,
         "frame file " + name + ": the rebuilt bytes' XXH3-128 " + digest_hex(got) +
             " differs from the recorded " + digest_hex(hash));
}

}  // namespace residue
}  // namespace capz
