// capz — readers and writers. Every function throws capz::Error naming the file on failure.
// Writers never leave a partial output: they write a temporary sibling and rename it into place.
#pragma once

#include <cstdint>
#include <string>
#include <vector>

#include "capz/take.h"

namespace capz {

// Format from the path: a directory -> the folder format of its frame files (.pcd, else .ply,
// else .bin files; PCD when it holds none); a file by its magic, then its extension (.c3d, .trc,
// .pcd, .ply, .bin; a single frame file is the one-frame take of its folder format).
Format detect_format(const std::string& path);

// Whether a directory holds frame files (.pcd, .ply or .bin regular files, hidden ones aside:
// a name starting with '.', as macOS's "._NAME" copies): the folder of a take. False for a path
// that is not a readable directory.
bool holds_frame_files(const std::string& dir);

// Whether frame files written to the folder `dir` go in beside what it holds: `dir` is an
// existing directory (not a symbolic link) holding nothing but subfolders, hidden files and
// .capz archives, such as the folder of an archive tree that holds its subfolder's archive
// (`decompress -r` restores both). Writing a take's frames there is no overwrite: the folder
// writers (write_take, the frame sinks, rebuild_original) move their files in at the end, each
// under a name the folder does not hold yet.
bool frames_go_beside(const std::string& dir);

// Reads any supported input (.c3d, .trc, a folder of .pcd, .ply or .bin frames, or a single
// .pcd, .ply or .bin frame file as a one-frame take). Folders whose frames' point counts differ
// give a ragged take (take.h).
Take read_take(const std::string& path);

// What a reader is told that its files do not say.
struct ReadOptions {
  // A .bin source's record (parse_bin_record's text, the CLI's --bin-fields); empty: the frame
  // names' (KITTI's or nuScenes'). Given for another source, an Error(kUsage).
  std::string bin_fields;
};
Take read_take(const std::string& path, const ReadOptions& opts);
// The record opts gives a .bin source at `path` (its fields after x y z), or none (empty
// bin_fields). Throws Error(kUsage) for a bad text or a source of another format.
std::vector<PCDField> declared_bin_record(const std::string& path, const ReadOptions& opts);
// The options that read a .bin source in the record `header` holds: its declared record's text
// (take.h BinExtra), else none (the names' record, and any other format).
ReadOptions read_options_of(const Take& header);

struct WriteOptions {
  bool overwrite = false;  // replace an existing output (the CLI's -f)
  // PCD DATA: "ascii", "binary" or "binary_compressed"; empty: the source's (Take::pcd), else
  // binary.
  std::string pcd_encoding;
  // PLY: "ascii", "binary_little_endian" or "binary_big_endian"; empty: the source's (Take::ply),
  // else binary_little_endian.
  std::string ply_encoding;
  // The format of a folder output (kPCDFolder, kPLYFolder or kBinFolder); kUnknown: the take's
  // own when it is one of those, else PCD. A path ending in .pcd, .ply or .bin (not an existing
  // directory) is a single frame file of that format whatever this says.
  Format folder_format = Format::kUnknown;
  bool c3d_float = false;  // C3D written as float even if the source was int16 (default: source's)
  // Writing a take with point fields (Take::attributes) to C3D or TRC, which cannot hold them,
  // is an error naming them unless this is set; then they are left out.
  bool drop_fields = false;
  // TRC output: '\t' (OpenSim's form) or ',' (the comma form, every line padded to the same
  // field count); 0: the take's own (a comma-separated TRC source's commas, else tabs).
  char trc_delimiter = 0;
};

// Throws kUsage naming the take's point fields when a file of format f cannot hold them and
// !opts.drop_fields (C3D and TRC hold none; a PCD folder holds every one; PLY every one of COUNT
// 1; .bin only "intensity"; padding fields "_" go without a word), and for a ragged take when f
// is C3D or TRC (a fixed number of points a frame).
void check_fields_fit(const Take& take, Format f, const std::string& path,
                      const WriteOptions& opts);

// Writes by the output path: ".c3d", ".trc", ".pcd", ".ply", ".bin" (a one-frame file),
// otherwise (a directory path, existing or ending in '/', or a name without extension) a folder
// of frames in output_format's format. Throws kUsage if the output exists and !opts.overwrite.
void write_take(const Take& take, const std::string& path, const WriteOptions& opts = {});
// The format a path names: kC3D, kTRC, kPCDFolder (.pcd files and folders), kPLYFolder (.ply),
// kBinFolder (.bin); kUnknown for other extensions.
Format format_for_output(const std::string& path);
// The format `take` is written in at `path` with `opts`: format_for_output, a folder made
// PLY or .bin by opts.folder_format or, without it, by the take's own format.
Format output_format(const Take& take, const std::string& path, const WriteOptions& opts);
// What writing `take` as `out` leaves out, each as a phrase: "the 16 analog channels", "the C3D
// parameter section (with its 8 events)", "the 2 rotation segments", "the frame rate (100 Hz)"
// (PCD frames store none), "float64 values (x y z: rounded to float32)" (.bin frames from
// PCD or PLY doubles); empty when `out` keeps it all. Point fields are not listed: the
// writers refuse them without WriteOptions::drop_fields.
std::vector<std::string> dropped_by(const Take& take, Format out);

// Per format. `name` in the *_bytes readers is only used in messages.
Take read_c3d(const std::string& path);
Take read_c3d_bytes(const uint8_t* data, size_t size, const std::string& name);
void write_c3d(const Take& take, const std::string& path, const WriteOptions& opts = {});
// The parameter section write_c3d gives a take not read from C3D (POINT, ANALOG with unit
// SCALE, zero OFFSET and GEN_SCALE 1, TRIAL; ROTATION when it has rotations), as a C3DExtra to
// set as take.c3d before adding groups of one's own: float storage, point_scale 0 (the writer
// takes the scale from the data, as without a section), no sample words. `name` is for messages
// (kUsage when the take does not fit C3D's counts). take.c3d itself is not read.
std::shared_ptr<C3DExtra> new_c3d_parameters(const Take& take, const std::string& name);

Take read_trc(const std::string& path);
Take read_trc_bytes(const uint8_t* data, size_t size, const std::string& name);
void write_trc(const Take& take, const std::string& path, const WriteOptions& opts = {});

// PCD, PLY and .bin frames: `path` is a folder of frame files or one frame file; writing to a
// path ending in the format's extension writes one frame file (a take of one frame).
Take read_pcd_folder(const std::string& path);
void write_pcd_folder(const Take& take, const std::string& path, const WriteOptions& opts = {});
Take read_ply_folder(const std::string& path);
void write_ply_folder(const Take& take, const std::string& path, const WriteOptions& opts = {});
Take read_bin_folder(const std::string& path);
void write_bin_folder(const Take& take, const std::string& path, const WriteOptions& opts = {});

}  // namespace capz
