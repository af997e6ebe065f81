// Frame files: takes whose frames are files of their own (PCD, PLY, KITTI .bin), given as a
// folder of them or as one such file (a one-frame take). What the three readers share: listing
// the frames, the choice between a fixed take (every frame has the same point count, the case
// capz always had) and a ragged one (take.h), and a FrameSource that reads a range of frames
// file by file into a FrameBlock of either shape. Part of the decoder library.
#pragma once

#include <cstddef>
#include <cstdint>
#include <functional>
#include <memory>
#include <optional>
#include <string>
#include <vector>

#include "capz/stream.h"
#include "capz/take.h"

namespace capz {

// The frames of a folder (its regular files with the extension, natural-sort order) or a single
// frame file.
struct FrameFiles {
  std::string dir;                 // the folder; a single file's own folder ("." when none)
  std::vector<std::string> names;  // file names, one per frame
  bool single = false;             // one file was given, not a folder
  std::string path(size_t f) const;
};

// Lists `path`: a directory gives its files ending in `ext` (".pcd", case-insensitive), hidden
// ones aside (hidden_name), a file gives itself. Throws Error(kUsage) for a path that is
// neither, kNotOurFormat for a folder without such files.
FrameFiles list_frame_files(const std::string& path, const std::string& ext);

// Whether a file name in a folder is hidden (starts with '.'): never a frame of the folder.
// macOS leaves "._NAME" files of its own beside every file it copies to a foreign file system,
// and editors their ".NAME.swp": none is a frame.
bool hidden_name(const std::string& name);

// The first min(size, `bytes`) bytes of a file. Throws Error(kIo) naming it.
std::vector<uint8_t> read_file_head(const std::string& path, size_t bytes);

// The first bytes of a frame file through its header: 16 KiB, or up to 1 MiB when those do not
// hold `marker` (the header's last line's key, "\nDATA", "end_header").
std::vector<uint8_t> read_header_bytes(const std::string& path, const std::string& marker);

// One frame as a writer takes it: its points, their coordinates (points x 3) and validity, and
// per take attribute a pointer to the frame's bytes (points x count x size).
struct FrameView {
  size_t points = 0;
  const double* xyz = nullptr;
  const uint8_t* valid = nullptr;
  std::vector<const uint8_t*> attrs;
};

// Frame f of a take, frame k of a block (its arrays must match its shape).
FrameView frame_view(const Take& take, size_t f);
FrameView frame_view(const FrameBlock& b, size_t k);

// A frame file's bytes from its frame (pcd_file_writer, ply_file_writer, bin_file_writer: the
// one producer both the whole-take writers and the folder sink use).
using FrameFileBytes = std::function<std::vector<uint8_t>(const FrameView&)>;

// Writes the take's frames as files ending in `ext` (".pcd", ".ply", ".bin"), each frame's bytes
// from frame(frame_view(take, f)): one file at `path` when single_frame_output(path, ext) (the
// take must have one frame), else a folder of frame_output_names, replaced atomically
// (AtomicDir). Throws Error(kInternal) for a take whose arrays do not match its shape, kUsage for
// a take without frames or a single file asked of several.
void write_frame_files(const Take& take, const std::string& path, const std::string& ext,
                       bool overwrite, const FrameFileBytes& frame);

// A sink writing a folder of frame files as the blocks come (memory bounded by a block, not by
// the take): each frame's file goes into the AtomicDir's temporary folder, renamed into `path` at
// commit (nothing is left on failure). `make(header, xyz_float)` gives the format's producer;
// `needs_scan` says whether its coordinate type comes from the data, which the sink then learns
// by a prescan of every block (coordinates_are_floats). The same files as write_frame_files.
// When single_frame_output(path, ext), one file at `path` (a take of one frame; its block scanned
// as it is written, no prescan), written at commit.
std::unique_ptr<FrameSink> frame_folder_sink(
    const Take& header, const std::string& path, const std::string& ext, bool overwrite,
    bool needs_scan, std::function<FrameFileBytes(std::optional<bool>)> make);

// The extension of a frame format's files: ".pcd", ".ply", ".bin" ("" for another format).
const char* frame_extension(Format f);

// True when `path`'s extension is `ext` (".pcd"), case-insensitive.
bool has_extension(const std::string& path, const std::string& ext);

// The frame file names the take's source had (its PCD, PLY or .bin extras), or null.
const std::vector<std::string>* source_frame_names(const Take& take);

// The file names a folder output of `take` with extension `ext` (".pcd", ".ply", ".bin") uses:
// the source's frame names (source_frame_names) with their extension made `ext`, when there is
// one per frame, each a plain file name and all different; else frame_000001<ext>, ...
std::vector<std::string> frame_output_names(const Take& take, const std::string& ext);

// With `overwrite`, an existing `dir` may be replaced only when it holds nothing but frame files
// ending in `ext`: throws Error(kUsage) otherwise. A `dir` the frames go beside what it holds
// (frames_go_beside) is not replaced.
void check_replaceable_frame_dir(const std::string& dir, const std::string& ext, bool overwrite);

// True when `path` names a single frame file to write: it ends in `ext` and is no directory.
bool single_frame_output(const std::string& path, const std::string& ext);

// The fixed or ragged shape of a take whose frames have these point counts: a fixed take
// (points = the count, labels one empty string a point) when every frame has the same count,
// else a ragged one (frame_offsets, points 0). Sets frames, points, frame_offsets and labels of
// *t; xyz and valid are left empty.
void set_frame_shape(const std::vector<size_t>& counts, Take* t);

// One frame as a reader gives it: points x 3 coordinates (a gap's are 0), validity, and per
// attribute of the take its bytes (points x count x size, little-endian).
struct FrameData {
  size_t points = 0;
  std::vector<double> xyz;
  std::vector<uint8_t> valid;
  std::vector<std::vector<uint8_t>> attrs;
};

// A take of frame files read frame by frame. A subclass fills header_ (metadata, attribute
// layouts) and calls set_counts() from the files' headers when it opens; read() then reads each
// frame of a range with read_frame() into a block of the take's shape, checking that the frame
// holds the points its header announced.
class FileFrameSource : public FrameSource {
 public:
  explicit FileFrameSource(FrameFiles files) : files_(std::move(files)) {}
  bool has_sample_words() const override { return false; }
  // The folder (a single file's folder): the encoder stores each frame file's checksum and
  // residue where the format has a residue (FORMAT.md 7.3, 14.3).
  std::string original_file() const override { return files_.dir; }
  void read(size_t first, size_t count, FrameBlock* out) override;
  // As read(), but the block's attributes may be left empty (not one array each): what a pass
  // over the coordinates alone needs, cheaper where the format allows (a PCD folder's
  // binary_compressed bodies: their field planes after x y z's are not decompressed).
  void read_coordinates(size_t first, size_t count, FrameBlock* out);
  size_t preferred_block() const override { return 16; }

 protected:
  void set_counts(const std::vector<size_t>& counts);
  // Reads frame f (files_.path(f)) into *out. Throws Error naming the file.
  virtual void read_frame(size_t f, FrameData* out) = 0;
  // The same, but out's attrs may be left empty; by default read_frame.
  virtual void read_frame_coordinates(size_t f, FrameData* out) { read_frame(f, out); }

  FrameFiles files_;
  std::vector<size_t> counts_;

 private:
  void read_frames(size_t first, size_t count, FrameBlock* out, bool coordinates);
};

}  // namespace capz
