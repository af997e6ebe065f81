// The decoder (decoder.h). Part of the decoder library.
#include "codec/decoder.h"

#include <algorithm>
#include <cmath>

#include "capz/error.h"
#include "codec/decoder_registry.h"
#include "codec/grid.h"
#include "codec/negative_zeros.h"
#include "codec/transform_output.h"
#include "coding/analog/analog_codec.h"
#include "coding/attributes.h"
#include "coding/attributes_ring.h"
#include "coding/buffers.h"
#include "coding/bytes.h"
#include "coding/c3d_words.h"
#include "coding/entropy.h"
#include "coding/mask.h"
#include "coding/positions.h"
#include "coding/rotations.h"
#include "coding/scan_geometry.h"
#include "coding/scan_raw.h"
#include "coding/scan_shared.h"
#include "coding/scan_split.h"

namespace capz {
namespace {

// The chunks of one window, in order: next() returns the next chunk of a type, skipping the
// residue's and ancillary ones (an unknown critical type is refused, FORMAT.md 2); a window
// chunk of another type ends the search.
class WindowChunks {
 public:
  WindowChunks(const StreamContext& ctx, size_t w, const uint8_t* region, size_t base, size_t end)
      : ctx_(ctx),
        w_(w),
        region_(region),
        base_(base),
        end_(end),
        off_(base),
        wname_(" of window " + std::to_string(w)) {}

  Chunk next(const char* type, bool required) {
    while (off_ < end_) {
      const Chunk c = at_offset();
      if (c.type == type) {
        off_ = c.end;
        return c;
      }
      if (c.type == "POSW" || c.type == "MASK" || c.type == "SCNW" || c.type == "C3DW" ||
          c.type == "ANLG" || c.type == "ROTW" || c.type == "ATTR")
        break;
      check_chunk_known(c, ctx_.features, ctx_.name);
      off_ = c.end;  // a residue or ancillary chunk: skipped
    }
    if (required)
      fail(ErrorCode::kCorrupt, ctx_.name, std::string("missing chunk ") + type + wname_);
    return Chunk();
  }
  // The chunks after the last one read: each checked (CRC, and an unknown critical type refused,
  // FORMAT.md 2), none decoded (the residue's are read by the rebuild).
  void check_rest() {
    while (off_ < end_) {
      const Chunk c = at_offset();
      check_chunk_known(c, ctx_.features, ctx_.name);
      off_ = c.end;
    }
  }
  // Reads the window index that starts every window chunk's payload; it must be w.
  void open(const Chunk& c, ByteReader* r) const {
    const uint64_t idx = r->varint();
    if (idx != w_)
      fail(ErrorCode::kCorrupt, ctx_.name,
           "chunk " + c.type + " at byte " + std::to_string(c.offset) + " belongs to window " +
               std::to_string(idx) + ", expected " + std::to_string(w_));
  }
  // "name: chunk TYPE of window w", for messages.
  std::string what(const char* type) const {
    return (ctx_.name.empty() ? "" : ctx_.name + ": ") + "chunk " + type + wname_;
  }
  const std::string& wname() const { return wname_; }

 private:
  // The chunk at off_ (< end_), framing and CRC checked within the window's extent.
  Chunk at_offset() const {
    const uint8_t* p = region_ + (off_ - base_);
    if (end_ - off_ < kChunkOverhead || load_le32(p + 4) > end_ - off_ - kChunkOverhead)
      fail(ErrorCode::kCorrupt, ctx_.name,
           "chunk at byte " + std::to_string(off_) + wname_ + " runs past its INDX extent");
    return read_chunk(region_, end_, off_, ctx_.name, base_);
  }

  const StreamContext& ctx_;
  size_t w_;
  const uint8_t* region_;
  size_t base_, end_, off_;
  std::string wname_;
};

// Window positions with transform output: the codec's reconstruction of the valid samples.
void decode_transform_output(const uint8_t* data, size_t size, const StreamHeader& h, size_t fn,
                             const std::string& what, const WindowInts& wi,
                             std::vector<double>* xyz) {
  const TransformDecoder* codec = find_decoder(h.codec);
  if (!codec)
    fail(ErrorCode::kUnsupportedVersion, what,
         "stream uses transform codec id " + std::to_string(h.codec) + ", unknown to this capz");
  const CodecOnly co = split_transform_only(data, size, what);
  codec->decode(co.data, co.size, fn, h.points, xyz);
  if (xyz->size() != fn * h.points * 3)
    fail(ErrorCode::kCorrupt, what, "codec payload has the wrong size");
  for (size_t i = 0; i < fn * h.points; ++i)
    if (wi.valid[i])
      for (int a = 0; a < 3; ++a)
        if (!std::isfinite((*xyz)[i * 3 + a]))
          fail(ErrorCode::kCorrupt, what, "the transform reconstructs a non-finite value");
}

// The transform's prediction on the grid for a POSW with a codec block (empty without a codec).
std::vector<int32_t> transform_prediction(const StreamContext& ctx, const PositionsPayload& pp,
                                          size_t fn, const std::string& what) {
  const StreamHeader& h = ctx.h;
  if (h.codec == 0 || h.points == 0) return {};
  const TransformDecoder* codec = find_decoder(h.codec);
  if (!codec)
    fail(ErrorCode::kUnsupportedVersion, ctx.name,
         "stream uses transform codec id " + std::to_string(h.codec) + ", unknown to this capz");
  std::vector<double> recon;
  codec->decode(pp.codec_bytes, pp.codec_size, fn, h.points, &recon);
  if (recon.size() != fn * h.points * 3)
    fail(ErrorCode::kCorrupt, what, "codec payload has the wrong size");
  return grid_prediction(recon, h.step);
}

// POSW (and MASK) of the window: the gap mask into *valid, the coordinates of its valid
// samples into *xyz (fn x points x 3, gap samples 0) and its integers into *q (empty with
// transform output; ATTR predictors 10 and 11 read them, FORMAT.md 13.5).
void decode_window_positions(const StreamContext& ctx, WindowChunks* chunks, size_t fn,
                             std::vector<uint8_t>* valid, std::vector<double>* xyz,
                             std::vector<int32_t>* q) {
  const StreamHeader& h = ctx.h;
  const size_t N = h.points;
  Chunk pc = chunks->next("POSW", true);
  const std::string pwhat = chunks->what("POSW");
  ByteReader pr(pc.payload, pc.size, pwhat);
  chunks->open(pc, &pr);
  const uint8_t has_mask = pr.u8();
  if (has_mask > 1) fail(ErrorCode::kCorrupt, pwhat, "bad has_mask byte");
  WindowInts wi;
  wi.frames = fn;
  wi.points = N;
  wi.valid.assign(fn * N, 1);
  if (has_mask) {
    Chunk mc = chunks->next("MASK", true);
    ByteReader mr(mc.payload, mc.size, "MASK");
    chunks->open(mc, &mr);
    decode_mask(mc.payload + mr.offset(), mc.size - mr.offset(), fn, N, wi.valid.data(),
                chunks->what("MASK"));
  }
  const uint8_t* body = pc.payload + pr.offset();
  const size_t body_size = pc.size - pr.offset();
  std::vector<double> tout_xyz;  // transform output (FORMAT.md 4.3): the reconstruction itself
  if (h.transform_output) {
    decode_transform_output(body, body_size, h, fn, pwhat, wi, &tout_xyz);
  } else {
    const PositionsPayload pp = split_positions(body, body_size, pwhat);
    const std::vector<int32_t> tpred = transform_prediction(ctx, pp, fn, pwhat);
    decode_positions(pp, tpred, h.mode == PosMode::kFloat64, &wi, pwhat, ray_kind(h.mode));
  }
  if (h.transform_output) {
    xyz->assign(fn * N * 3, 0.0);
  } else {
    Grid g;
    g.mode = h.mode;
    g.step = h.step;
    dequantise_all(g, wi, xyz);  // gap samples are set to 0 below
  }
  for (size_t i = 0; i < fn * N; ++i)
    if (wi.valid[i]) {
      if (h.transform_output) std::copy(&tout_xyz[i * 3], &tout_xyz[i * 3 + 3], &(*xyz)[i * 3]);
      keep_valid_off_origin(h.source_format, h.lossless, &(*xyz)[i * 3]);
    } else {
      std::fill(&(*xyz)[i * 3], &(*xyz)[i * 3 + 3], 0.0);
    }
  valid->assign(wi.valid.begin(), wi.valid.end());
  q->swap(wi.q);
}

// ROTW of the window (FORMAT.md 12): its fn x R samples of G segments into the block's
// rotation arrays.
void decode_window_rotations(const StreamContext& ctx, WindowChunks* chunks, size_t fn,
                             FrameBlock* b) {
  const size_t R = ctx.h.rotation_samples_per_frame, G = ctx.h.rotation_segments;
  Chunk rc = chunks->next("ROTW", true);
  const std::string rwhat = chunks->what("ROTW");
  ByteReader rr(rc.payload, rc.size, rwhat);
  chunks->open(rc, &rr);
  // decode_rotations checks the count against the block's size before allocating.
  RotationWindow rw =
      decode_rotations(rc.payload + rr.offset(), rc.size - rr.offset(), fn * R, G, rwhat);
  b->rotation_matrices.swap(rw.matrices);
  b->rotation_reliability.swap(rw.reliability);
}

// Opens window w's SCNW chunk: checks the window index and returns the window's total points,
// within the caller's limit, in *origin its gaps byte's bit 0 (FORMAT.md "Origin points") and
// in *raw its bit 1 ("Raw windows"; *r then after that byte).
uint64_t open_scan_chunk(const StreamContext& ctx, WindowChunks* chunks, const Chunk& c,
                         ByteReader* r, bool* origin, bool* raw) {
  chunks->open(c, r);
  const uint64_t total = r->varint();
  if (total > ctx.max_points)
    fail(ErrorCode::kMemoryLimit, chunks->what("SCNW"),
         std::to_string(total) + " points exceed the memory limit (" +
             std::to_string(ctx.max_points) + " points)");
  const uint8_t gaps = r->u8();
  if (gaps > (scan::kOriginGapsBit | scan::kRawWindowBit))
    fail(ErrorCode::kCorrupt, chunks->what("SCNW"),
         "gaps byte " + std::to_string(gaps) + " has bits other than bits 0 and 1");
  *origin = (gaps & scan::kOriginGapsBit) != 0;
  *raw = (gaps & scan::kRawWindowBit) != 0;
  const PosMode m = ctx.h.mode;
  if (*raw && (*origin || !ctx.h.lossless || (m != PosMode::kFloat32 && m != PosMode::kFloat64)))
    fail(ErrorCode::kCorrupt, chunks->what("SCNW"),
         "a raw window with origin points, in a bounded stream or outside modes 2 and 3");
  if (!*raw && m == PosMode::kFloat64)
    fail(ErrorCode::kCorrupt, chunks->what("SCNW"), "a mode 3 window that is not raw");
  return total;
}

// SCNW's fields after `total` ("Lossless ragged streams"): the negative zeros of a lossless
// mode 1 window into *zeros (else none), then the split exponent E (mode 2 only), returned, or
// scan::kNoSplit.
int read_split(const StreamHeader& h, uint64_t total, ByteReader* r, std::vector<uint64_t>* zeros) {
  zeros->clear();
  if (lists_negative_zeros(h)) *zeros = read_negative_zeros(r, total);
  if (h.mode != PosMode::kFloat32) return scan::kNoSplit;
  const int e = static_cast<int8_t>(r->u8());
  if (e != scan::kNoSplit && (e < scan::kMinSplitExponent || e > scan::kMaxSplitExponent))
    fail(ErrorCode::kCorrupt, r->what(),
         "float32 split exponent " + std::to_string(e) + " is neither -128 nor in -64..64");
  return e;
}

// A raster window's fine shift k as the factor 2^-k of its integers (exact: (q s) 2^-k), only
// in mode 0.
double scan_fine(const Grid& grid, int k, const std::string& what) {
  if (k != 0 && grid.mode != PosMode::kGrid)
    fail(ErrorCode::kCorrupt, what, "a raster fine shift outside mode 0");
  return std::ldexp(1.0, -k);
}

// The coordinates of n scan points from their grid integers (3 n) and flags, 0 at gaps.
void scan_coordinates(const Grid& grid, double fine, size_t n, const int32_t* q,
                      const uint8_t* valid, double* xyz) {
  with_mode(grid.mode, [&](auto m) {
    for (size_t i = 0; i < n; ++i)
      for (size_t a = 0; a < 3; ++a)
        xyz[3 * i + a] =
            valid[i] ? dequantise_as<decltype(m)::value>(grid, q[3 * i + a], 0) * fine : 0.0;
  });
}

// Throws kCorrupt when a frame of n points is not of the organized shape of ctx's layout
// (FORMAT.md "Ragged frames: HEAD and the window chunk").
void check_organized_count(const StreamContext& ctx, uint64_t n, const std::string& what) {
  const size_t shape = organized_points(ctx);
  if (shape != 0 && n != shape)
    fail(ErrorCode::kCorrupt, what,
         "a frame of " + std::to_string(n) + " points in a stream whose frames are " +
             std::to_string(ctx.take.pcd->width) + " x " + std::to_string(ctx.take.pcd->height));
}

// A window's frame offsets into b from its frames' counts (their number and sum checked by the
// caller), each count checked against an organized layout's shape.
void set_frame_offsets(const StreamContext& ctx, const std::vector<uint32_t>& counts,
                       const std::string& what, FrameBlock* b) {
  b->frame_offsets.assign(counts.size() + 1, 0);
  for (size_t f = 0; f < counts.size(); ++f) {
    check_organized_count(ctx, counts[f], what);
    b->frame_offsets[f + 1] = b->frame_offsets[f] + counts[f];
  }
}

// "Raw windows": the rest of a raw window's SCNW (r after its gaps byte) into b's frame offsets,
// gaps and coordinates; *q its grid integers with fields in mode 2 (else none), no geometry rings
// (ATTR's predictor 13 walks without them).
void decode_raw_scan(const StreamContext& ctx, const Chunk& c, const ByteReader& r, size_t fn,
                     uint64_t total, const std::string& what, FrameBlock* b,
                     std::vector<int32_t>* q, std::vector<uint16_t>* rings) {
  const bool f64 = ctx.h.mode == PosMode::kFloat64;
  scan::RawWindow rw = scan::decode_raw_window(c.payload + r.offset(), c.size - r.offset(), what,
                                               fn, total, f64 ? 8 : 4);
  set_frame_offsets(ctx, rw.counts, what, b);
  b->valid.swap(rw.valid);
  b->xyz.swap(rw.xyz);
  rings->clear();
  if (!f64 && !ctx.take.attributes.empty())
    *q = scan::raw_window_ints(b->xyz, b->valid);
  else
    q->clear();
}

// "Scans (format 1.1)": the fn frames of window w of a ragged stream from its SCNW chunk, into
// out's frame offsets, gaps and coordinates (gaps 0), and its grid integers (total x 3, in the
// flattened point order) into *q for ATTR's predictors 10 and 11, and with fields each point's
// geometry ring into *rings for ATTR's predictor 13 (else *rings empty); *origin: the window's
// gaps are origin points (FORMAT.md "Origin points", made points by the caller after ATTR).
void decode_window_scan(const StreamContext& ctx, WindowChunks* chunks, size_t fn, FrameBlock* out,
                        std::vector<int32_t>* q, std::vector<uint16_t>* rings, bool* origin) {
  Chunk c = chunks->next("SCNW", true);
  const std::string what = chunks->what("SCNW");
  ByteReader r(c.payload, c.size, what);
  bool raw = false;
  const uint64_t total = open_scan_chunk(ctx, chunks, c, &r, origin, &raw);
  if (raw) return decode_raw_scan(ctx, c, r, fn, total, what, out, q, rings);
  std::vector<uint64_t> zeros;
  const int e = read_split(ctx.h, total, &r, &zeros);
  size_t geo = r.remaining();
  if (e != scan::kNoSplit) {
    const uint64_t len = r.varint();
    if (len > r.remaining()) fail(ErrorCode::kCorrupt, what, "geometry length beyond the chunk");
    geo = static_cast<size_t>(len);
  }
  const size_t at = r.offset();
  FrameBlock& b = *out;
  Grid grid;
  grid.mode = ctx.h.mode;
  grid.step = ctx.h.step;
  // Without ATTR (predictors 10 and 11) or the float32 split, nothing reads the window's
  // integers but its coordinates: each frame's become coordinates as soon as they are decoded,
  // from one frame's buffer (the window's integers are never all held) in *q's memory.
  const bool keep_q = e != scan::kNoSplit || !ctx.take.attributes.empty();
  ScanGeometry g;
  if (keep_q) {
    g = decode_scan_geometry(c.payload + at, geo, what, static_cast<size_t>(total), q,
                             !ctx.take.attributes.empty());
  } else {
    const double fine = scan_fine(grid, scan_fine_shift(c.payload + at, geo, what), what);
    size_for_overwrite(&b.xyz, static_cast<size_t>(total) * 3);  // each value written once
    g = decode_scan_geometry(
        c.payload + at, geo, what, static_cast<size_t>(total),
        [&](size_t first, size_t n, const int32_t* fq, const uint8_t* fv) {
          if (first + n > total)  // read_header bounds them: not reached
            fail(ErrorCode::kCorrupt, what, "frames beyond the chunk's total");
          scan_coordinates(grid, fine, n, fq, fv, b.xyz.data() + 3 * first);
        },
        q);
  }
  if (g.octree && !ctx.h.octree_frames)
    fail(ErrorCode::kCorrupt, what, "octree frames in a stream without HEAD feature bit 6");
  if (g.counts.size() != fn)
    fail(ErrorCode::kCorrupt, what,
         std::to_string(g.counts.size()) + " frames, the window has " + std::to_string(fn));
  if (g.total() != total)
    fail(ErrorCode::kCorrupt, what,
         "frame counts sum to " + std::to_string(g.total()) + " points, the chunk says " +
             std::to_string(total));
  set_frame_offsets(ctx, g.counts, what, &b);
  b.valid.swap(g.valid);
  rings->swap(g.ring);
  if (e != scan::kNoSplit) {  // "Lossless ragged streams": the float32 split
    b.xyz.assign(b.valid.size() * 3, 0.0);
    scan::decode_split(c.payload + at + geo, c.size - at - geo, what, e, g.q, b.valid,
                       b.xyz.data());
    q->swap(g.q);
    return;
  }
  if (keep_q) {
    const double fine = scan_fine(grid, g.fine, what);
    size_for_overwrite(&b.xyz, b.valid.size() * 3);  // each value written once below
    scan_coordinates(grid, fine, b.valid.size(), g.q.data(), b.valid.data(), b.xyz.data());
  }
  apply_negative_zeros(zeros, b.valid, what, &b.xyz);
  if (keep_q)
    q->swap(g.q);
  else
    q->clear();  // none held (the buffer's memory kept)
}

// ATTR of the window (FORMAT.md 13): its fields over `frames` x `points` (a ragged window: one
// frame of all its points, "Scans (format 1.1)") into out->attributes. q: the window's grid
// integers (frames x points x 3), or empty (predictors 10 and 11 are then corrupt); rings: a
// ragged window's geometry rings (predictor 13), else empty.
void decode_window_attributes(const StreamContext& ctx, WindowChunks* chunks, size_t frames,
                              size_t points, size_t width, const std::vector<int32_t>& q,
                              const std::vector<uint16_t>& rings, FrameBlock* out) {
  Chunk tc = chunks->next("ATTR", true);
  const std::string twhat = chunks->what("ATTR");
  ByteReader tr(tc.payload, tc.size, twhat);
  chunks->open(tc, &tr);
  const PCDExtra* px = ctx.take.pcd.get();
  RaggedFields ragged;  // a ragged window: key-first, predictor 12 on its decoded positions
  ragged.xyz = out->xyz.data();
  ragged.ring = rings.size() == frames * points ? rings.data() : nullptr;
  if (q.size() == frames * points * 3 && !q.empty() && !out->frame_offsets.empty() &&
      out->frame_offsets.back() == frames * points) {
    ragged.q = q.data();
    ragged.frame_offsets = out->frame_offsets.data();
    ragged.frames = out->frame_offsets.size() - 1;
  }
  decode_attributes(tc.payload + tr.offset(), tc.size - tr.offset(), attribute_specs(px->fields),
                    out->valid.data(), frames, points, width, &out->attributes, twhat,
                    q.size() == frames * points * 3 && !q.empty() ? q.data() : nullptr,
                    ctx.h.ragged ? &ragged : nullptr);
}

}  // namespace

// The rings the scan decoder hands ATTR (predictor 13) mean the same to both: no ring, and the
// most rings a payload has.
static_assert(attr::kNoGeometryRing == ScanGeometry::kNoRing, "a point without a geometry ring");
static_assert(attr::kMaxGeometryRings == scan::kMaxRings, "the most rings of a payload");

void origin_points(FrameBlock* b) {
  for (size_t i = 0; i < b->valid.size(); ++i)
    if (!b->valid[i]) {
      b->valid[i] = 1;
      for (size_t a = 0; a < 3; ++a) b->xyz[3 * i + a] = 0.0;
    }
}

void decode_window_chunks(const StreamContext& ctx, size_t w, const uint8_t* region, size_t base,
                          size_t end, FrameBlock* out, std::vector<int32_t>* ints) {
  const StreamHeader& h = ctx.h;
  const size_t N = h.points;
  const size_t f0 = w * h.window_frames;
  const size_t fn = std::min<size_t>(h.window_frames, static_cast<size_t>(h.frames) - f0);
  const size_t S = h.analog_samples_per_frame, C = h.analog_channels;
  WindowChunks chunks(ctx, w, region, base, end);
  FrameBlock& b = *out;
  // Decoded straight into the caller's arrays (their capacity is reused window after window).
  std::vector<int32_t> q;       // the window's POSW or SCNW integers (none with transform output)
  std::vector<uint16_t> rings;  // a ragged window's geometry rings (with fields)
  if (ints) q.swap(*ints);      // its memory, given back at the end
  b.frame_offsets.clear();
  if (h.ragged && ctx.words) fail(ErrorCode::kCorrupt, ctx.name, "ragged frames with C3D words");
  bool origin = false;  // a ragged window's gaps are origin points (FORMAT.md "Origin points")
  if (h.ragged)
    decode_window_scan(ctx, &chunks, fn, &b, &q, &rings, &origin);
  else
    decode_window_positions(ctx, &chunks, fn, &b.valid, &b.xyz, &q);
  // The analog rows must fit what the chunks can hold before they are allocated.
  const size_t per_byte = kMaxAnalogValuesPerByte;
  if (C > 0 && S > 0 && fn * S * C > per_byte * (end - base))
    fail(ErrorCode::kCorrupt, ctx.name,
         "analog window" + chunks.wname() + " larger than its chunks can hold");
  b.first = f0;
  b.frames = fn;
  b.points = N;
  b.residual.assign(ctx.words ? fn * N : 0, 0.0f);
  b.camera_mask.assign(ctx.words ? fn * N : 0, 0);
  b.analog.assign(C > 0 && S > 0 ? fn * S * C : 0, 0.0);
  if (ctx.words) {
    Chunk cc = chunks.next("C3DW", true);
    const std::string cwhat = chunks.what("C3DW");
    ByteReader cr(cc.payload, cc.size, cwhat);
    chunks.open(cc, &cr);
    decode_c3d_words(cc.payload + cr.offset(), cc.size - cr.offset(), b.valid.data(), fn * N, N,
                     ctx.take.c3d->point_scale, b.residual.data(), b.camera_mask.data(), cwhat);
  }
  if (C > 0 && S > 0) {
    Chunk ac = chunks.next("ANLG", true);
    const std::string awhat = chunks.what("ANLG");
    ByteReader ar(ac.payload, ac.size, awhat);
    chunks.open(ac, &ar);
    if (fn * S * C > per_byte * ac.size)
      fail(ErrorCode::kCorrupt, awhat, "analog window larger than its chunk can hold");
    decode_analog_window(ac.payload + ar.offset(), ac.size - ar.offset(), fn * S,
                         static_cast<int>(C), b.analog.data(), awhat, S);
  }
  b.rotation_matrices.clear();
  b.rotation_reliability.clear();
  if (ctx.h.rotations()) decode_window_rotations(ctx, &chunks, fn, out);
  b.attributes.clear();
  if (!ctx.take.attributes.empty() && h.ragged) {  // one frame of every point, of width total
    const size_t total = b.valid.size();
    decode_window_attributes(ctx, &chunks, 1, total, total, q, rings, out);
  } else if (!ctx.take.attributes.empty()) {
    decode_window_attributes(ctx, &chunks, fn, N, ctx.take.pcd->width, q, {}, out);
  }
  chunks.check_rest();
  if (origin) origin_points(&b);
  if (ints) ints->swap(q);
}

void window_extent(const ParsedStream& ps, size_t size, size_t w, size_t* base, size_t* end) {
  const IndexEntry& ie = ps.index[w];
  if (ie.offset < ps.first_window_offset || ie.offset >= size || ie.bytes > size - ie.offset)
    fail(ErrorCode::kCorrupt, ps.name,
         "INDX entry of window " + std::to_string(w) + " points outside the file");
  *base = static_cast<size_t>(ie.offset);
  *end = *base + static_cast<size_t>(ie.bytes);
}

std::vector<size_t> ragged_frame_offsets(StreamBytes& bytes, const ParsedStream& ps,
                                         std::vector<int>* splits) {
  std::vector<size_t> off(1, 0);
  const size_t F = static_cast<size_t>(ps.h.frames), W = ps.h.window_frames;
  for (size_t w = 0; w < ps.index.size(); ++w) {
    size_t base = 0, end = 0;
    window_extent(ps, bytes.size(), w, &base, &end);
    WindowChunks chunks(ps, w, bytes.get(base, end - base), base, end);
    const Chunk c = chunks.next("SCNW", true);
    const std::string what = chunks.what("SCNW");
    ByteReader r(c.payload, c.size, what);
    bool origin = false, raw = false;
    const uint64_t total = open_scan_chunk(ps, &chunks, c, &r, &origin, &raw);
    std::vector<uint64_t> counts;
    if (raw) {  // "Raw windows"
      if (splits) splits->push_back(scan::kRawWindowKey);
      counts = scan::raw_frame_counts(c.payload + r.offset(), c.size - r.offset(), what);
    } else {
      std::vector<uint64_t> zeros;
      const int e = read_split(ps.h, total, &r, &zeros);
      if (e != scan::kNoSplit) r.varint();  // the geometry's length
      if (splits) splits->push_back(e);
      counts = scan_frame_counts(c.payload + r.offset(), c.size - r.offset(), what);
    }
    const size_t fn = std::min(W, F - std::min(F, w * W));
    if (counts.size() != fn) fail(ErrorCode::kCorrupt, what, "frame count is not the window's");
    uint64_t sum = 0;
    for (uint64_t n : counts) {
      check_organized_count(ps, n, what);
      sum += n;
      if (n > total || sum > total) break;
      off.push_back(off.back() + static_cast<size_t>(n));
    }
    if (sum != total)
      fail(ErrorCode::kCorrupt, what,
           "frame counts disagree with the chunk's total of " + std::to_string(total));
  }
  if (off.size() != F + 1) fail(ErrorCode::kCorrupt, ps.name, "windows do not hold every frame");
  return off;
}

void decode_window(StreamBytes& bytes, const ParsedStream& ps, size_t w, FrameBlock* out,
                   std::vector<int32_t>* ints) {
  size_t base = 0, end = 0;
  window_extent(ps, bytes.size(), w, &base, &end);
  decode_window_chunks(ps, w, bytes.get(base, end - base), base, end, out, ints);
}

}  // namespace capz
