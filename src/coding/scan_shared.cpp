// The scan geometry coder's shared parts: header, table, trigonometry, state
// (docs/FORMAT.md "Scans (format 1.1)").
#include "coding/scan_shared.h"

#include <cmath>

#include "capz/error.h"
#include "coding/bytes.h"

namespace capz {
namespace scan {

namespace {

void check_finite(float v, ByteReader* r) {
  if (!std::isfinite(v)) fail(ErrorCode::kCorrupt, r->what(), "laser table value is not finite");
}

// The firing's slots (FORMAT.md, units bit 6).
void read_slots(ByteReader* r, uint64_t rings, Table* t, const std::string& what) {
  t->slots = r->u8();
  if (t->slots < 1 || t->slots > kMaxSlots)
    fail(ErrorCode::kCorrupt, what, "the laser table's firing slots are out of range");
  for (uint64_t k = 0; k < rings; ++k) t->slot.push_back(r->u8());
}

// The firing's turn and the rings' shares of it (FORMAT.md, units bit 3).
void read_shares(ByteReader* r, uint64_t rings, Table* t, const std::string& what) {
  t->fire_turn = r->f32();
  bool ok = std::fabs(t->fire_turn) <= kMaxFireTurn;
  for (uint64_t k = 0; k < rings; ++k) {
    t->share.push_back(r->f32());
    ok = ok && std::fabs(t->share.back()) <= kMaxShare;
  }
  if (!ok)
    fail(ErrorCode::kCorrupt, what, "the laser table's firing turn or shares are out of range");
}

// One packed field of `rings` values (FORMAT.md "Packed laser table"): each J_k 2^-E, binary64.
std::vector<double> read_packed(ByteReader* r, uint64_t rings, uint8_t* exponent) {
  const std::string& what = r->what();
  const int e = r->u8();
  int64_t j = r->svarint();
  if (e > kMaxPackExponent || j > kMaxPacked || j < -kMaxPacked)
    fail(ErrorCode::kCorrupt, what,
         "a packed laser table field's exponent or value is out of range");
  *exponent = static_cast<uint8_t>(e);
  std::vector<double> v(rings);
  v[0] = std::ldexp(static_cast<double>(j), -e);
  if (rings < 2) return v;
  const unsigned b = r->u8();
  if (b > kMaxPackBits)
    fail(ErrorCode::kCorrupt, what, "a packed laser table field's differences are too wide");
  const uint64_t bits = (rings - 1) * b, size = (bits + 7) / 8;
  if (size > r->remaining())
    fail(ErrorCode::kCorrupt, what, "a packed laser table field runs past the bytes left");
  const uint8_t* p = r->bytes(static_cast<size_t>(size));
  uint64_t at = 0;
  for (uint64_t k = 1; k < rings; ++k) {
    uint64_t u = 0;
    for (unsigned i = 0; i < b; ++i, ++at) u |= uint64_t{(p[at >> 3] >> (at & 7)) & 1u} << i;
    j += static_cast<int64_t>(u >> 1) ^ -static_cast<int64_t>(u & 1);  // |j| <= 2^53 before
    if (j > kMaxPacked || j < -kMaxPacked)
      fail(ErrorCode::kCorrupt, what, "a packed laser table value is out of range");
    v[k] = std::ldexp(static_cast<double>(j), -e);
  }
  if ((bits & 7) != 0 && (p[size - 1] >> (bits & 7)) != 0)
    fail(ErrorCode::kCorrupt, what, "a packed laser table field's padding bits are not zero");
  return v;
}

// The laser table's per-ring values after the units byte (FORMAT.md): plain or packed.
void read_rings(ByteReader* r, uint64_t rings, uint8_t byte, Table* t) {
  const uint8_t units = byte & 3;
  if (byte & kPackBit) {
    std::vector<double> f[5];
    const size_t fields = units == 0 ? 3 : units == 1 ? 4 : 5;
    t->pack.resize(fields);
    for (size_t i = 0; i < fields; ++i) f[i] = read_packed(r, rings, &t->pack[i]);
    for (uint64_t k = 0; k < rings; ++k) {
      t->azimuth0.push_back(static_cast<float>(f[0][k]));
      t->slope.push_back(static_cast<float>(f[1][k]));
      t->z0.push_back(static_cast<float>(f[2][k]));
      if (units != 0) t->unit.push_back(f[3][k]), t->offset.push_back(units == 2 ? f[4][k] : 0.0);
    }
  } else {
    for (uint64_t k = 0; k < rings; ++k) {
      t->azimuth0.push_back(r->f32());
      t->slope.push_back(r->f32());
      t->z0.push_back(r->f32());
    }
    for (uint64_t k = 0; units != 0 && k < rings; ++k) {
      t->unit.push_back(r->f64());
      t->offset.push_back(units == 2 ? r->f64() : 0.0);
    }
  }
  for (uint64_t k = 0; k < rings; ++k) {
    check_finite(t->azimuth0[k], r);
    check_finite(t->slope[k], r);
    check_finite(t->z0[k], r);
  }
  for (size_t k = 0; k < t->unit.size(); ++k)
    if (!(t->unit[k] >= kMinUnit && t->unit[k] <= kMaxUnit) ||
        !(std::fabs(t->offset[k]) <= kMaxOffset))
      fail(ErrorCode::kCorrupt, r->what(), "a ring's range unit or offset is out of range");
}

// The raster frames' pixel table header (FORMAT.md "Raster frames"); returns P.
uint32_t read_raster_header(ByteReader* r, Header* h) {
  const uint64_t p = r->varint();
  if (p == 0 || p > (uint64_t{1} << 22))
    fail(ErrorCode::kCorrupt, r->what(), "raster pixel table of 0 or more than 2^22 pixels");
  h->pixels = static_cast<uint32_t>(p);
  h->delta = r->f64();
  h->exponent = r->u8();
  h->fine = r->u8();
  if (!std::isfinite(h->delta) || !(h->delta > 0) || h->exponent > 30 || h->fine > kMaxFine)
    fail(ErrorCode::kCorrupt, r->what(),
         "raster range quantum, vector exponent or fine shift out of range");
  return h->pixels;
}

// A block of its own before the main block: varint(L), then L bytes (offset *at, size *size),
// for `symbols` values at most kMaxSymbolsPerByte a byte.
void read_side_block(ByteReader* r, uint64_t symbols, const char* name, const char* too_many,
                     size_t* at, size_t* size) {
  const uint64_t len = r->varint();
  if (len > r->remaining())
    fail(ErrorCode::kCorrupt, r->what(), std::string(name) + " is longer than the bytes left");
  *at = r->offset();
  *size = static_cast<size_t>(len);
  if (symbols > kMaxSymbolsPerByte * len) fail(ErrorCode::kCorrupt, r->what(), too_many);
  r->bytes(*size);
}

// The header's frame counts (their sum at most max_points), flags and copies.
void read_frames(ByteReader* r, size_t max_points, Header* h) {
  const std::string& what = r->what();
  const size_t frames = static_cast<size_t>(r->count(2, "frame count"));
  h->counts.resize(frames);
  uint64_t total = 0;
  for (uint32_t& n : h->counts) {
    const uint64_t v = r->varint();
    total += v;
    if (v > UINT32_MAX || total > max_points)
      fail(ErrorCode::kCorrupt, what,
           "the frames' point counts exceed " + std::to_string(max_points) + " points");
    n = static_cast<uint32_t>(v);
  }
  const uint8_t* f = r->bytes(frames);
  h->flags.assign(f, f + frames);
  h->flags_end = r->offset();
  h->copies.assign(frames, 0);
  for (size_t i = 0; i < frames; ++i) {
    if (!(h->flags[i] & kCells)) continue;
    const uint64_t d = r->varint();
    if (d == 0 || d >= h->counts[i])
      fail(ErrorCode::kCorrupt, what, "frame " + std::to_string(i) + "'s copies are out of range");
    h->copies[i] = static_cast<uint32_t>(d);
  }
}

// The laser table of `rings` rings (at least 1) after its ring count, its more byte and the
// frames' turns.
void read_table(ByteReader* r, uint64_t rings, Header* h) {
  const std::string& what = r->what();
  Table& t = h->table;
  t.step = r->f32();
  check_finite(t.step, r);
  const uint64_t cols = r->varint();
  if (t.step == 0.0f || cols == 0 || cols * rings > kMaxMapCells)
    fail(ErrorCode::kCorrupt, what, "laser table with a zero step or too many columns");
  t.columns = static_cast<uint32_t>(cols);
  const uint8_t byte = r->u8(), units = byte & 3;
  if (units == 3 || (byte & ~(7 | kShareBit | kTurnBit | kPackBit | kSlotBit | kBeforeBit)) != 0 ||
      ((byte & (kShareBit | kSlotBit)) && !(byte & kTurnBit)) ||
      ((byte & kShareBit) && (byte & kSlotBit)))
    fail(ErrorCode::kCorrupt, what, "unknown range units in the laser table");
  read_rings(r, rings, byte, &t);
  t.turn = (byte & kTurnBit) != 0;
  t.before = (byte & kBeforeBit) != 0;
  if (byte & kBowBit) {
    t.bow = r->f32();
    if (!(std::fabs(t.bow) <= kMaxBow))
      fail(ErrorCode::kCorrupt, what, "the laser table's bow is out of range");
  }
  if (byte & kShareBit) read_shares(r, rings, &t, what);
  if (byte & kSlotBit) read_slots(r, rings, &t, what);
  const uint8_t more = r->u8();
  t.successors = (more & kMoreSuccessors) != 0;
  if (more & ~(kMoreTurns | kMoreSuccessors))
    fail(ErrorCode::kCorrupt, what, "unknown bits in the table's more byte");
  if (more & kMoreTurns) {  // the frames' turns (FORMAT.md "Turns")
    h->turns.resize(h->counts.size());
    for (int32_t& v : h->turns) {
      const int64_t s = r->svarint();
      if (s >= int64_t{t.columns} || s <= -int64_t{t.columns})
        fail(ErrorCode::kCorrupt, what, "a frame's turn is a whole turn or more");
      v = static_cast<int32_t>(s);
    }
  }
}

// What the frames' flags say the blocks after the header hold (read_header).
struct FrameTally {
  uint64_t coded = 0;    // points that code at least one symbol
  uint64_t counted = 0;  // coded points of frames with cells: a count each at most
  // Octree frames' cells as far as known here (FORMAT "Octree frames"): the points less copies
  // of a frame without gaps, 1 at least for one with gaps (its G is in the octree block).
  uint64_t in_tree = 0;
  bool raster = false;
};

// The frames' flags checked (rings: the laser table's) and tallied.
FrameTally check_flags(const Header& h, uint64_t rings, const std::string& what) {
  FrameTally c;
  const size_t frames = h.counts.size();
  for (size_t i = 0; i < frames; ++i) {
    const uint8_t fl = h.flags[i];
    if (octree_frame(fl)) {
      if ((fl & 3) > kSomeValid || (fl & (kHypot | kRingPairs)) || h.counts[i] == 0)
        fail(ErrorCode::kCorrupt, what, "octree frame " + std::to_string(i) + " has unknown flags");
      if ((fl & kNearPart) && (i + 1 == frames || octree_frame(h.flags[i + 1])))
        fail(ErrorCode::kCorrupt, what,
             "split frame " + std::to_string(i) + "'s near part is not followed by a far part");
      c.in_tree += (fl & 3) == kSomeValid ? 1 : h.counts[i] - h.copies[i];
      continue;
    }
    if ((fl & ~kFrameFlagMask) != 0 || (fl & 3) == 3 || ((fl & kSpherical) && (fl & kRaster)) ||
        ((fl & (kRingWalk | kHypot | kRingPairs)) && !(fl & kSpherical)) ||
        ((fl & kRingWalk) && (fl & kRingPairs)))
      fail(ErrorCode::kCorrupt, what, "frame " + std::to_string(i) + " has unknown flags");
    if ((fl & kSpherical) && rings == 0)
      fail(ErrorCode::kCorrupt, what, "a spherical frame without a laser table");
    if ((fl & 3) != kNoneValid) c.coded += h.counts[i] - h.copies[i];
    if (fl & kCells) c.counted += h.counts[i] - h.copies[i];
    c.raster = c.raster || (fl & kRaster);
  }
  return c;
}

}  // namespace

Header read_header(const uint8_t* data, size_t size, const std::string& what, size_t max_points) {
  ByteReader r(data, size, what);
  Header h;
  read_frames(&r, max_points, &h);
  const uint64_t rings = r.varint();
  if (rings > kMaxRings) fail(ErrorCode::kCorrupt, what, "more than 1024 rings in the laser table");
  if (rings > 0) read_table(&r, rings, &h);
  FrameTally c = check_flags(h, rings, what);
  if (c.raster) c.coded += read_raster_header(&r, &h);
  if (c.counted > 0)  // the counts block (FORMAT "Cells with counts")
    read_side_block(&r, c.counted, "the counts block", "more points than the counts block can hold",
                    &h.cells, &h.cells_size);
  if (c.in_tree > 0)  // the octree block (FORMAT "Octree frames")
    read_side_block(&r, c.in_tree, "the octree block", "more cells than the octree block can hold",
                    &h.octree, &h.octree_size);
  h.body = r.offset();
  if (c.coded > kMaxSymbolsPerByte * (size - h.body))
    fail(ErrorCode::kCorrupt, what, "more points than the coded bytes can hold");
  return h;
}

State::State(const Table& t, std::shared_ptr<SweepMaps> maps)
    : ring(t.rings()),
      succ(t.rings()),
      firing(t.rings()),
      t_(&t),
      angles_(std::make_shared<const Angles>(t.azimuth0, static_cast<double>(t.step), t.columns)),
      maps_(std::move(maps)) {
  for (size_t k = 0; k < succ.size(); ++k) succ[k] = static_cast<uint32_t>((k + 1) % succ.size());
  if (!maps_) maps_ = std::make_shared<SweepMaps>();
  maps_->reset(t.rings() * t.columns);
}

void State::end_frame() {
  if (!trial_) maps_->end_sweep();
}

void State::clear_sweep() {
  maps_->clear_sweep();
}

}  // namespace scan
}  // namespace capz
