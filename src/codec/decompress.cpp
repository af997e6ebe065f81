// decompress(), decompress_frames() and describe() (capz/codec.h): a .capz in memory back to a
// Take, through the frame source and the one decoder. Part of the decoder library.
#include <algorithm>
#include <cstddef>
#include <limits>
#include <memory>
#include <string>

#include "capz/codec.h"
#include "capz/error.h"
#include "codec/capz_source.h"
#include "codec/decoder.h"
#include "codec/decoder_registry.h"
#include "codec/grid.h"
#include "coding/analog/analog_codec.h"
#include "coding/scan_raw.h"
#include "coding/scan_split.h"

namespace capz {

static_assert(scan::kNoSplit == kPlainFloat32WindowsKey,
              "plain float32 windows' key in the reports");

namespace {

// Frames [first, first + count) of the stream, clipped, with the per-frame metadata sliced.
Take decode_range(const uint8_t* data, size_t size, size_t first, size_t count,
                  const std::string& name, const DecompressOptions& opts) {
  std::unique_ptr<StreamBytes> mem(new MemoryBytes(data, size));
  CapzSource src(std::move(mem), name, false, opts.threads, opts.memory_limit);
  const ParsedStream& ps = src.parsed();
  const size_t F = ps.take.frames;
  first = std::min(first, F);
  count = std::min(count, F - first);
  if (first == 0 && count == F) check_tiling(ps, size, name);
  if (opts.progress) {
    // By value: the source calls it from read() below, after this block's locals are gone.
    const size_t W = ps.h.window_frames, end = first + count;
    src.after_window([W, end, first, count, &opts](size_t w) {
      opts.progress(std::min((w + 1) * W, end) - first, count);
    });
  }
  FrameBlock b;
  src.read(first, count, &b);
  Take t = src.header();  // a stream of one ragged frame: one fixed frame (capz_source.h)
  t.frames = count;
  t.xyz = std::move(b.xyz);
  t.valid = std::move(b.valid);
  t.frame_offsets = std::move(b.frame_offsets);  // a ragged take's; empty for a fixed one
  t.analog.values = std::move(b.analog);
  t.rotations.matrices = std::move(b.rotation_matrices);
  t.rotations.reliability = std::move(b.rotation_reliability);
  for (size_t a = 0; a < t.attributes.size() && a < b.attributes.size(); ++a)
    t.attributes[a].data = std::move(b.attributes[a]);
  if (ps.words) {
    t.c3d = std::make_shared<C3DExtra>(*ps.take.c3d);
    t.c3d->residual = std::move(b.residual);
    t.c3d->camera_mask = std::move(b.camera_mask);
  }
  if (first > 0 || count < F) slice_frame_metadata(first, count, F, &t);
  return t;
}

}  // namespace

uint64_t effective_memory_limit(uint64_t memory_limit, uint64_t archive_bytes) {
  if (memory_limit != kAutoMemoryLimit) return memory_limit;
  const uint64_t per_byte = archive_bytes > kAutoMemoryLimit / kMemoryPerArchiveByte
                                ? kAutoMemoryLimit - 1
                                : archive_bytes * kMemoryPerArchiveByte;
  return std::max(kDefaultMemoryLimit, per_byte);
}

Take decompress(const uint8_t* data, size_t size, const std::string& name,
                const DecompressOptions& opts) {
  return decode_range(data, size, 0, std::numeric_limits<size_t>::max(), name, opts);
}

Take decompress_frames(const uint8_t* data, size_t size, size_t first, size_t count,
                       const std::string& name, const DecompressOptions& opts) {
  return decode_range(data, size, first, count, name, opts);
}

bool is_capz(const uint8_t* data, size_t size) {
  return size >= 9 &&
         (std::memcmp(data, kCapzMagic, 9) == 0 || std::memcmp(data, kPrereleaseMagic, 9) == 0);
}

namespace {

// describe() of the bytes in memory or in a file (read a chunk at a time).
StreamInfo describe_bytes(StreamBytes& bytes, const std::string& name) {
  ParsedStream ps = parse_stream(bytes, name);
  StreamInfo si;
  si.major = kCapzMajor;
  si.minor = ps.features.minor;
  si.source_format = ps.h.source_format;
  si.source_name = ps.take.source;
  si.frames = ps.take.frames;
  si.points = ps.take.points;
  si.ragged = ps.h.ragged;
  si.points_reordered = ps.h.points_reordered;
  ps.max_points = size_t{1} << 40;  // only the counts are read: no limit on a window's points
  std::vector<int> splits;
  si.total_points =
      si.ragged ? ragged_frame_offsets(bytes, ps, &splits).back() : si.frames * si.points;
  if (ps.h.mode == PosMode::kFloat32 || ps.h.mode == PosMode::kFloat64)  // with raw windows
    for (int e : splits) ++si.float32_split_windows[e];  // SCNW's E, or kRawWindowKey
  si.window_frames = ps.h.window_frames;
  si.windows = ps.h.windows();
  si.mode = ps.h.transform_output ? "transform-output" : mode_name(ps.h.mode);
  if (scan::has_split_windows(si.float32_split_windows))
    si.mode = "float32-split";  // as the encoder's CompressStats::mode says it
  si.transform_output = ps.h.transform_output;
  si.kg_target = ps.h.kg_target;
  if (ps.h.codec == 0) {
    si.codec = "none";
  } else {
    const TransformDecoder* c = find_decoder(ps.h.codec);
    si.codec = c ? c->name() : "id " + std::to_string(ps.h.codec);
  }
  si.lossless = ps.h.lossless;
  si.step = ps.h.mode == PosMode::kDecimal ? 1.0 / ps.h.step : ps.h.step;
  si.max_error = ps.h.max_error;
  si.rate = ps.take.rate;
  si.units = ps.take.units;
  si.analog_channels = ps.take.analog.channels;
  si.analog_samples_per_frame = ps.take.analog.samples_per_frame;
  si.rotation_segments = ps.take.rotations.segments;
  si.rotation_samples_per_frame = ps.take.rotations.samples_per_frame;
  si.rotation_rate = ps.take.rotations.rate;
  si.rotation_labels = ps.take.rotations.labels;
  if (ps.take.pcd) {
    si.pcd_fields = ps.take.pcd->fields;
    si.pcd_field_bounds = ps.take.pcd->field_bounds;
    si.pcd_width = ps.take.pcd->width;
    si.pcd_height = ps.take.pcd->height;
  }
  if (ragged_reads_fixed(ps)) {  // read as the fixed take (capz_source.h)
    si.ragged = false;
    si.points = organized_points(ps) ? organized_points(ps) : si.total_points;
    if (ps.take.pcd && !organized_points(ps)) si.pcd_width = si.total_points, si.pcd_height = 1;
  }
  if (ps.take.analog.lossy()) {  // FORMAT.md 5.7
    si.analog_bounds = ps.take.analog.bounds;
    si.analog_factors = ps.take.analog.factors;
    si.analog_labels = ps.take.analog.labels;
    si.analog_labels.resize(si.analog_bounds.size());
    for (const AnalogPhysics& p : analog_physics(ps.take)) si.analog_units.push_back(p.unit);
  }
  si.chunk_bytes = ps.chunk_bytes;
  for (size_t off = ps.first_window_offset; off < ps.index_offset;) {  // the window chunks
    Chunk k = chunk_at(bytes, off, name);
    si.chunk_bytes[k.type] += k.end - k.offset;
    off = k.end;
  }
  return si;
}

}  // namespace

StreamInfo describe(const uint8_t* data, size_t size, const std::string& name) {
  MemoryBytes bytes(data, size);
  return describe_bytes(bytes, name);
}

StreamInfo describe_file(const std::string& path) {
  FileBytes bytes(path);
  return describe_bytes(bytes, path);
}

}  // namespace capz
