// capz — streaming: takes read, compressed, decompressed and written a block of frames at a time,
// so memory is bounded by the block (the coder's window), not by the take.
//
// A FrameSource gives a take's metadata (everything of a Take but the per-frame arrays) without
// reading its frames, then any range of frames on demand. A FrameSink writes a take whose
// metadata and frame count are known up front, frames in order. compress_stream and
// decompress_stream connect them to the .capz coder; they produce exactly what compress() and
// decompress() followed by write_take() produce.
#pragma once

#include <cstddef>
#include <cstdint>
#include <functional>
#include <memory>
#include <string>
#include <vector>

#include "capz/codec.h"
#include "capz/io.h"
#include "capz/take.h"

namespace capz {

// Frames [first, first + frames) of a take: the per-frame arrays of Take (take.h) cut to them,
// in the same layouts. A block of a ragged take has frame_offsets: frames + 1 offsets from 0,
// relative to the block (frame first + k holds the block's points [frame_offsets[k],
// frame_offsets[k + 1])), points 0, and xyz / valid / attributes sized for total_points(); its
// C3D words, analog and rotation arrays are empty.
struct FrameBlock {
  size_t first = 0, frames = 0, points = 0;
  std::vector<size_t> frame_offsets;  // empty: every frame has `points` points
  std::vector<double> xyz;            // total_points() x 3
  std::vector<uint8_t> valid;         // total_points()
  std::vector<float> residual;       // frames x points (C3D 4th word), empty when the take has none
  std::vector<uint8_t> camera_mask;  // frames x points, empty when the take has none
  std::vector<double> analog;        // (frames * samples_per_frame) x channels
  // The frames' rotation samples (Rotations in take.h), bit for bit; empty without rotations:
  std::vector<float> rotation_matrices;     // (frames * R) x segments x 16
  std::vector<float> rotation_reliability;  // (frames * R) x segments
  // Per Take::attributes entry, the frames' bytes: frames x points x count x size (take.h).
  std::vector<std::vector<uint8_t>> attributes;
  // A C3D source's frames as the file stores them, from byte file_bytes_at of the file (the
  // residue's original, not read a second time); empty from other sources.
  std::vector<uint8_t> file_bytes;
  uint64_t file_bytes_at = 0;

  // Sizes every array for `frames` x `points` (gaps, zeros); words: with residual/camera arrays;
  // rotations_per_frame: R x segments (0 without rotations).
  void reset(size_t first, size_t frames, size_t points, size_t analog_values_per_frame, bool words,
             size_t rotations_per_frame = 0);
  // A ragged block of counts.size() frames from `first`, frame k holding counts[k] points:
  // frame_offsets set, xyz and valid sized (gaps, zeros), every other array empty.
  void reset_ragged(size_t first, const std::vector<size_t>& counts);
  bool ragged() const { return !frame_offsets.empty(); }
  size_t frame_begin(size_t k) const { return ragged() ? frame_offsets[k] : k * points; }
  size_t frame_points(size_t k) const {
    return ragged() ? frame_offsets[k + 1] - frame_offsets[k] : points;
  }
  size_t total_points() const { return ragged() ? frame_offsets.back() : frames * points; }
  // The bytes a frame of the block takes once reset with these arguments and its attribute
  // arrays sized for `attribute_bytes_per_point` (the sum of PointAttribute::bytes_per_point):
  // what a decoder's memory limit counts (CapzSource). Counts and result in double: a hostile
  // header's products may not fit size_t.
  static double frame_bytes(double points, double analog_values_per_frame, bool words,
                            double rotations_per_frame, double attribute_bytes_per_point);
};

class FrameSource {
 public:
  virtual ~FrameSource() = default;
  // The take without its per-frame arrays: frames and points set (a ragged take: points 0 and
  // frame_offsets for every frame, known when the source is opened); xyz, valid, analog.values,
  // rotations.matrices / reliability and c3d->residual / camera_mask empty (the rotation layout,
  // rate and labels are set). Per-frame metadata that is small (TRC times and frame numbers, PCD
  // frame names) is kept.
  const Take& header() const { return header_; }
  // The same, for a caller that amends metadata before using the source (e.g. units for data
  // that has none); the frame and point counts, the analog and the rotation layouts must not
  // change.
  Take& edit_header() { return header_; }
  // True when read() fills residual and camera_mask (C3D 4th words).
  virtual bool has_sample_words() const = 0;
  // Frames [first, first + count), clipped to the take. Reads only those frames where the
  // format allows it (C3D: seek; .capz: the windows they touch). Throws capz::Error.
  virtual void read(size_t first, size_t count, FrameBlock* out) = 0;
  // The block size reads are cheapest in (a .capz: its window size).
  virtual size_t preferred_block() const { return 1024; }
  // Warnings found while reading frames (e.g. C3D 4th words beyond 16 bits); complete after
  // every frame has been read once, in order.
  virtual std::vector<std::string> frame_warnings() const { return {}; }
  // Bytes read from the file so far (0 for sources in memory).
  virtual uint64_t bytes_read() const { return 0; }
  // The path of the original C3D or TRC file (or PCD folder) whose frames read() gives as read
  // (the encoder then stores its checksum and residue, FORMAT.md 7, 14); empty for every
  // other source.
  virtual std::string original_file() const { return std::string(); }

 protected:
  // Clips [*first, *first + *count) to the take's frames.
  void clip(size_t* first, size_t* count) const {
    *first = *first < header_.frames ? *first : header_.frames;
    *count = *count < header_.frames - *first ? *count : header_.frames - *first;
  }

  Take header_;
};

// A C3D file read by frame ranges (the file stays open; frames are read with seeks).
std::unique_ptr<FrameSource> open_c3d_frames(const std::string& path);
// A TRC read by frame ranges: opening reads every line once (the point count, the decimals and
// the Time column depend on all of them), keeping the per-row metadata (times, frame numbers) and
// each row's file offset, about 32 bytes a frame; a range reads and parses only its rows.
std::unique_ptr<FrameSource> open_trc_frames(const std::string& path);
// A folder of PCD, PLY or .bin frames (or one such file) read file by file: opening lists the
// files and reads each one's header (its point count: a ragged take when they differ) or size.
std::unique_ptr<FrameSource> open_pcd_frames(const std::string& path);
std::unique_ptr<FrameSource> open_ply_frames(const std::string& path);
std::unique_ptr<FrameSource> open_bin_frames(const std::string& path);
// open_frames with what its files do not say (io.h): a .bin source in a declared record.
std::unique_ptr<FrameSource> open_frames(const std::string& path, const ReadOptions& opts);
// A .capz read window by window (HEAD, META and INDX up front; a range decodes the windows it
// touches). The header is what decompress() returns without its frame arrays. With
// opts.threads above 1, windows are decoded ahead in parallel when read in order.
std::unique_ptr<FrameSource> open_capz_frames(const std::string& path,
                                              const DecompressOptions& opts = {});
// An in-memory take as a source (the take must outlive the source).
std::unique_ptr<FrameSource> take_frames(const Take& take);
// Any input read_take() accepts (C3D, TRC, PCD / PLY / .bin frames), read by frame ranges.
std::unique_ptr<FrameSource> open_frames(const std::string& path);

class FrameSink {
 public:
  virtual ~FrameSink() = default;
  // True when the writer must see every frame once before the first write() (a C3D written as
  // int16 checks that every value fits); the caller then calls prescan() on all frames in order.
  virtual bool wants_prescan() const { return false; }
  virtual void prescan(const FrameBlock&) {}
  // Instead of the prescan, a sink may offer to plan its output from what it expects and check
  // each block as it is written (true: it will). If a block then proves the plan wrong, the sink
  // discards what it wrote and needs_rewrite() turns true: the caller writes every frame again,
  // after a prescan of them all if wants_prescan() still holds (a C3D sink that found a value
  // beyond int16 knows the file is float and needs none). The output is the same either way.
  virtual bool skip_prescan() { return false; }
  virtual bool needs_rewrite() const { return false; }
  // Frames in order, starting at 0, ending at header().frames.
  virtual void write(const FrameBlock& block) = 0;
  // Checks that every frame was written, then renames the output into place.
  virtual void commit() = 0;
};

// A writer for `path` by its extension, the bytes write_take writes: .c3d, .trc and folders of
// PCD, PLY or .bin frames written block by block (a frame folder file by file into a temporary
// folder renamed at commit, a single frame file from its block at commit); a C3D whose int16
// scale comes from the data written whole from memory. `header` as FrameSource::header();
// `words`: blocks carry C3D 4th words.
std::unique_ptr<FrameSink> create_frame_sink(const Take& header, bool words,
                                             const std::string& path,
                                             const WriteOptions& opts = {});

// Compresses a source window by window into `path` (written atomically, as file.h says). Same
// bytes as compress() on the whole take, plus, for a source with an original_file(), its HASH
// and residue chunks (FORMAT.md 7, 14). Lossless and --max-error read the source twice (a scan
// that fixes the grid, then the coding pass); so does a KG target when its valid coordinates fit
// in 64 MiB (the scan keeps them for the grid search), else it reads it once more per bisection
// step of the search (about 26). codec "auto" is not streamed (throws
// kInvalidParameter: use compress()).
void compress_stream(FrameSource& source, const CompressOptions& opts, const std::string& path,
                     bool overwrite, CompressStats* stats = nullptr);

// Copies every frame of the source to the sink, `block` frames at a time (prescanning first
// when the sink asks and cannot skip it, or when a write without it needs redoing), then
// commits the sink.
void copy_frames(FrameSource& source, FrameSink& sink, size_t block = 1024);

// Every frame of the source as one take in memory (the header's metadata, the frames' arrays,
// and the source's frame_warnings() added to its warnings: read_take() of a frame folder is
// this), read `block` frames at a time (0: the source's preferred_block(), at most 64).
// progress, when set, is called with (frames read, frames) after each block; what it throws
// stops the read and leaves this call.
Take read_all_frames(FrameSource& source,
                     const std::function<void(size_t, size_t)>& progress = nullptr,
                     size_t block = 0);

// Writes every frame of the source to `path` (create_frame_sink: the bytes write_take writes of
// the whole take), `block` frames at a time (0: the source's preferred_block()). A frame folder
// in and a frame folder out hold one block in memory, not the take (`capz convert`). Throws
// capz::Error; nothing is left at `path` on failure.
void write_frames(FrameSource& source, const std::string& path, const WriteOptions& opts = {},
                  size_t block = 0);

}  // namespace capz
