// NOT PART OF THE STABLE API (include/capz/tool/): what the capz CLI and the Python module share
// so that they behave alike. Installed for programs that want the CLI's exact behaviour, but it
// may change in any release; the stable API is the headers of include/capz/ itself.
// capz — `capz compress IN -o OUT` as library calls: the input opened, the error target chosen
// and the output written exactly as the command does, so any caller (the CLI, the Python
// package) gets the same bytes for the same options.
#pragma once

#include <memory>
#include <optional>
#include <string>

#include "capz/codec.h"
#include "capz/stream.h"
#include "capz/take.h"

namespace capz {

// The error target as the command line gives it: at most one of lossless, kg_error and
// max_error; none given means the default bound (see set_compress_target).
struct CompressTarget {
  bool lossless = false;
  std::optional<double> kg_error;        // KG error target in percent
  std::optional<std::string> max_error;  // a length parse_length() reads ("0.1mm", "0.5")
};

// The input of a compression. C3D, TRC and PCD inputs stream: `source` reads the file a window
// at a time. `whole` (codec auto, which compares whole-take encodings) reads the take into
// `take` and `source` serves it (the take is held by pointer, so a moved input stays valid).
struct CompressInput {
  std::unique_ptr<Take> take;
  std::unique_ptr<FrameSource> source;
};

// Opens `path` (C3D, TRC, PCD / PLY / .bin frames) for compression. `units` (may be empty) is
// given to data that has none, whose units capz cannot read, or whose units the reader assumed
// (Take::units_assumed: metres for PCD, PLY and .bin).
CompressInput open_compress_input(const std::string& path, bool whole, const std::string& units);
// The same, told what the files do not say (a .bin source's record: ReadOptions, capz/io.h).
CompressInput open_compress_input(const std::string& path, bool whole, const std::string& units,
                                  const ReadOptions& read);

// Sets opts->lossless, kg_error and max_error from `target` as `capz compress` does. The default
// bound is 0.1 mm; for data without units, or with assumed ones, it is 1e-4 of the bounding-box
// diagonal of the valid samples (the source is read once for it), lossless for frames that
// store float32 coordinates too far from the origin for float32 to resolve that bound, and any
// bound when no sample is valid. A bound with a unit on assumed units is read in them (--max-error
// 1mm on PCD frames: 0.001 m). A few samples far outside the others (up to 16 at each end of an
// axis, none in a take of under 1000 samples, their box's diagonal over 100x the others') do not
// set the default: it is then the others' box's (or lossless, when that bound cannot hold at the
// far samples), and the returned note (otherwise empty) says so. Throws Error(kUsage) for more
// than one target, kInvalidParameter for a KG target or a bound that is not > 0, or a bound with
// a unit on data without units.
std::string set_compress_target(FrameSource& source, const CompressTarget& target,
                                CompressOptions* opts);

// Compresses the input into `out`, written atomically: compress_stream() (for a C3D or TRC
// source with the original file's checksum and residue), or under codec auto compress() of the
// whole take. Assumed units are not stored (they are cleared from the input's header first):
// the archive keeps what the file said, so such takes keep the bytes capz gave them before it
// assumed metres. Throws kUsage if `out` exists and !overwrite.
void compress_input(CompressInput& input, const CompressOptions& opts, const std::string& out,
                    bool overwrite, CompressStats* stats = nullptr);

// The note a compression's report gives on samples marked absent (a C3D's negative residual
// word) whose coordinates the archive does not keep (stats.dropped_coordinates: at a bound, as
// for every gap; --lossless keeps them), as the CLI prints it ("capz compress: note: IN: " before
// it) and the Python module warns it (a UserWarning); "" when there are none.
std::string dropped_coordinates_note(const CompressStats& stats);

// The three above in a row: `capz compress IN -o OUT` with `target`, `units` (--units; checked
// to name a unit capz knows) and the coding options of `opts` (codec, clusters, codec_options,
// window_frames, check, progress; its target fields are replaced), IN read with `read`. Returns
// set_compress_target's note.
std::string compress_file(const std::string& in, const std::string& out,
                          const CompressTarget& target, const CompressOptions& opts,
                          const std::string& units, bool overwrite, CompressStats* stats = nullptr,
                          const ReadOptions& read = {});

}  // namespace capz
