// capz/tool/file.h's path helpers: the one trailing-slash rule every output path goes through,
// and TemporaryFolder (the CLI's pipe folder) removed with what it holds.
#include <gtest/gtest.h>

#include <filesystem>
#include <fstream>
#include <string>

#include "capz/tool/file.h"
#include "test_util.h"

namespace fs = std::filesystem;

TEST(WithoutTrailingSlashes, GivenPathsThenOnlyTrailingSlashesGoAndTheRootStays) {
  EXPECT_EQ(capz::without_trailing_slashes("a/b/frames/"), "a/b/frames");
  EXPECT_EQ(capz::without_trailing_slashes("a/b//"), "a/b");
  EXPECT_EQ(capz::without_trailing_slashes("/a/b"), "/a/b");
  EXPECT_EQ(capz::without_trailing_slashes("out.ply/"), "out.ply");
  EXPECT_EQ(capz::without_trailing_slashes("/"), "/");
  EXPECT_EQ(capz::without_trailing_slashes("///"), "/");
  EXPECT_EQ(capz::without_trailing_slashes(""), "");
}

TEST(TemporaryFolder, GivenFilesInsideThenTheFolderGoesWithThem) {
  capz_test::TempDir dir;
  std::string path;
  {
    capz::TemporaryFolder t(dir.file("pipe-XXXXXX"));
    path = t.path();
    ASSERT_TRUE(fs::is_directory(path));
    EXPECT_EQ(path.find("XXXXXX"), std::string::npos) << path;
    std::ofstream(path + "/stdin") << "bytes";
  }
  EXPECT_FALSE(fs::exists(path));
  EXPECT_THROW(capz::TemporaryFolder(dir.file("absent/pipe-XXXXXX")), capz::Error);
}
