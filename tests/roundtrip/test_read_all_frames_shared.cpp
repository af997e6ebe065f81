// read_all_frames (include/capz/stream.h) on the shared real data: every C3D and TRC file, the
// mesh animations' PCD folders and the scan sequences give read_take's take through open_frames
// (Python's capz.read reads them so, with progress and Ctrl-C); a file read_take refuses is
// refused with the same code.
#include <gtest/gtest.h>

#include <algorithm>
#include <filesystem>
#include <memory>
#include <string>
#include <vector>

#include "capz/error.h"
#include "capz/io.h"
#include "capz/stream.h"
#include "test_util.h"

namespace capz {
namespace {

// Both ways of reading `path`: the same take, or the same error code.
void check(const std::string& path) {
  SCOPED_TRACE(path);
  Take whole;
  try {
    whole = read_take(path);
  } catch (const Error& e) {
    EXPECT_EQ(capz_test::error_of([&] { read_all_frames(*open_frames(path)); }), e.code());
    return;
  }
  capz_test::expect_same_take(read_all_frames(*open_frames(path)), whole);
}

std::vector<std::string> files_under(const std::string& dir, const std::string& ext) {
  std::vector<std::string> out;
  for (const auto& e : std::filesystem::recursive_directory_iterator(dir))
    if (e.is_regular_file() && e.path().extension() == ext) out.push_back(e.path().string());
  std::sort(out.begin(), out.end());
  return out;
}

TEST(ReadAllFramesShared, EveryC3dAndTrcFile) {
  const std::string root = capz_test::shared_data_or_skip();
  if (root.empty()) return;
  size_t n = 0;
  for (const char* kind : {"c3d", "trc"})
    for (const std::string& f : files_under(root + "/" + kind, std::string(".") + kind)) {
      check(f);
      ++n;
    }
  EXPECT_GT(n, 100u);
}

TEST(ReadAllFramesShared, PcdFoldersAndScans) {
  const std::string root = capz_test::shared_data_or_skip();
  if (root.empty()) return;
  for (const auto& e : std::filesystem::directory_iterator(root + "/pcd"))
    if (e.is_directory()) check(e.path().string());
  for (const char* rel : {"scan/pandar64-factory20", "scan/robosense-e1",
                          "scan/robosense-helios16p", "scan/single/hesai-xt16.pcd"})
    check(root + "/" + rel);
}

}  // namespace
}  // namespace capz
