// The encoder of ragged takes (scan_encoder.h).
#include "codec/scan_encoder.h"

#include <algorithm>
#include <cmath>
#include <cstring>
#include <initializer_list>
#include <limits>
#include <map>
#include <memory>
#include <string>
#include <type_traits>
#include <utility>

#include "capz/error.h"
#include "capz/metrics.h"
#include "codec/decoder.h"
#include "codec/encode_settings.h"
#include "codec/grid.h"
#include "codec/grid_choice.h"
#include "codec/negative_zeros.h"
#include "codec/point_order.h"
#include "codec/residue_writer.h"
#include "codec/scan_field_hints.h"
#include "codec/scan_raw_choice.h"
#include "codec/scan_split_choice.h"
#include "codec/scan_window_check.h"
#include "codec/stream_reader.h"
#include "coding/attributes.h"
#include "coding/attributes_quantum.h"
#include "coding/bytes.h"
#include "coding/container.h"
#include "coding/meta.h"
#include "coding/scan_geometry.h"
#include "coding/scan_raw.h"
#include "coding/scan_split.h"
#include "io/frame_files.h"
#include "io/take_source.h"

namespace capz {
namespace {

// What format 1.1 does not code yet for frames of their own size: refused, never dropped.
void refuse_unsupported(const Take& t, const CompressOptions& opts) {
  const std::string what = "frames of their own point counts (a ragged take, format 1.1)";
  if (!opts.lossless && !(opts.max_error > 0))
    fail(ErrorCode::kInvalidParameter, t.source,
         "only --max-error and --lossless are implemented for " + what + " (no KG target)");
  const bool frames = is_frame_files(t.format);
  if (!frames || t.analog.channels > 0 || t.rotations.segments > 0)
    fail(ErrorCode::kInvalidParameter, t.source,
         "only PCD, PLY and .bin frames are coded as " + what + " yet: convert them first");
  if (opts.any_point_order && opts.lossless)  // refused earlier by compress(); for direct calls
    fail(ErrorCode::kInvalidParameter, t.source, "--point-order any with --lossless");
  if (opts.lossless && !opts.analog_max_error.empty())  // as set_analog_bounds says it
    fail(ErrorCode::kInvalidParameter, t.source,
         "--lossless keeps every analog sample: it cannot be given with --analog-max-error");
}

// Frames per window: about 2^21 points in a window at a bound, 2^20 lossless, 1 .. 8192 frames.
// A window's first sweep has no sweep before it and costs 2.2-2.6x the next ones at a bound
// (pandar64: 4.9 bits a point more at 1 cm), while the encoder holds 85-90 bytes a point of the
// window: 2^21 points halve that first sweep's share of 2^20's for about 110 MiB more. Lossless,
// a window of 2^21 points was only 1.5 % smaller, for 55 % more memory
// (docs/lab/2026-12-02-scan-windows.md).
uint32_t window_frames(const Take& t, const CompressOptions& opts) {
  if (opts.window_frames > 0)
    return static_cast<uint32_t>(std::min<size_t>(opts.window_frames, kMaxWindowFrames));
  size_t most = 1;
  for (size_t f = 0; f < t.frames; ++f) most = std::max(most, t.frame_points(f));
  const size_t points = opts.lossless ? size_t{1} << 20 : size_t{1} << 21;
  return static_cast<uint32_t>(std::clamp<size_t>(points / most, 1, kMaxWindowFrames));
}

// What choose_grid reads of the take (hdr: its header): x y z's layout spelled out, and no
// per-point ray track (not for frames of their own size).
TakeScan start_ragged_scan(const Take& t, const CompressOptions& opts, Take* hdr) {
  hdr->source = t.source;
  hdr->format = t.format;
  hdr->units = t.units;
  hdr->pcd = std::make_shared<PCDExtra>();
  // x's size, which bounded_grid reads (float32_frames) for the files written back: a float64
  // frame keeps its values' precision, and a field list is needed to say so (none: F 4).
  hdr->pcd->fields = {PCDField{"x", 'F', float32_frames(t) ? 4 : 8, 1}};
  TakeScan s = start_scan(*hdr, opts);
  s.ray_track = false;
  s.zeros_listed = true;  // a lossless decimal grid's windows list their negative zeros
  return s;
}

// The grid whose step bounds every coordinate by opts.max_error, after float32 rounding when
// the frames are written back as float32. Pass 1 (docs/STREAMING.md "Passes over the source"):
// the source read a window of frames at a time, each block's values scanned where they are
// (maxima, minima and all-of flags, so the order of the blocks does not matter). The blocks are
// read last to first, so *first ends holding window 0's frames, which pass 2 codes first
// without reading them again; the windows before it only need their coordinates scanned (a
// file source's read_coordinates).
Grid choose_grid(FrameSource& src, const CompressOptions& opts, size_t W, FrameBlock* first) {
  const Take& t = src.header();
  Take hdr;
  TakeScan s = start_ragged_scan(t, opts, &hdr);
  // Frame files' sources read coordinates alone cheaper. A virtual of the public FrameSource
  // would move its vtable (the installed library's ABI), so the one source is asked for here.
  FileFrameSource* files = dynamic_cast<FileFrameSource*>(&src);
  for (size_t f0 = t.frames ? (t.frames - 1) / W * W : 0;; f0 -= W) {
    if (t.frames && f0 > 0 && files)
      files->read_coordinates(f0, std::min(W, t.frames - f0), first);
    else if (t.frames)
      src.read(f0, std::min(W, t.frames - f0), first);
    scan_block(*first, t.source, false, 0, &s);
    if (f0 == 0) break;
  }
  // Lossless ("Lossless ragged streams"): a decimal grid, float32 bits, or float64 bits in raw
  // windows ("Raw windows").
  Grid g = opts.lossless ? lossless_grid(s) : bounded_grid(hdr, s, opts.max_error);
  if (!opts.lossless && g.mode == PosMode::kDecimal)
    fail(ErrorCode::kInvalidParameter, t.source,
         std::string("no grid for frames of their own size in mode ") + mode_name(g.mode));
  return g;
}

// The organized shape META keeps for t's frames (FORMAT.md "Ragged frames: HEAD and the window
// chunk"): its PCD layout's width x height when that is every frame's count, else the count x 1.
// Throws kInvalidParameter when the frames' counts differ or are 0.
std::pair<size_t, size_t> organized_shape(const Take& t) {
  const size_t n = t.frames ? t.frame_points(0) : 0;
  for (size_t f = 0; f < t.frames; ++f)
    if (t.frame_points(f) != n || n == 0)
      fail(ErrorCode::kInvalidParameter, t.source,
           "frames of one organized shape need one point count, above 0, in every frame");
  if (t.pcd && t.pcd->width > 0 && t.pcd->width * t.pcd->height == n)
    return {t.pcd->width, t.pcd->height};
  return {n, 1};
}

// The take META describes: t's header (no samples) with its PCD layout as the archive keeps it
// ("Ragged frames: HEAD and the window chunk": width 0 and height 1, or with `organized` the
// frames' one shape): x y z and the point fields (settled and bounded as for every take,
// encode_settings.h), or x y z alone without fields or with opts.drop_fields.
Take meta_take_of(const Take& t, const CompressOptions& opts, bool organized) {
  Take m = t;
  m.xyz.clear();
  m.valid.clear();
  for (PointAttribute& a : m.attributes) a.data.clear();
  if (m.attributes.empty() || opts.drop_fields) {
    m.attributes.clear();
    if (m.pcd) {
      auto x = std::make_shared<PCDExtra>(*m.pcd);
      x->fields.erase(std::remove_if(x->fields.begin(), x->fields.end(),
                                     [](const PCDField& f) {
                                       return f.name != "x" && f.name != "y" && f.name != "z";
                                     }),
                      x->fields.end());
      m.pcd = x;
    }
  } else {
    settle_fields(m, opts);
  }
  set_field_bounds(m, opts);
  const std::pair<size_t, size_t> shape =
      organized ? organized_shape(t) : std::pair<size_t, size_t>{0, 1};
  if (organized && !m.pcd) m.pcd = std::make_shared<PCDExtra>();
  if (m.pcd && (m.pcd->width != shape.first || m.pcd->height != shape.second)) {
    auto x = std::make_shared<PCDExtra>(*m.pcd);
    x->width = shape.first;
    x->height = shape.second;
    m.pcd = x;
  }
  return m;
}

// What encode_ragged carries from window to window.
struct RaggedRun {
  RaggedRun(const Take& t_, const CompressOptions& opts_, const Grid& grid_,
            const StreamContext& ctx_, const Take& meta_, StreamOut* out_, ResidueWriter* residue_)
      : t(t_), opts(opts_), grid(grid_), ctx(ctx_), meta(meta_), out(out_), residue(residue_) {}
  const Take& t;  // the source's header
  const CompressOptions& opts;
  const Grid& grid;
  const StreamContext& ctx;
  const Take& meta;               // META's take: its layout names the fields coded
  StreamOut* out;                 // the stream so far
  std::vector<IndexEntry> index;  // INDX
  size_t position_bytes = 0, attribute_bytes = 0;
  std::map<int, size_t> splits;  // mode 2: windows per split exponent (CompressStats)
  ErrorAccumulator acc;
  ResidueWriter* residue = nullptr;  // a lossless stream of a folder: PCDP per window
  std::vector<uint8_t> buf;          // the window's chunks
  WindowChecks* checks = nullptr;    // the self-check of each window (decodes_windows)
  int fine = 0;                      // the last SCNW's fine shift (FORMAT.md "Raster frames")
  ScanWorkspace scan_ws;             // the scan coder's maps, kept from window to window
  bool origin = false;               // the window's gaps are origin points (SCNW's gaps bit 0)
  bool key_fields = false;           // META has a field predictor 13 may code (attr::is_key_field)
  int last_split = scan::kNoSplit;   // mode 2: the window before's (choose_split's start)
  FieldTrials trials;                // the fields' trials skipped (RaggedFields::trials)
};

// The SCNW chunk of window w (the frames of b), appended to r.buf; *q gets the integers the
// payload codes (with fields; without, a fine window's are not worked out: the grid's). coded: the
// window's geometry payload when --point-order any's choice has coded it already (never in mode 2),
// else null. *rings (when not null): each point's geometry ring in the payload (ATTR's predictor
// 13: FORMAT.md "Point fields of a ragged window").
void append_scan_chunk(RaggedRun& r, size_t w, const FrameBlock& b, std::vector<int32_t>* q,
                       const std::vector<uint8_t>* coded, std::vector<uint16_t>* rings) {
  const size_t n = b.total_points();
  ScanGeometry g;
  for (size_t k = 0; k < b.frames; ++k)
    g.counts.push_back(static_cast<uint32_t>(b.frame_points(k)));
  std::vector<int32_t> bits = std::move(quantise_window(b, r.grid).q);
  g.valid = b.valid;
  ScanHints hints;
  if (!coded) {
    hints.ring = ring_field(r.t.attributes, b);
    hints.distance = distance_field(r.t.attributes, b);
    hints.xyz.resize(b.xyz.size());
    for (size_t i = 0; i < b.xyz.size(); ++i) hints.xyz[i] = static_cast<float>(b.xyz[i]);
  }
  // Mode 2 (lossless float32): a float32 split when it codes smaller.
  const bool mode2 = r.grid.mode == PosMode::kFloat32;
  if (mode2 && coded)
    fail(ErrorCode::kInternal, r.t.source, "a float32 split of a reordered window");
  int e = mode2 ? choose_split(b, g.counts, hints, bits, r.last_split, &r.scan_ws) : scan::kNoSplit;
  std::vector<uint32_t> corrections;
  if (e != scan::kNoSplit && !scan::split_coordinates(b.xyz.data(), g.valid.data(), g.valid.size(),
                                                      e, kSplitLimit, &g.q, &corrections))
    e = scan::kNoSplit;  // a later frame's coordinate beyond the split's integers
  if (e == scan::kNoSplit) g.q = std::move(bits);
  if (mode2) ++r.splits[e], r.last_split = e;
  hints.grid_per_unit = e != scan::kNoSplit ? std::ldexp(1.0, e) : grid_per_unit(r.grid);
  bound_hints(r.grid, &hints);
  ByteWriter pw;
  pw.varint(w);
  pw.varint(n);
  pw.u8(r.origin ? scan::kOriginGapsBit : 0);  // gaps
  if (lists_negative_zeros(r.ctx.h)) write_negative_zeros(b.xyz, b.valid, &pw);
  std::vector<uint8_t> payload = std::move(pw.buffer());
  r.scan_ws.remember = !mode2;  // the take's windows in order, each coded once here
  std::vector<uint8_t> geo;
  const std::vector<uint8_t> body =
      scan_body(g, hints, mode2, e, corrections, &r.scan_ws, coded, &geo);
  r.scan_ws.remember = false;
  // The coder's rings for its payload; a payload coded before (--point-order any's, whose
  // choice coded others after it) is decoded again for them.
  if (rings && r.scan_ws.ring_payload == geo)
    rings->swap(r.scan_ws.rings);
  else if (rings)
    *rings = decode_scan_geometry(geo.data(), geo.size(), "SCNW", n, nullptr, true).ring;
  payload.insert(payload.end(), body.begin(), body.end());
  // A raster window at a bound codes integers of its own (a finer grid): the decoder's, which the
  // fields' predictors take (without fields they are not used). The coder hands them out with
  // the payload it chose; a payload coded before (--point-order any's) is decoded again.
  r.fine = mode2 ? 0 : scan_fine_shift(body.data(), body.size(), "SCNW");
  if (r.fine != 0 && !r.meta.attributes.empty()) {
    if (!r.scan_ws.fine_q.empty() && r.scan_ws.fine_payload == body)
      g.q.swap(r.scan_ws.fine_q);
    else
      g.q = decode_scan_geometry(body.data(), body.size(), "SCNW", n).q;
  }
  const size_t before = r.buf.size();
  append_chunk(&r.buf, "SCNW", payload);
  r.position_bytes += r.buf.size() - before;
  q->swap(g.q);
}

// "Scans (format 1.1)": the ATTR chunk of window w, its fields as one frame of its n points
// (width n), the SCNW integers q offered to predictors 10 and 11 and the positions the decoder
// will have to predictor 12 (0 at gaps): lossless, the source's (b.xyz; every valid coordinate
// decodes bit for bit, whether the window is split or not), else q's by the grid. The bounded
// float fields of META's layout (FORMAT.md 16.4) are quantised where that codes them smaller
// (encode_attributes_within), with `bounded`; *fields then holds what the decoder gives back.
void append_fields_chunk(RaggedRun& r, size_t w, std::vector<std::vector<uint8_t>>* fields,
                         bool bounded, const FrameBlock& b, const std::vector<int32_t>& q,
                         const std::vector<uint16_t>& rings) {
  const std::vector<uint8_t>& valid = b.valid;
  const size_t n = valid.size();
  std::vector<double> xyz(3 * n, 0.0);
  const double fine = std::ldexp(1.0, -r.fine);  // as the decoder's (FORMAT.md "Raster frames")
  with_mode(r.grid.mode, [&](auto m) {
    for (size_t i = 0; i < n; ++i)
      if (valid[i])
        for (size_t a = 0; a < 3; ++a)
          xyz[3 * i + a] = r.grid.lossless
                               ? b.xyz[3 * i + a]
                               : dequantise_as<decltype(m)::value>(r.grid, q[3 * i + a], 0) * fine;
  });
  RaggedFields ragged;
  ragged.trials = &r.trials;
  ragged.xyz = xyz.data();
  ragged.ring = rings.size() == n ? rings.data() : nullptr;
  if (q.size() == 3 * n && n > 0 && b.frame_offsets.size() > 1 && b.frame_offsets.back() == n) {
    ragged.q = q.data();
    ragged.frame_offsets = b.frame_offsets.data();
    ragged.frames = b.frame_offsets.size() - 1;
  }
  ByteWriter aw;
  aw.varint(w);
  std::vector<uint8_t> payload = std::move(aw.buffer());
  const std::vector<uint8_t> at = encode_attributes_within(
      attribute_specs(r.meta.pcd->fields),
      bounded ? attribute_bounds(*r.meta.pcd) : std::vector<double>(), fields, valid.data(), 1, n,
      n, q.empty() ? nullptr : q.data(), true, &ragged, true);
  payload.insert(payload.end(), at.begin(), at.end());
  const size_t before = r.buf.size();
  append_chunk(&r.buf, "ATTR", payload);
  r.attribute_bytes += r.buf.size() - before;
}

// Window w's SCNW and, with fields, ATTR appended to r.buf from block b (its fields taken into
// *fields, the bounded float ones of META's layout as the decoder gives them back, FORMAT.md
// 16.4); *q: the SCNW integers; coded: as append_scan_chunk's.
void code_chunks(RaggedRun& r, size_t w, FrameBlock* b, std::vector<int32_t>* q,
                 std::vector<std::vector<uint8_t>>* fields, const std::vector<uint8_t>* coded) {
  std::vector<uint16_t> rings;  // with a field predictor 13 may code (a key field)
  append_scan_chunk(r, w, *b, q, coded, r.key_fields ? &rings : nullptr);
  if (r.meta.attributes.empty()) return;
  *fields = std::move(b->attributes);
  append_fields_chunk(r, w, fields, true, *b, *q, rings);
}

// "Raw windows": window w's SCNW as a raw window of block b (its points as read), appended to
// r.buf, and ATTR of *fields (as read with `bounded`, then as code_chunks leaves them; else as
// they are); *q: the integers ATTR's predictors see.
void code_raw_chunks(RaggedRun& r, size_t w, const FrameBlock& b, std::vector<int32_t>* q,
                     std::vector<std::vector<uint8_t>>* fields, bool bounded) {
  const size_t before = r.buf.size();
  append_chunk(&r.buf, "SCNW", raw_scan_payload(w, b, r.grid.mode, r.t.source));
  r.position_bytes += r.buf.size() - before;
  r.fine = 0;
  *q = r.meta.attributes.empty() ? std::vector<int32_t>() : raw_scan_ints(b, r.grid.mode);
  if (!r.meta.attributes.empty()) append_fields_chunk(r, w, fields, bounded, b, *q, {});
}

// The position and field bytes counted before a window's chunks, and the fields' trial rests
// its codings start from.
struct WindowBytes {
  size_t position, attribute;
  FieldTrials trials;
};

// Window w's chunks in r.buf (the byte counts and trial rests from `at` on) replaced by those
// `code` appends to an empty r.buf when they are smaller: true, the caller then takes what `code`
// made; else false, r.buf, the counts and the rests as they were.
template <class Code>
bool replaced_if_smaller(RaggedRun& r, const WindowBytes& at, Code code) {
  std::vector<uint8_t> first;
  first.swap(r.buf);
  WindowBytes first_at{r.position_bytes, r.attribute_bytes, at.trials};
  std::swap(first_at.trials, r.trials);
  r.position_bytes = at.position, r.attribute_bytes = at.attribute;
  code();
  if (r.buf.size() < first.size()) return true;
  r.buf.swap(first);
  r.position_bytes = first_at.position, r.attribute_bytes = first_at.attribute;
  std::swap(r.trials, first_at.trials);
  return false;
}

// Window w's chunks in r.buf (of block *b, *q and *fields as code_chunks gave them; the byte
// counts from `at` on) replaced by those of block `other` (its geometry payload `coded`) when
// they are smaller, *b, *q and *fields with them.
void keep_smaller(RaggedRun& r, size_t w, const WindowBytes& at, FrameBlock* other,
                  const std::vector<uint8_t>& coded, FrameBlock* b, std::vector<int32_t>* q,
                  std::vector<std::vector<uint8_t>>* fields) {
  std::vector<int32_t> q2;
  std::vector<std::vector<uint8_t>> fields2;
  if (!replaced_if_smaller(r, at, [&] { code_chunks(r, w, other, &q2, &fields2, &coded); })) return;
  *b = std::move(*other);
  q->swap(q2);
  fields->swap(fields2);
}

// "Raw windows", mode 2: window w's chunks in r.buf (of block b as read, *q and *fields as
// code_chunks gave them; the byte counts from `at` on) replaced by a raw window's when the
// estimate lets it be tried (raw_may_win) and it is smaller.
void keep_raw_if_smaller(RaggedRun& r, size_t w, const WindowBytes& at, const FrameBlock& b,
                         std::vector<int32_t>* q, std::vector<std::vector<uint8_t>>* fields) {
  if (r.grid.mode != PosMode::kFloat32 || !raw_may_win(b, r.position_bytes - at.position)) return;
  std::vector<int32_t> q2;
  if (!replaced_if_smaller(r, at, [&] { code_raw_chunks(r, w, b, &q2, fields, false); })) return;
  q->swap(q2);
  if (--r.splits[r.last_split] == 0) r.splits.erase(r.last_split);  // counted as split before
  ++r.splits[scan::kRawWindowKey];
}

// Whether the offered octree window (point_order.h) may be smaller with its fields than the
// window now in r.buf (its byte counts from `at` on): when its geometry saves at least a tenth
// of that window's field bytes. In the cells' Morton order the fields grew by 15 to 56 % (1 cm:
// an E1 sweep +15 %, the E1 folder +18 %, the Helios +27 %, vlp16 +56 %), so a smaller saving
// is not worth coding them again (docs/lab/2026-11-30-octree-fields.md).
bool octree_may_win(const RaggedRun& r, const WindowBytes& at, const OctreeOffer& offer) {
  const size_t geometry = r.position_bytes - at.position;
  const size_t saving = geometry - std::min(geometry, offer.coded.size());
  return !offer.coded.empty() && 10 * saving >= r.attribute_bytes - at.attribute;
}

// FORMAT.md "Origin points": when block b has points at exactly +0.0 +0.0 +0.0 (bit patterns)
// and no gap, those points become its gaps (true returned), else b is left as it is.
bool origin_gaps(FrameBlock* b) {
  const auto origin = [&](size_t i) { return origin_point(&b->xyz[3 * i]); };
  bool any = false;
  for (size_t i = 0; i < b->valid.size(); ++i) {
    if (!b->valid[i]) return false;
    any = any || origin(i);
  }
  for (size_t i = 0; any && i < b->valid.size(); ++i)
    if (origin(i)) b->valid[i] = 0;
  return any;
}

// Whether each window is decoded after its coding: for the self-check (opts.check), whose
// decode also measures the report's error; without it the error is not measured (NaN), and a
// lossless take's is 0 by its rule.
bool decodes_windows(const RaggedRun& r) {
  return r.opts.check;
}

// Window w (the frames of b, as read; its fields are taken): its chunks written to r.out, after
// the one decoder has given them back for the check and the report's measures (decodes_windows).
void code_window(RaggedRun& r, size_t w, FrameBlock* b) {
  const Take& t = r.t;
  if (r.opts.drop_fields) keep_hint_fields(t.attributes, b);
  for (size_t a = 0; a < t.attributes.size() && !r.opts.drop_fields; ++a)
    if (a >= b->attributes.size() ||
        b->attributes[a].size() != b->total_points() * t.attributes[a].bytes_per_point())
      fail(ErrorCode::kInvalidParameter, t.source,
           "point field '" + t.attributes[a].name + "' does not hold a value for every point");
  // --point-order any: the window coded, checked and measured in its coded order. Its order is
  // chosen on the geometry's bytes; with fields, the file's order and octree frames (where their
  // geometry is smaller) are coded too, fields and all, and the smallest window kept: the fields
  // (timestamps, rings) may cost more in a sorted or Morton order than in a firing's.
  const bool raw = r.grid.mode == PosMode::kFloat64;  // "Raw windows": every window
  r.origin = !raw && origin_gaps(b);
  std::unique_ptr<FrameBlock> as_read;
  OctreeOffer offer;
  std::vector<uint8_t> coded, kept;  // the geometry payloads of the chosen and the file's order
  if (r.opts.any_point_order) {
    if (!r.meta.attributes.empty()) as_read.reset(new FrameBlock(*b));
    if (!reorder_window(b, r.grid, ring_field(t.attributes, *b), distance_field(t.attributes, *b),
                        &coded, as_read ? &kept : nullptr, &r.scan_ws, true,
                        as_read ? &offer : nullptr))
      as_read.reset();
  }
  const bool any = r.opts.any_point_order;
  const size_t base = r.out->size();
  r.buf.clear();
  std::vector<int32_t> q;
  std::vector<std::vector<uint8_t>> fields;
  const WindowBytes at{r.position_bytes, r.attribute_bytes, r.trials};
  if (raw) {
    fields = std::move(b->attributes);
    code_raw_chunks(r, w, *b, &q, &fields, true);
    ++r.splits[scan::kRawWindowKey];
  } else {
    code_chunks(r, w, b, &q, &fields, any ? &coded : nullptr);
  }
  if (as_read) keep_smaller(r, w, at, as_read.get(), kept, b, &q, &fields);
  if (octree_may_win(r, at, offer))
    keep_smaller(r, w, at, &offer.block, offer.coded, b, &q, &fields);
  if (r.origin) origin_points(b);  // b as read again
  if (!raw) keep_raw_if_smaller(r, w, at, *b, &q, &fields);
  // The self-check (beside the next window's coding, it takes b and the fields).
  if (decodes_windows(r)) r.checks->check(w, r.buf.data(), r.buf.size(), base, b, &fields);
  if (r.residue) {  // last in the window, rebuilt from the self-check's decode (in place)
    b->attributes = std::move(fields);
    r.residue->window_chunk(w, *b, decodes_windows(r) ? &r.checks->decoded() : nullptr, &r.buf);
  }
  r.index.push_back(IndexEntry{base, r.buf.size()});
  r.out->flush(&r.buf);
  if (decodes_windows(r)) r.checks->release();
}

void fill_stats(const RaggedRun& r, size_t total, CompressStats* stats) {
  const size_t bytes = r.out->size();
  *stats = CompressStats();
  stats->bytes = bytes;
  stats->raw_bytes = total * 12;
  stats->bpvf = total ? 8.0 * static_cast<double>(bytes) / static_cast<double>(total) : 0;
  stats->step = r.grid.step;
  stats->lossless = r.grid.lossless;
  stats->float32_split_windows = r.splits;
  stats->mode = scan::has_split_windows(r.splits) ? "float32-split" : mode_name(r.grid.mode);
  stats->error = r.acc.finish();
  if (!decodes_windows(r) && !r.grid.lossless) {  // not measured
    const double nan = std::numeric_limits<double>::quiet_NaN();
    stats->error.max_abs = stats->error.max_error = stats->error.rmse = nan;
    stats->error.kg_error = stats->error.psnr = nan;
  }
  stats->codec = "none";
  for (const auto& kv : r.opts.analog_max_error)  // frames of their own counts hold no analog
    stats->analog_unmatched.push_back(kv.first);
  stats->position_bytes = r.position_bytes;
  stats->attribute_bytes = r.attribute_bytes;
  stats->other_bytes = bytes - r.position_bytes - r.attribute_bytes;
}

// encode_ragged's checks of its source's header.
void check_ragged_header(const Take& t, const CompressOptions& opts, bool organized) {
  if (t.points != 0 || !t.labels.empty())  // take.h: a ragged take has neither
    fail(ErrorCode::kInvalidParameter, t.source,
         "a ragged take has no per-point labels or shared point count (points " +
             std::to_string(t.points) + ", " + std::to_string(t.labels.size()) + " labels)");
  refuse_unsupported(t, opts);
  if (organized && opts.any_point_order)  // FORMAT.md: not in such a stream
    fail(ErrorCode::kInvalidParameter, t.source,
         "frames of one organized shape are coded in their order");
}

// The stream's HEAD of a ragged take on `grid`, in windows of W frames (window_frames).
StreamHeader ragged_header(const Take& t, const CompressOptions& opts, const Grid& grid,
                           uint32_t W) {
  StreamHeader h;
  h.frames = t.frames;
  h.window_frames = W;
  h.source_format = t.format;  // PLY and .bin: HEAD's frame-file source (feature bit 4)
  h.bin_record_declared = declares_bin_record(t, opts.drop_fields);
  h.mode = grid.mode;
  h.step = grid.step;
  h.max_error = grid.lossless ? 0 : opts.max_error;
  h.lossless = grid.lossless;
  h.ragged = true;
  h.points_reordered = opts.any_point_order;
  h.octree_frames = opts.any_point_order;  // point_order_encode.cpp may code octree frames
  return h;
}

}  // namespace

void encode_ragged(FrameSource& src, const CompressOptions& opts, StreamOut* out,
                   CompressStats* stats, const std::string& original, bool organized) {
  const Take& t = src.header();
  check_ragged_header(t, opts, organized);
  FrameBlock block;  // window 0 after pass 1; then each window as read
  const uint32_t W = window_frames(t, opts);
  const Grid grid = choose_grid(src, opts, W, &block);
  const Take meta_take = meta_take_of(t, opts, organized);
  const StreamHeader h = ragged_header(t, opts, grid, W);
  std::vector<uint8_t> head_buf;
  write_file_header(&head_buf, kFormatScans.minor);
  const std::vector<uint8_t> head = encode_header(h), meta = encode_meta(meta_take, false);
  append_chunk(&head_buf, "HEAD", head);
  append_chunk(&head_buf, "META", meta);
  const size_t meta_at = head_buf.size() - meta.size() - kChunkOverhead;
  StreamFeatures features;
  features.minor = kFormatScans.minor;
  const StreamContext ctx = read_context(
      h, read_chunk(head_buf.data(), head_buf.size(), meta_at, t.source), features, t.source);
  // "Lossless ragged streams": HASH and PCDR of the frame files, a PCDP per window, against the
  // take as META gives it back (the decoder's header).
  std::unique_ptr<ResidueWriter> residue;
  if (grid.lossless && !original.empty())
    residue = ResidueWriter::open(original, ctx.take, opts.check);
  if (residue) residue->file_chunks(&head_buf, true);
  out->flush(&head_buf);
  RaggedRun r(t, opts, grid, ctx, meta_take, out, residue.get());
  if (!meta_take.attributes.empty()) {
    const std::vector<AttrSpec> specs = attribute_specs(meta_take.pcd->fields);
    r.key_fields = std::any_of(specs.begin(), specs.end(), attr::is_key_field);
  }
  // With threads, each window's self-check runs beside the next window's coding (not with a
  // residue, which is written from the check's decode; nor for one window).
  const bool beside =
      decodes_windows(r) && !residue && resolve_threads(opts.threads) > 1 && t.frames > W;
  WindowChecks checks(t, ctx, opts.max_error, grid.lossless, beside, &r.acc);
  r.checks = &checks;
  for (size_t w = 0; w * W < t.frames; ++w) {
    const size_t f0 = w * W, f1 = std::min<size_t>(f0 + W, t.frames);
    if (w > 0) src.read(f0, f1 - f0, &block);  // window 0: still there from pass 1
    code_window(r, w, &block);
    if (opts.progress) opts.progress(f1, t.frames);
  }
  checks.finish();
  if (residue) residue->finish();
  std::vector<uint8_t> tail;
  append_chunk(&tail, "INDX", encode_index(r.index));
  out->flush(&tail);
  if (stats) fill_stats(r, t.total_points(), stats);
}

namespace {

// compress_ragged's checks of its take.
void check_ragged(const Take& t, const CompressOptions& opts) {
  const size_t total = t.total_points();
  if (t.frame_offsets.size() != t.frames + 1 || t.xyz.size() != total * 3 ||
      t.valid.size() != total)
    fail(ErrorCode::kInvalidParameter, t.source, "ragged take arrays do not match its offsets");
  if (t.points != 0 || !t.labels.empty())  // take.h: a ragged take has neither
    fail(ErrorCode::kInvalidParameter, t.source,
         "a ragged take has no per-point labels or shared point count (points " +
             std::to_string(t.points) + ", " + std::to_string(t.labels.size()) + " labels)");
  for (const PointAttribute& a : t.attributes)
    if (a.data.size() != total * a.bytes_per_point() && !opts.drop_fields)
      fail(ErrorCode::kInvalidParameter, t.source,
           "point field '" + a.name + "' does not hold a value for every point");
  refuse_unsupported(t, opts);
}

std::vector<uint8_t> encode_source_ragged(FrameSource& src, const CompressOptions& opts,
                                          CompressStats* stats, const std::string& original,
                                          bool organized) {
  std::vector<uint8_t> bytes;
  StreamOut out(&bytes);
  encode_ragged(src, opts, &out, stats, original, organized);
  return bytes;
}

}  // namespace

std::vector<uint8_t> compress_ragged(const Take& t, const CompressOptions& opts,
                                     CompressStats* stats, const std::string& original,
                                     bool organized) {
  check_ragged(t, opts);
  return encode_source_ragged(*take_frames(t), opts, stats, original, organized);
}

std::vector<uint8_t> compress_ragged(Take&& t, const CompressOptions& opts, CompressStats* stats,
                                     const std::string& original, bool organized) {
  check_ragged(t, opts);
  return encode_source_ragged(*handing_take_frames(std::move(t)), opts, stats, original, organized);
}

}  // namespace capz
