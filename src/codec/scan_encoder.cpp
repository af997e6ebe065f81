// The encoder of ragged takes (scan_encoder.h).
#include "codec/scan_encoder.h"

#include <algorithm>
#include <cmath>
#include <string>

#include "capz/error.h"
#include "capz/metrics.h"
#include "codec/decoder.h"
#include "codec/grid.h"
#include "codec/grid_choice.h"
#include "codec/stream_reader.h"
#include "coding/bytes.h"
#include "coding/container.h"
#include "coding/meta.h"
#include "coding/scan_geometry.h"

namespace capz {
namespace {

// What format 1.1 does not code yet for frames of their own size: refused, never dropped.
void refuse_unsupported(const Take& t, const CompressOptions& opts) {
  const std::string what = "frames of their own point counts (a ragged take, format 1.1)";
  if (opts.lossless)
    fail(ErrorCode::kInvalidParameter, t.source,
         "--lossless is not implemented for " + what +
             ": the byte-exact rebuild of their frame files (a residue of ragged frames) is "
             "missing; give --max-error");
  if (!(opts.max_error > 0))
    fail(ErrorCode::kInvalidParameter, t.source,
         "only --max-error is implemented for " + what + " (no KG target)");
  if (!t.attributes.empty() && !opts.drop_fields)
    fail(ErrorCode::kInvalidParameter, t.source,
         "point fields of " + what +
             " are not coded yet (ATTR of a ragged window is missing): --drop-fields keeps "
             "x y z only");
  const bool frames = t.format == Format::kPCDFolder || t.format == Format::kPLYFolder ||
                      t.format == Format::kBinFolder;
  if (!frames || t.analog.channels > 0 || t.rotations.segments > 0)
    fail(ErrorCode::kInvalidParameter, t.source,
         "only PCD, PLY and .bin frames are coded as " + what + " yet: convert them first");
}

// The ring / laser / channel number of every point from an unsigned or signed integer field of
// that name, or empty.
std::vector<uint32_t> ring_field(const Take& t) {
  for (const PointAttribute& a : t.attributes) {
    if (a.count != 1 || a.type == 'F' || a.size > 4) continue;
    if (a.name != "ring" && a.name != "channel" && a.name != "laser_id" && a.name != "laser")
      continue;
    const size_t n = t.total_points(), sz = static_cast<size_t>(a.size);
    if (a.data.size() != n * sz) return {};
    std::vector<uint32_t> r(n);
    for (size_t i = 0; i < n; ++i) {
      uint32_t v = 0;
      for (size_t k = 0; k < sz; ++k) v |= static_cast<uint32_t>(a.data[i * sz + k]) << (8 * k);
      r[i] = v;
    }
    return r;
  }
  return {};
}

// Frames per window: about 2^20 points in a window, 1 .. 8192 frames.
uint32_t window_frames(const Take& t, const CompressOptions& opts) {
  if (opts.window_frames > 0)
    return static_cast<uint32_t>(std::min<size_t>(opts.window_frames, kMaxWindowFrames));
  size_t most = 1;
  for (size_t f = 0; f < t.frames; ++f) most = std::max(most, t.frame_points(f));
  return static_cast<uint32_t>(std::clamp<size_t>((size_t{1} << 20) / most, 1, kMaxWindowFrames));
}

// Whether a PCD writer stores the take's x y z as float32 (no layout: x y z F 4).
bool float32_xyz(const Take& t) {
  if (!t.pcd || t.pcd->fields.empty()) return true;
  for (const PCDField& f : t.pcd->fields)
    if (f.name == "x") return f.size == 4;
  return true;
}

// The grid whose step bounds every coordinate by opts.max_error, after float32 rounding when
// the frames are written back as float32.
Grid choose_grid(const Take& t, const CompressOptions& opts) {
  Take hdr;  // what the grid choice reads of the take, x y z's layout spelled out
  hdr.source = t.source;
  hdr.format = t.format;
  hdr.units = t.units;
  hdr.pcd = std::make_shared<PCDExtra>();
  const PCDField x32{"x", 'F', 4, 1};
  if (float32_xyz(t)) hdr.pcd->fields = {x32};
  TakeScan s = start_scan(hdr, opts);
  s.ray_track = false;  // a per-point track: not for frames of their own size
  FrameBlock b;
  b.frames = 1;
  b.points = t.total_points();
  b.xyz = t.xyz;
  b.valid = t.valid;
  scan_block(b, t.source, false, 0, &s);
  Grid g = bounded_grid(hdr, s, opts.max_error);
  if (g.mode == PosMode::kDecimal || g.mode == PosMode::kFloat64)
    fail(ErrorCode::kInvalidParameter, t.source,
         std::string("no grid for frames of their own size in mode ") + mode_name(g.mode));
  return g;
}

// Throws kInternal unless the decoded window has the source's counts, gaps and every valid
// coordinate within the bound, also as the float32 a PCD writer stores.
void check_window(const Take& t, size_t p0, size_t f0, const FrameBlock& d, double bound) {
  const bool f32 = float32_xyz(t);
  const size_t fn = d.frame_offsets.size() - 1;
  for (size_t f = 0; f < fn; ++f)
    if (d.frame_offsets[f + 1] - d.frame_offsets[f] != t.frame_points(f0 + f))
      fail(ErrorCode::kInternal, t.source, "self-check: frame counts differ");
  for (size_t i = 0; i < d.valid.size(); ++i) {
    if (d.valid[i] != t.valid[p0 + i])
      fail(ErrorCode::kInternal, t.source, "self-check: gaps differ");
    if (!d.valid[i]) continue;
    for (size_t a = 0; a < 3; ++a) {
      const double x = t.xyz[3 * (p0 + i) + a], y = d.xyz[3 * i + a];
      const double y32 = f32 ? static_cast<double>(static_cast<float>(y)) : y;
      if (!(std::fabs(y - x) <= bound && std::fabs(y32 - x) <= bound))
        fail(ErrorCode::kInternal, t.source,
             "self-check: coordinate " + std::to_string(x) + " comes back as " + std::to_string(y) +
                 ", off by more than " + std::to_string(bound));
    }
  }
}

}  // namespace

std::vector<uint8_t> compress_ragged(const Take& t, const CompressOptions& opts,
                                     CompressStats* stats) {
  const size_t total = t.total_points();
  if (t.frame_offsets.size() != t.frames + 1 || t.xyz.size() != total * 3 ||
      t.valid.size() != total)
    fail(ErrorCode::kInvalidParameter, t.source, "ragged take arrays do not match its offsets");
  refuse_unsupported(t, opts);
  const Grid grid = choose_grid(t, opts);
  Take meta_take = t;  // META without the dropped fields; positions live in SCNW
  meta_take.attributes.clear();
  meta_take.xyz.clear();
  meta_take.valid.clear();
  if (meta_take.pcd) {
    auto x = std::make_shared<PCDExtra>(*meta_take.pcd);
    x->fields.erase(std::remove_if(x->fields.begin(), x->fields.end(),
                                   [](const PCDField& f) {
                                     return f.name != "x" && f.name != "y" && f.name != "z";
                                   }),
                    x->fields.end());
    meta_take.pcd = x;
  }
  StreamHeader h;
  h.frames = t.frames;
  h.window_frames = window_frames(t, opts);
  h.source_format = t.format;  // PLY and .bin: HEAD's frame-file source (feature bit 4)
  h.mode = grid.mode;
  h.step = grid.step;
  h.max_error = opts.max_error;
  h.ragged = true;
  std::vector<uint8_t> out;
  write_file_header(&out, kFormatScans.minor);
  const std::vector<uint8_t> head = encode_header(h), meta = encode_meta(meta_take, false);
  append_chunk(&out, "HEAD", head);
  append_chunk(&out, "META", meta);
  const size_t meta_at = out.size() - meta.size() - kChunkOverhead;
  StreamFeatures features;
  features.minor = kFormatScans.minor;
  StreamContext ctx =
      read_context(h, read_chunk(out.data(), out.size(), meta_at, t.source), features, t.source);
  const std::vector<uint32_t> ring = ring_field(t);
  std::vector<IndexEntry> index;
  size_t position_bytes = 0;
  ErrorAccumulator acc;
  for (size_t w = 0; w * h.window_frames < t.frames; ++w) {
    const size_t f0 = w * h.window_frames, f1 = std::min<size_t>(f0 + h.window_frames, t.frames);
    const size_t p0 = t.frame_begin(f0), p1 = t.frame_begin(f1);
    FrameBlock b;
    b.frames = 1;
    b.points = p1 - p0;
    b.xyz.assign(t.xyz.begin() + static_cast<std::ptrdiff_t>(3 * p0),
                 t.xyz.begin() + static_cast<std::ptrdiff_t>(3 * p1));
    b.valid.assign(t.valid.begin() + static_cast<std::ptrdiff_t>(p0),
                   t.valid.begin() + static_cast<std::ptrdiff_t>(p1));
    const WindowInts wi = quantise_window(b, grid);
    ScanGeometry g;
    for (size_t f = f0; f < f1; ++f) g.counts.push_back(static_cast<uint32_t>(t.frame_points(f)));
    g.q = wi.q;
    g.valid = b.valid;
    ScanHints hints;
    if (!ring.empty())
      hints.ring.assign(ring.begin() + static_cast<std::ptrdiff_t>(p0),
                        ring.begin() + static_cast<std::ptrdiff_t>(p1));
    hints.xyz.resize(b.xyz.size());
    for (size_t i = 0; i < b.xyz.size(); ++i) hints.xyz[i] = static_cast<float>(b.xyz[i]);
    ByteWriter pw;
    pw.varint(w);
    pw.varint(p1 - p0);
    std::vector<uint8_t> payload = std::move(pw.buffer());
    const std::vector<uint8_t> geo = encode_scan_geometry(g, hints);
    payload.insert(payload.end(), geo.begin(), geo.end());
    const size_t base = out.size();
    append_chunk(&out, "SCNW", payload);
    index.push_back(IndexEntry{base, out.size() - base});
    position_bytes += out.size() - base;
    if (opts.check || stats) {  // the one decoder gives the window back
      FrameBlock d;
      decode_window_chunks(ctx, w, out.data() + base, base, out.size(), &d);
      if (opts.check) check_window(t, p0, f0, d, opts.max_error);
      acc.add_ragged(f1 - f0, d.frame_offsets.data(), t.xyz.data() + 3 * p0, d.xyz.data(),
                     t.valid.data() + p0);
    }
    if (opts.progress) opts.progress(f1, t.frames);
  }
  append_chunk(&out, "INDX", encode_index(index));
  if (stats) {
    *stats = CompressStats();
    stats->bytes = out.size();
    stats->raw_bytes = total * 12;
    stats->bpvf = total ? 8.0 * static_cast<double>(out.size()) / static_cast<double>(total) : 0;
    stats->step = grid.step;
    stats->mode = mode_name(grid.mode);
    stats->error = acc.finish();
    stats->codec = "none";
    stats->position_bytes = position_bytes;
    stats->other_bytes = out.size() - position_bytes;
  }
  return out;
}

}  // namespace capz
