// The PCD residue's encoder (pcd_residue.h; docs/FORMAT.md 7.3, 14.3): the file part and each
// frame file against what capz regenerates; the decoder is pcd_residue.cpp.
#include <cctype>
#include <cstring>
#include <utility>

#include "capz/error.h"
#include "io/residue/pack.h"
#include "io/residue/patch.h"
#include "io/residue/pcd_ascii.h"
#include "io/residue/pcd_residue.h"
#include "io/residue/pcd_residue_shared.h"

namespace capz {
namespace residue {

namespace {

using namespace pcdr;

// zstd level for a packed string of n bytes: the best below 256 KiB, a fast one above (bodies
// of their own are rare, and level 19 runs at a few MB/s).
int level_for(size_t n) {
  return n <= (size_t{1} << 18) ? 19 : 6;
}

// Whether a[0, n) is b[0, n). No memcmp of n = 0: an empty vector's data() may be null (a
// .bin frame of 0 bytes), which memcmp must not be given.
bool same_bytes(const uint8_t* a, const uint8_t* b, size_t n) {
  return n == 0 || std::memcmp(a, b, n) == 0;
}

// Whether a's bytes from ah on are b's from bh on.
bool same_body(const std::vector<uint8_t>& a, size_t ah, const std::vector<uint8_t>& b, size_t bh) {
  return a.size() - ah == b.size() - bh && same_bytes(a.data() + ah, b.data() + bh, a.size() - ah);
}

// The encoding a frame file's header names (FORMAT.md 14.3, "Lossless frame-file streams"): a
// PCD file's DATA word (its last header line), a PLY file's format line's second word; 1
// (binary, binary_little_endian) for any other.
int encoding_word(const std::vector<uint8_t>& orig, size_t header_end, uint8_t kind) {
  size_t a = 0, end = header_end;
  if (kind == 3) {  // the DATA line: the header's last
    if (end > 0 && orig[end - 1] == '\n') --end;
    a = end;
    while (a > 0 && orig[a - 1] != '\n') --a;
  } else {  // PLY: line 2, "format ENCODING VERSION"
    while (a < end && orig[a] != '\n') ++a;
    end = ++a;
    while (end < header_end && orig[end] != '\n') ++end;
  }
  const std::string line(orig.begin() + static_cast<long>(a),
                         orig.begin() + static_cast<long>(end));
  size_t p = 0;
  while (p < line.size() && is_space(static_cast<uint8_t>(line[p]))) ++p;
  while (p < line.size() && !is_space(static_cast<uint8_t>(line[p]))) ++p;  // DATA, format
  while (p < line.size() && is_space(static_cast<uint8_t>(line[p]))) ++p;
  size_t q = p;
  while (q < line.size() && !is_space(static_cast<uint8_t>(line[q]))) ++q;
  std::string word = line.substr(p, q - p);
  if (kind == 3) {
    for (char& c : word) c = static_cast<char>(std::tolower(static_cast<unsigned char>(c)));
    return pcd_encoding_code(word);
  }
  return word == "ascii" ? 0 : word == "binary_big_endian" ? 2 : 1;
}

// The header's part of a frame's residue (FORMAT.md 14.3, flags bits 2-3): none when the
// regenerated header (its first rh bytes of regen) is the original's (its first oh), the file
// part's reference header when that is, else packed against the regenerated one into *rest.
uint8_t header_residue(const std::vector<uint8_t>& orig, size_t oh,
                       const std::vector<uint8_t>& regen, size_t rh,
                       const std::vector<uint8_t>& reference, ByteWriter* rest) {
  if (oh == rh && same_bytes(orig.data(), regen.data(), oh)) return 0;
  if (!reference.empty() && oh == reference.size() && same_bytes(orig.data(), reference.data(), oh))
    return 1 << 2;
  pack(slice(orig, 0, oh), slice(regen, 0, rh), *rest);
  return 2 << 2;
}

// The body's part (flags bits 4-5) of the original body o (ob bytes) against the regenerated r
// (rb): none when they are the same, else the smallest of a patch, the ascii body by column
// styles (`styled`, when there) and the body packed with r as dictionary, into *rest.
uint8_t body_residue(const uint8_t* o, size_t ob, const uint8_t* r, size_t rb,
                     const ByteWriter* styled, ByteWriter* rest) {
  if (ob == rb && same_bytes(o, r, rb)) return 0;
  ByteWriter patched;
  bool have_patch = false;
  if (ob >= rb) {
    const std::vector<uint8_t> patch = diff_bytes(r, o, rb);
    const std::vector<uint8_t> tail(o + rb, o + ob);
    pack(patch, {}, patched, level_for(patch.size()));
    pack(tail, {}, patched, level_for(tail.size()));
    have_patch = true;
  }
  // A patch or a styled body that is small next to the body wins outright; else the body of
  // its own, packed with the writer's body as dictionary, when that is smaller.
  const size_t small = rb / 8 + 64;
  ByteWriter own;
  if ((!have_patch || patched.size() > small) && (!styled || styled->size() > small)) {
    const std::vector<uint8_t> body(o, o + ob), dict(r, r + rb);
    pack(body, dict, own, level_for(ob));
  }
  const size_t inf = SIZE_MAX;
  const size_t sp = have_patch ? patched.size() : inf, ss = styled ? styled->size() : inf,
               so = own.size() ? own.size() : inf;
  if (sp <= ss && sp <= so) {
    rest->bytes(patched.buffer());
    return 1 << 4;
  }
  if (ss <= so) {
    rest->bytes(styled->buffer());
    return 3 << 4;
  }
  rest->bytes(own.buffer());
  return 2 << 4;
}

}  // namespace

PCDResidueEncoder::PCDResidueEncoder(const Take& header) : regen_(header), frames_(header.frames) {}

std::vector<uint8_t> PCDResidueEncoder::file_part(const std::vector<uint8_t>& first) {
  const std::string h = regen_.take_header();
  const size_t e = regen_.header_end(first.data(), first.size());
  reference_.clear();
  if (e != SIZE_MAX && e > 0 && (e != h.size() || std::memcmp(first.data(), h.data(), e) != 0))
    reference_.assign(first.begin(), first.begin() + static_cast<long>(e));
  ByteWriter w;
  w.u8(regen_.kind());
  w.varint(frames_);
  pack(reference_, std::vector<uint8_t>(h.begin(), h.end()), w);
  return std::move(w.buffer());
}

void PCDResidueEncoder::frame(const FrameBlock& block, size_t k, const std::vector<uint8_t>& orig,
                              const Digest128& hash, ByteWriter& out) {
  size_t oh = regen_.header_end(orig.data(), orig.size());
  int enc = regen_.kind() == 3 ? 1 : 0;
  if (oh == SIZE_MAX) {
    oh = 0;  // no header: the whole file is its body (the reader refuses it; kept all the same)
  } else if (regen_.kind() != 4) {
    enc = encoding_word(orig, oh, regen_.kind());
  }
  size_t rh = 0;
  regen_.frame(block, k, enc, &bytes_, &rh);
  uint8_t flags = static_cast<uint8_t>(enc);
  if (regen_.kind() == 3 && enc == 2 && !same_body(orig, oh, bytes_, rh)) {
    // PCL's LZF (variant 1) wrote it? Then that regenerates it (FORMAT.md 14.3, flags bit 6).
    size_t vh = 0;
    regen_.frame(block, k, enc, &variant_, &vh, LzfVariant::kLiblzf13);
    if (same_body(orig, oh, variant_, vh)) {
      std::swap(bytes_, variant_);
      rh = vh;
      flags |= 1 << 6;
    }
  }
  const size_t rb = bytes_.size() - rh, ob = orig.size() - oh;
  ByteWriter rest;
  flags |= header_residue(orig, oh, bytes_, rh, reference_, &rest);
  const uint8_t* o = orig.data() + oh;
  const uint8_t* r = bytes_.data() + rh;
  if (!(ob == rb && same_bytes(o, r, rb))) {
    // An ascii body: regenerated by column styles (pcd_ascii.h).
    ByteWriter styled;
    const bool have_styled = enc == 0 && regen_.kind() != 4 &&
                             encode_ascii_body(regen_.plan(0), regen_.points().data(),
                                               block.frame_points(k), o, ob, &styled);
    flags |= body_residue(o, ob, r, rb, have_styled ? &styled : nullptr, &rest);
  }
  out.varint(orig.size());
  for (uint8_t x : hash) out.u8(x);
  out.u8(flags);
  out.bytes(rest.buffer());
}

}  // namespace residue
}  // namespace capz
