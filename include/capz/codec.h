// capz — compression API: a Take to .capz bytes and back (docs/FORMAT.md describes the bytes).
#pragma once

#include <cstddef>
#include <cstdint>
#include <functional>
#include <map>
#include <string>
#include <vector>

#include "capz/metrics.h"
#include "capz/take.h"

namespace capz {

struct CompressOptions {
  // Exactly one target applies, in this order: lossless, kg_error (> 0), max_error (> 0).
  bool lossless = false;
  double kg_error = 0;   // KG error target in percent (metrics.h): the grid step is searched so
                         // the achieved KG error is at or just under it; with a transform codec
                         // the transform's reconstruction is the output instead and the
                         // transform meets the target (no per-coordinate bound then)
  double max_error = 0;  // per-coordinate bound, in the take's own units
  std::string codec;     // "" or "none": temporal prediction only; a transform ("ts", ...);
                         // "auto": each of them on the whole take, the smallest kept
  int clusters = 0;      // passed to the transform codec (0 = its default)
  std::map<std::string, std::string> codec_options;  // the CLI's --codec-opt key=value
  // Frames per independently decodable window, 1 .. 8192; 0: auto_window_frames(points). Fewer
  // when the take has more than kMaxWindowAnalogValues analog values in that many frames.
  size_t window_frames = 0;
  bool check = true;  // decode every window after writing it and verify the bound / exactness
  // Worker threads coding windows in parallel (0: all cores). The stream's bytes, the stats and
  // any error thrown are the same for every count; at most threads + 1 windows are in memory.
  int threads = 1;
  // Leave the take's point fields (Take::attributes, PCD fields other than x y z) out of the
  // archive instead of coding them (they are lossless by default).
  bool drop_fields = false;
  // --point-order any: the archive may reorder the points of each frame of a take whose frames
  // have their own point counts (and of a single unorganized sweep), each point with its fields,
  // and codes them in the laser's firing order (docs/FORMAT.md "Points reordered"); gaps are
  // kept, after each frame's valid points. The decoded take has the coded order. Other takes
  // (frames whose points correspond) keep their order. Not with lossless (refused).
  bool any_point_order = false;
  // Bounds for float point fields (PCD), in each field's own units: a key names a field, or
  // every field NAME_* ("normal" bounds normal_x, normal_y, normal_z). Fields not named are
  // lossless. A key that names no float field is an error.
  std::map<std::string, double> attr_error;
  // Bounds for analog channels (docs/FORMAT.md 5.7), each in the channel's physical units
  // (ANALOG:UNITS, after ANALOG:SCALE, GEN_SCALE and OFFSET): a key names a channel's label
  // ("Fz1") or a unit ("N", "V"), the label's bound winning over its unit's. Channels not named
  // stay lossless. Keys that name no channel are reported in CompressStats::analog_unmatched.
  // Not with lossless (an error).
  std::map<std::string, double> analog_max_error;
  // Called after each window with (frames done, frames total); may be empty.
  std::function<void(size_t, size_t)> progress;
};

// The window size `window_frames = 0` stands for with codec none: 1024 frames, or for takes
// of few points as many more (a power of two, at most 8192) as make a window hold about 2^16
// samples, so a small take is not split into windows that each pay their own headers and
// context warm-up. With a transform codec it stands for 1024.
size_t auto_window_frames(size_t points);

// The keys of CompressStats / StreamInfo::float32_split_windows beside the float32 split
// exponents (-64..64): windows of plain float32 bits (docs/FORMAT.md "Lossless ragged streams",
// no split), and raw windows ("Raw windows": a lossless window's coordinates as their bits
// through LZMA2).
constexpr int kPlainFloat32WindowsKey = -128;
constexpr int kRawWindowsKey = -127;

struct CompressStats {
  size_t bytes = 0;      // size of the .capz stream
  size_t raw_bytes = 0;  // frames x points x 3 x 4: the positions as raw float32
  double bpvf = 0;       // 8 * bytes / (frames * points)
  double step = 0;       // grid step used (0 for float-bit lossless coding)
  std::string mode;      // "grid", "decimal-grid", "float32-bits", "float64-bits",
                         // "transform-output" (only a KG target and a transform)
  // A ragged stream in mode 2 or 3: its windows per float32 split exponent, as
  // StreamInfo::float32_split_windows counts them (kPlainFloat32WindowsKey:
  // plain float32 bits; kRawWindowsKey: raw windows). Else empty.
  std::map<int, size_t> float32_split_windows;
  std::string codec;  // transform stage used: "none", "ts", "pdct" (what auto chose)
  bool lossless = false;
  // Achieved, over valid samples (zero when lossless); NaN (samples 0) when not measured: a take
  // of ragged frames coded without the check (CompressOptions::check), whose measure is a decode.
  ErrorStats error;
  size_t position_bytes = 0;                  // bytes of POSW + MASK chunks
  size_t analog_bytes = 0;                    // bytes of ANLG chunks
  size_t rotation_bytes = 0;                  // bytes of ROTW chunks
  size_t attribute_bytes = 0;                 // bytes of ATTR chunks (point fields)
  size_t other_bytes = 0;                     // everything else
  std::vector<std::string> analog_unmatched;  // analog_max_error keys that named no channel
  // At a bound, from a C3D: samples marked absent (4th word negative) whose coordinates the file
  // holds but the archive does not keep, as for every gap (--lossless keeps them).
  size_t dropped_coordinates = 0;
};

// Throws Error(kInvalidParameter) for an impossible target (no target, bound too fine for the
// coordinate range, unknown codec), Error(kInternal) if the self-check fails.
std::vector<uint8_t> compress(const Take& take, const CompressOptions& opts,
                              CompressStats* stats = nullptr);

// The most analog values (frames x samples per frame x channels) the encoder puts in one window;
// a take with more per frame gets windows of fewer frames than asked (at least one).
constexpr size_t kMaxWindowAnalogValues = size_t{1} << 22;

// The decoder's memory limit (DecompressOptions::memory_limit) by default: the larger of 4 GiB
// and 1024 bytes for each byte of the archive, so that a small damaged or hostile file cannot
// ask for more than 4 GiB while a large archive (a long sequence of big point clouds) decodes
// with whatever its windows need.
constexpr uint64_t kDefaultMemoryLimit = uint64_t{4} << 30;
constexpr uint64_t kMemoryPerArchiveByte = 1024;
constexpr uint64_t kAutoMemoryLimit = ~uint64_t{0};
// The limit in bytes that `memory_limit` stands for with an archive of `archive_bytes` (0: none).
uint64_t effective_memory_limit(uint64_t memory_limit, uint64_t archive_bytes);

struct DecompressOptions {
  // Worker threads decoding windows in parallel (0: all cores); the result and any error thrown
  // are the same for every count. At most threads + 2 windows are decoded ahead in memory.
  int threads = 1;
  // Bytes of decoded samples the decoder may hold at once: the arrays decompress() returns, or
  // the windows a frame source keeps (the one read, and those decoded ahead). A stream whose
  // header asks for more is refused with Error(kMemoryLimit) before anything is allocated. A
  // valid stream can ask for a lot from few bytes (a constant analog channel of an hour codes
  // in a few bytes a window), so this bound, not the file's size, is what keeps a damaged or
  // hostile file from exhausting memory. kAutoMemoryLimit (the default): 4 GiB, or 1024 bytes
  // per archive byte when that is more; 0: no limit.
  uint64_t memory_limit = kAutoMemoryLimit;
  // Called after each window decoded with (frames decoded, frames asked for), in the calling
  // thread; may be empty. An exception it throws leaves decompress() (nothing is returned).
  std::function<void(size_t, size_t)> progress;
};

// Throws Error(kNotOurFormat / kUnsupportedVersion / kCorrupt) naming `name` and the chunk.
Take decompress(const uint8_t* data, size_t size, const std::string& name = "",
                const DecompressOptions& opts = {});
// Frames [first, first + count) only (clipped to the take); decodes only the windows they touch.
Take decompress_frames(const uint8_t* data, size_t size, size_t first, size_t count,
                       const std::string& name = "", const DecompressOptions& opts = {});

// What `capz info` prints about a .capz, read from HEAD, META and the chunk table.
struct StreamInfo {
  int major = 0, minor = 0;
  Format source_format = Format::kUnknown;
  std::string source_name;
  size_t frames = 0, points = 0, window_frames = 0, windows = 0;
  // Frames of their own point counts (format 1.1; points is then 0): the points of all frames.
  // A stream of one ragged frame is described as the fixed frame every reader gives it
  // (ragged false, points its count, an unorganized layout of that width).
  bool ragged = false;
  size_t total_points = 0;
  // Each frame's points are in the encoder's order, not the source's (compress
  // --point-order any; HEAD feature bit 5, format 1.1): compare them with the source as sets.
  bool points_reordered = false;
  std::string mode;  // as CompressStats::mode
  // A ragged stream in mode "float32-bits" (FORMAT.md "Lossless ragged streams"): how many of
  // its windows code their float32 coordinates on each float32 split grid 2^-E (the key E),
  // exactly, with corrections; kPlainFloat32WindowsKey: windows of plain float32 bits;
  // kRawWindowsKey: raw windows (also in mode "float64-bits", where every window is raw). Empty
  // otherwise.
  std::map<int, size_t> float32_split_windows;
  std::string codec;  // "none", "ts", "pdct", or "id N" when unknown
  bool lossless = false;
  // The transform's reconstruction is the output (only a KG target was given): no bound holds,
  // max_error is 0, and kg_target is the KG error target (percent) the encoder met.
  bool transform_output = false;
  double kg_target = 0;
  double step = 0, max_error = 0;
  double rate = 0;
  std::string units;
  int analog_channels = 0, analog_samples_per_frame = 0;
  // Rotations (Rotations in take.h): segments 0 when the take has none.
  int rotation_segments = 0, rotation_samples_per_frame = 0;
  double rotation_rate = 0;  // Hz, 0 unknown
  std::vector<std::string> rotation_labels;
  // A PCD source's frame layout (FORMAT.md 5.5): every field, x y z included (empty when the
  // stream has none), and WIDTH x HEIGHT (height 1: unorganized). The fields other than x y z
  // are coded losslessly (ATTR).
  std::vector<PCDField> pcd_fields;
  std::vector<double> pcd_field_bounds;  // per pcd_fields entry, 0: lossless; empty: all lossless
  size_t pcd_width = 0, pcd_height = 1;
  // Lossy analog channels (FORMAT.md 5.7), per channel, empty when all are lossless: the bound
  // in physical units (0: lossless), the factor from stored to physical units, and the label
  // and unit to name the channel by.
  std::vector<double> analog_bounds, analog_factors;
  std::vector<std::string> analog_labels, analog_units;
  std::map<std::string, size_t> chunk_bytes;  // total bytes (with framing) per chunk type
};
StreamInfo describe(const uint8_t* data, size_t size, const std::string& name = "");
// The same for the .capz file at `path`, read a chunk at a time (memory: the largest chunk).
StreamInfo describe_file(const std::string& path);

// True when the bytes start with the .capz magic: of format 1.x, or of the pre-release formats
// (capz 0.1.0 and earlier), which decoding refuses (kUnsupportedVersion) with how to upgrade.
bool is_capz(const uint8_t* data, size_t size);

// A length typed by the user: "0.1mm", "2 cm", "0.001m", "0.5in" or a bare number (the take's
// units). Converted to `take_units` ("mm", "cm", "m", ...). A number with a unit on a take
// whose units are unknown (empty) throws Error(kInvalidParameter) unless `assume_units` says
// what the take's units are. Throws kInvalidParameter on a malformed or negative value.
double parse_length(const std::string& text, const std::string& take_units,
                    const std::string& assume_units = "");

}  // namespace capz
