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
const char* const kEncodings[3] = {"ascii", "binary", "binary_compressed"};

}  // namespace

size_t pcd_header_end(const uint8_t* p, size_t n) {
  size_t pos = 0;
  while (pos < n) {
    const void* nl = std::memchr(p + pos, '\n', n - pos);
    const size_t e = nl ? static_cast<size_t>(static_cast<const uint8_t*>(nl) - p) : n;
    size_t w = pos;
    while (w < e && is_space(p[w])) ++w;
    if (e - w >= 4 && std::memcmp(p + w, "DATA", 4) == 0 && (e - w == 4 || is_space(p[w + 4])))
      return e < n ? e + 1 : n;
    pos = e + 1;
  }
  return SIZE_MAX;
}

int pcd_encoding_code(const std::string& data) {
  for (int i = 0; i < 3; ++i)
    if (data == kEncodings[i]) return i;
  return 1;
}

PcdRegen::PcdRegen(const Take& header) {
  for (int i = 0; i < 3; ++i) plans_[i] = pcd_frame_plan(header, kEncodings[i]);
  take_enc_ = pcd_encoding_code(header.pcd ? header.pcd->encoding : "binary");
  attrs_.resize(header.attributes.size());
  take_header_ = pcd_frame_header(plans_[take_enc_].layout);  // before frame() sets a width
}

std::string PcdRegen::take_header() const {
  return take_header_;
}

void PcdRegen::frame(const FrameBlock& b, size_t k, int enc, std::vector<uint8_t>* out,
                     size_t* header_end, LzfVariant lzf) {
  // A ragged block's frame k: its own count, from its offset (FORMAT.md "Lossless ragged
  // streams"); a fixed block's: b.points from k x b.points.
  const size_t N = b.frame_points(k), p0 = b.frame_begin(k), total = b.total_points();
  if (b.attributes.size() != attrs_.size() || k >= b.frames)
    fail(ErrorCode::kInternal, "", "PCD residue: a frame block without its point fields");
  for (size_t a = 0; a < attrs_.size(); ++a) {
    const size_t per_point = total ? b.attributes[a].size() / total : 0;
    if (b.attributes[a].size() != per_point * total)
      fail(ErrorCode::kInternal, "", "PCD residue: a frame block without its point fields");
    attrs_[a] = b.attributes[a].data() + p0 * per_point;
  }
  PcdFramePlan& plan = plans_[enc];
  if (b.ragged()) {
    plan.layout.width = N;
    plan.layout.height = 1;
  }
  pcd_frame_points(plan, N, b.xyz.data() + p0 * 3, b.valid.data() + p0, attrs_, &points_);
  *out = pcd_frame_bytes(plan.layout, points_.data(), lzf);
  *header_end = pcd_header_end(out->data(), out->size());
  if (*header_end == SIZE_MAX) fail(ErrorCode::kInternal, "", "PCD writer wrote no DATA line");
}

PCDResidueDecoder::PCDResidueDecoder(const uint8_t* file_part, size_t size, const Take& header,
                                     const std::string& what)
    : regen_(header), what_(what) {
  ByteReader in(file_part, size, what + ": PCDR");
  if (in.u8() != kKind) fail(ErrorCode::kCorrupt, what, "PCDR: not a PCD residue");
  if (in.varint() != header.frames)
    fail(ErrorCode::kCorrupt, what, "PCDR: frame count differs from the take's");
  const std::string h = regen_.take_header();
  reference_ = unpack(in, std::vector<uint8_t>(h.begin(), h.end()), kMaxReference);
  if (!in.at_end()) fail(ErrorCode::kCorrupt, what, "PCDR: bytes left over");
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
  if (enc == 3 || hmode == 3 || (bmode == 3 && enc != 0) || (liblzf && enc != 2) ||
      (flags >> 7) != 0)
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
