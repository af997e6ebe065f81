// Split frames, the encoding side (scan_octree.h; docs/FORMAT.md "Split frames"): near parts as
// octree frames, spliced into a payload of the far parts.
#include <algorithm>
#include <cstdint>

#include "capz/error.h"
#include "coding/bytes.h"
#include "coding/scan_octree.h"
#include "coding/scan_shared.h"

namespace capz {

namespace {

// One frame of the split payload: its n_f, flags_f and d_f.
struct PayloadFrame {
  uint32_t n = 0;
  uint8_t flags = 0;
  uint32_t copies = 0;
};

// The near parts' octree block (with L when the table has rings) and their payload frames
// interleaved with the far payload's (h). Empty block: a near part too wide for an octree.
std::vector<uint8_t> near_block(const ScanGeometry& near, const std::vector<uint8_t>& far,
                                const scan::Header& h, uint32_t l,
                                std::vector<PayloadFrame>* frames) {
  IntEncoder tree(scan::kOctreeContexts);
  scan::start_octree_block(&tree);
  const scan::Table& table = h.table;
  if (table.rings() == 0) l = 0;
  if (table.rings() > scan::kMaxConeRings) l &= ~1u;
  if (!(l & 2)) l &= ~4u;  // the mix only with counting models
  scan::OctreeMode mode((l & 1) ? scan::table_cones(table) : scan::Cones{}, (l & 2) != 0,
                        (l & 4) != 0);
  if (table.rings() > 0) tree.put(l, scan::kOctFlagsCtx);
  std::vector<int32_t> prev;  // the previous near part's cells (a far part keeps them)
  size_t first = 0, j = 0;    // j: the far payload's next frame
  frames->clear();
  const auto far_part = [&]() {
    if (j >= h.counts.size()) throw Error(ErrorCode::kInternal, "split: far frames missing");
    frames->push_back(PayloadFrame{h.counts[j], h.flags[j], h.copies[j]});
    ++j;
  };
  for (size_t f = 0; f < near.counts.size(); ++f) {
    const size_t n = near.counts[f];
    size_t valid = 0;
    for (size_t i = first; i < first + n; ++i) valid += near.valid[i] != 0;
    if (valid == 0) {
      if (n > 0 || !far[f]) throw Error(ErrorCode::kInternal, "split: a frame without a part");
      far_part();
      prev.clear();
      continue;
    }
    if (!octree_frame_ok(near, first, n)) return {};
    PayloadFrame p;
    p.n = static_cast<uint32_t>(n);
    for (size_t i = first + 1; i < first + n; ++i)  // copies: in octree order after their cell
      p.copies += near.valid[i] && near.valid[i - 1] &&
                  std::equal(&near.q[3 * i], &near.q[3 * i] + 3, &near.q[3 * (i - 1)]);
    p.flags =
        static_cast<uint8_t>(scan::kOctreeFrame | (valid < n ? scan::kSomeValid : 0) |
                             (p.copies > 0 ? scan::kCells : 0) | (far[f] ? scan::kNearPart : 0));
    encode_octree_frame(near, first, n, p.copies, &prev, &tree, &mode);
    frames->push_back(p);
    if (far[f]) far_part();
    first += n;
  }
  if (j != h.counts.size()) throw Error(ErrorCode::kInternal, "split: far frames left over");
  std::vector<uint8_t> block = tree.finish();
  // The decoder's bound on the cone work (FORMAT.md "The block's flags"), as encode_scan_octree.
  if (mode.cones() && mode.cones()->work > scan::kMaxConeWorkPerByte * block.size())
    return near_block(near, far, h, l & ~1u, frames);
  return block;
}

}  // namespace

std::vector<uint8_t> encode_scan_split(const ScanGeometry& near,
                                       const std::vector<uint8_t>& far_payload,
                                       const std::vector<uint8_t>& far, uint32_t l) {
  if (far.size() != near.counts.size())
    throw Error(ErrorCode::kInternal, "split: a far flag per frame");
  const scan::Header h =
      scan::read_header(far_payload.data(), far_payload.size(), "split", SIZE_MAX);
  // (A far payload with turns is not split: its turns are one a frame of its own frames.)
  if (h.fine > 0 || h.octree_size > 0 || !h.turns.empty()) return {};
  std::vector<PayloadFrame> frames;
  const std::vector<uint8_t> block = near_block(near, far, h, l, &frames);
  if (block.empty()) return {};
  ByteReader r(far_payload.data(), far_payload.size(), "split");  // past the far d_f: K's offset
  r.bytes(h.flags_end);
  for (size_t i = 0; i < h.counts.size(); ++i)
    if (h.flags[i] & scan::kCells) r.varint();
  const uint8_t* at = far_payload.data();
  ByteWriter w;
  w.varint(frames.size());
  for (const PayloadFrame& p : frames) w.varint(p.n);
  for (const PayloadFrame& p : frames) w.u8(p.flags);
  for (const PayloadFrame& p : frames)
    if (p.flags & scan::kCells) w.varint(p.copies);
  w.bytes(at + r.offset(), h.body - r.offset());  // K .. the counts block
  put_block(&w, block);
  w.bytes(at + h.body, far_payload.size() - h.body);  // the main block
  return std::move(w.buffer());
}

}  // namespace capz
