// The scan geometry decoder (docs/FORMAT.md "Scans (format 1.1)").
#include <algorithm>
#include <cstdint>
#include <memory>

#include "capz/error.h"
#include "coding/buffers.h"
#include "coding/bytes.h"
#include "coding/scan_cells.h"
#include "coding/scan_geometry.h"
#include "coding/scan_octree.h"
#include "coding/scan_raster.h"
#include "coding/scan_shared.h"

namespace capz {

namespace {

// The decoding side of scan::code_frame and scan::raster::code_frame: values come from the
// block, actual ones are unused.
class DecodeIo {
 public:
  // Decodes through a copy of dec's cursor (entropy.h): commit() stores it back at the end.
  explicit DecodeIo(IntDecoder* dec) : dec_(dec), c_(dec->cursor()) {}
  // The block's values (FORMAT.md "Zero first"; scan::value_kind).
  __attribute__((always_inline)) int32_t sym(int32_t, int32_t pred, int ctx) {
    return wrap_add(pred, unzigzag(c_.get_zero_first(ctx)));
  }
  __attribute__((always_inline)) int32_t sym_plain(int32_t, int32_t pred, int ctx) {
    int tok;
    return wrap_add(pred, c_.get_signed(ctx, &tok));
  }
  __attribute__((always_inline)) uint32_t ring(uint32_t, uint32_t rings, int ctx) {
    const uint32_t d = c_.get_zero_first(ctx);
    if (d >= rings) c_.corrupt("ring residual beyond the laser table");
    return d;
  }
  __attribute__((always_inline)) bool flag(bool, int ctx) { return c_.get_bit(ctx); }
  scan::Polar polar(size_t) const { return {}; }
  scan::Fire fire(size_t) const { return {}; }
  const int32_t* actual(size_t) const { return zero_; }
  bool actual_valid(size_t) const { return false; }
  // Raster frames.
  int32_t coord(size_t, int, int32_t) const { return 0; }
  int32_t pixel_residual(size_t, int64_t) const { return 0; }
  int32_t rho(size_t, int32_t) const { return 0; }
  int64_t check_pixel(int64_t p, size_t pixels) {
    if (p < 0 || static_cast<uint64_t>(p) >= pixels) c_.corrupt("pixel outside the raster table");
    return p;
  }
  void commit() { dec_->commit(c_); }

 private:
  IntDecoder* dec_;
  IntDecoder::Cursor c_;
  int32_t zero_[3] = {0, 0, 0};
};

// The blocks beside the payload's body: the counts block of frames with cells (FORMAT "Cells
// with counts") and the octree block of octree frames (FORMAT "Octree frames"), each when there.
struct SideBlocks {
  std::unique_ptr<IntDecoder> cells, tree;
  scan::OctreeMode mode;
  size_t cells_left = 0;            // the octree's cells still allowed (FORMAT "Octree frames")
  std::vector<int32_t> prev_cells;  // the previous frame's cells when it is an octree frame
  std::vector<uint32_t> counts;     // expand_cells' scratch
};

void open_side_blocks(const uint8_t* data, const scan::Header& h, const std::string& what,
                      SideBlocks* b) {
  if (h.cells_size > 0)
    b->cells.reset(new IntDecoder(data + h.cells, h.cells_size, scan::kCellContexts, what));
  if (h.octree_size > 0) {
    b->tree.reset(new IntDecoder(data + h.octree, h.octree_size, scan::kOctreeContexts, what));
    scan::start_octree_block(b->tree.get());
    b->mode = scan::read_octree_flags(b->tree.get(), h.table);
    if (b->mode.cones()) b->mode.cones()->budget = scan::kMaxConeWorkPerByte * h.octree_size;
  }
  b->cells_left = kMaxSymbolsPerByte * h.octree_size;
}

// The frames' counts as the take has them: a split frame is its two parts (FORMAT "Split
// frames"), whose points are already in order.
std::vector<uint32_t> take_counts(const scan::Header& h, const std::string& what) {
  std::vector<uint32_t> out;
  for (size_t f = 0; f < h.counts.size(); ++f)
    if (f > 0 && scan::near_part(h.flags[f - 1])) {
      if (h.counts[f] > UINT32_MAX - out.back())
        fail(ErrorCode::kCorrupt, what, "a split frame of 2^32 points or more");
      out.back() += h.counts[f];
    } else {
      out.push_back(h.counts[f]);
    }
  return out;
}

// The raster frames' pixel table (FORMAT "Raster frames"), read ahead of the body's values.
scan::raster::Pixels read_pixel_table(const scan::Header& h, IntDecoder* dec) {
  scan::raster::Pixels px;
  if (h.pixels > 0) scan::raster::read_pixels(dec, h, &px);
  return px;
}

// The moving state of decode_frames' body: the spherical and raster states and their decoder
// (whose cursor io copies after the pixel table is read: members in this order).
struct BodyState {
  BodyState(const scan::Header& h, IntDecoder* dec)
      : st(h.table), px(read_pixel_table(h, dec)), io(dec), rs(px.count()) {}
  scan::State st;
  scan::raster::Pixels px;
  DecodeIo io;
  scan::raster::State rs;
};

// Frame f of the body (not an octree frame), its first point `first`, into q and valid; its
// repeated cells expanded, and with `ring` (the points' geometry rings) none for them.
void decode_body_frame(const scan::Header& h, size_t f, size_t first, BodyState* b,
                       SideBlocks* side, int32_t* q, uint8_t* valid, uint16_t* ring) {
  const size_t coded = h.counts[f] - h.copies[f];  // the frame's coded points
  if (f == 0 || !scan::near_part(h.flags[f - 1]))  // a far part keeps its near part's cells
    side->prev_cells.clear();
  b->st.set_turn(h.turns.empty() ? 0 : h.turns[f]);  // FORMAT "Turns"
  if (h.flags[f] & scan::kRaster) {
    scan::raster::code_frame(b->io, b->px, b->rs, h.flags[f], first, coded, q, valid);
  } else if (f + 1 < h.counts.size()) {
    scan::code_frame(b->io, b->st, h.flags[f], first, coded, q, valid);
  } else {  // the last: on a trial state, which leaves the map no later sweep reads
    scan::State last = b->st.trial();
    scan::code_points(b->io, last, h.flags[f], first, coded, q, valid);
  }
  if (h.copies[f] == 0) return;
  scan::expand_cells(side->cells.get(), h.copies[f], h.counts[f], q, valid, &side->counts);
  if (ring)  // a frame with cells has no geometry ring (FORMAT.md predictor 13)
    std::fill(ring + first, ring + first + h.counts[f], ScanGeometry::kNoRing);
}

// decode_scan_geometry: with `frame`, each frame's integers go to it from a buffer of one frame;
// without, into g.q.
ScanGeometry decode_frames(const uint8_t* data, size_t size, const std::string& what,
                           size_t max_points, const ScanFrameSink* frame,
                           std::vector<int32_t>* space, bool rings = false) {
  const scan::Header h = scan::read_header(data, size, what, max_points);
  ScanGeometry g;
  std::vector<int32_t> one;  // a frame's integers, with `frame`
  if (space) (frame ? one : g.q).swap(*space);
  g.fine = h.fine;
  size_t total = 0, most = 0;
  for (uint32_t n : h.counts) total += n, most = std::max<size_t>(most, n);
  if (frame)
    size_for_overwrite(&one, 3 * most);  // each frame's values written before they are read
  else
    size_for_overwrite(&g.q, 3 * total);  // every value written below
  g.valid.resize(total);
  IntDecoder dec(data + h.body, size - h.body, scan::kContexts, what);
  dec.add_bit_models();
  BodyState body(h, &dec);
  if (rings) {
    g.ring.assign(total, ScanGeometry::kNoRing);
    body.st.ring_out = g.ring.data();
  }
  SideBlocks side;
  open_side_blocks(data, h, what, &side);
  g.octree = side.tree != nullptr;
  size_t first = 0;
  for (size_t f = 0; f < h.counts.size(); ++f) {
    int32_t* q = frame ? one.data() : g.q.data() + 3 * first;
    uint8_t* valid = g.valid.data() + first;
    if (scan::octree_frame(h.flags[f]))
      scan::decode_octree_frame(side.tree.get(), h.counts[f], h.copies[f],
                                (h.flags[f] & 3) == scan::kSomeValid, &side.cells_left,
                                &side.prev_cells, q, valid, &side.mode);
    else
      decode_body_frame(h, f, first, &body, &side, q, valid, rings ? g.ring.data() : nullptr);
    if (frame) (*frame)(first, h.counts[f], q, valid);
    first += h.counts[f];
  }
  body.io.commit();
  g.counts = take_counts(h, what);
  if (!dec.at_end()) fail(ErrorCode::kCorrupt, what, "bytes left after the scan geometry");
  if (side.cells && !side.cells->at_end())
    fail(ErrorCode::kCorrupt, what, "bytes left after the cells' counts");
  if (side.tree && !side.tree->at_end())
    fail(ErrorCode::kCorrupt, what, "bytes left after the octree");
  if (frame && space) space->swap(one);
  return g;
}

}  // namespace

ScanGeometry decode_scan_geometry(const uint8_t* data, size_t size, const std::string& what,
                                  size_t max_points) {
  return decode_frames(data, size, what, max_points, nullptr, nullptr);
}

ScanGeometry decode_scan_geometry(const uint8_t* data, size_t size, const std::string& what,
                                  size_t max_points, std::vector<int32_t>* space, bool rings) {
  return decode_frames(data, size, what, max_points, nullptr, space, rings);
}

ScanGeometry decode_scan_geometry(const uint8_t* data, size_t size, const std::string& what,
                                  size_t max_points, const ScanFrameSink& frame,
                                  std::vector<int32_t>* space) {
  return decode_frames(data, size, what, max_points, &frame, space);
}

std::vector<uint64_t> scan_frame_counts(const uint8_t* data, size_t size, const std::string& what) {
  ByteReader r(data, size, what);
  const size_t frames = static_cast<size_t>(r.count(2, "frame count"));
  std::vector<uint64_t> n(frames);
  for (uint64_t& v : n) v = r.varint();
  const uint8_t* flags = r.bytes(frames);
  std::vector<uint64_t> counts;
  for (size_t f = 0; f < frames; ++f)
    if (f > 0 && scan::near_part(flags[f - 1]))
      counts.back() += std::min(n[f], UINT64_MAX - counts.back());  // saturated: too many anyway
    else
      counts.push_back(n[f]);
  return counts;
}

int scan_fine_shift(const uint8_t* data, size_t size, const std::string& what) {
  return scan::read_header(data, size, what, SIZE_MAX).fine;
}

}  // namespace capz
