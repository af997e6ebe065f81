// capz — PCD folder helpers shared by the folder writer (pcd_folder.cpp) and the byte-exact
// rebuild of a PCD archive (codec/rebuild_pcd.cpp).
#pragma once

#include <string>
#include <vector>

#include "capz/take.h"

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

}  // namespace capz
