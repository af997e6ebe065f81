// capz — PCD folder helpers shared by the folder writer (pcd_folder.cpp) and the byte-exact
// rebuild of a PCD archive (codec/rebuild_pcd.cpp).
#pragma once

#include <memory>
#include <optional>
#include <string>
#include <vector>

#include "capz/io.h"
#include "capz/stream.h"
#include "capz/take.h"
#include "io/frame_files.h"

namespace capz {

// The .pcd files of a folder in natural-sort order (the frames). Throws Error(kUsage) for a path
// that is no directory, kNotOurFormat when it holds no .pcd file.
std::vector<std::string> list_pcd_frames(const std::string& dir);

// The file names a folder output of `take` uses: the source's (take.pcd->frame_names) when there
// is one per frame, each a plain .pcd name and all different; else frame_000001.pcd, ...
std::vector<std::string> pcd_output_names(const Take& take);

// With `overwrite`, an existing `dir` may be replaced only when it holds nothing but PCD frames:
// throws Error(kUsage) otherwise.
void check_replaceable_pcd_dir(const std::string& dir, bool overwrite);

// A PCD frame file's bytes in encoding `enc` (pcd_frame_plan of `take`, `xyz_float` as there);
// `dir` names the output in messages (kUsage for a frame of more than 2^31 points).
FrameFileBytes pcd_file_writer(const Take& take, const std::string& enc, const std::string& dir,
                               std::optional<bool> xyz_float);

// A folder of PCD frames written block by block (frame_folder_sink): the files write_pcd_folder
// writes of the whole take.
std::unique_ptr<FrameSink> pcd_folder_sink(const Take& header, const std::string& dir,
                                           const WriteOptions& opts);

}  // namespace capz
