// Test helper: a folder of frame files compressed losslessly and rebuilt, every file compared
// byte for byte (docs/FORMAT.md "Lossless ragged streams").
#pragma once

#include <gtest/gtest.h>

#include <filesystem>
#include <memory>
#include <string>
#include <vector>

#include "capz/codec.h"
#include "capz/stream.h"
#include "capz/tool/file.h"
#include "capz/tool/original.h"
#include "io/pcd_folder.h"
#include "test_util.h"

namespace capz_test {

// Compresses folder `in` losslessly (windows of `window` frames), rebuilds it and expects every
// frame file back byte for byte; returns the stats.
inline capz::CompressStats expect_rebuilt(const std::string& in, const TempDir& tmp,
                                          size_t window = 0) {
  std::unique_ptr<capz::FrameSource> src = capz::open_frames(in);
  EXPECT_TRUE(src->header().ragged()) << in;
  capz::CompressOptions o;
  o.lossless = true;
  o.window_frames = window;
  capz::CompressStats st;
  const std::string z = tmp.file("l.capz"), out = tmp.file("back");
  capz::compress_stream(*src, o, z, true, &st);
  EXPECT_TRUE(st.lossless) << in;
  EXPECT_TRUE(capz::original_info(z).exact) << in;
  std::filesystem::remove_all(out);
  capz::rebuild_original(z, out, true);
  const std::vector<std::string> names = capz::list_pcd_frames(in);
  EXPECT_EQ(capz::list_pcd_frames(out), names) << in;
  for (const std::string& n : names)
    EXPECT_EQ(capz::read_file(out + "/" + n), capz::read_file(in + "/" + n)) << in << "/" << n;
  EXPECT_TRUE(capz::rebuilds_file(z, in).empty()) << capz::rebuilds_file(z, in);
  return st;
}

}  // namespace capz_test
