// Output paths: the one trailing-slash rule (capz/tool/file.h), TemporaryFolder (the CLI's pipe
// folder) removed with what it holds, and AtomicDir's files going in beside a folder's own
// (frames_go_beside: its rule, and asked only where it decides something).
#include <gtest/gtest.h>
#include <sys/stat.h>

#include <algorithm>
#include <filesystem>
#include <fstream>
#include <functional>
#include <string>
#include <vector>

#include "capz/io.h"
#include "capz/tool/file.h"
#include "core/atomic_file.h"
#include "support/frame_files.h"
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

namespace {

std::vector<std::string> names_in(const fs::path& dir) {
  std::vector<std::string> v;
  for (const auto& e : fs::directory_iterator(dir)) v.push_back(e.path().filename().string());
  std::sort(v.begin(), v.end());
  return v;
}

}  // namespace

// A folder of an archive tree (subfolders and .capz archives only) takes a folder output's files
// beside its own; a name it holds already refuses them all, and nothing is left behind.
TEST(AtomicDirBeside, GivenAFolderOfArchivesThenFilesGoInBesideAndANameHeldRefuses) {
  capz_test::TempDir dir;
  fs::create_directories(dir.path() / "a" / "sub");
  capz_test::put(dir.path() / "a" / "sub.capz", "archive");
  ASSERT_TRUE(capz::frames_go_beside(dir.file("a/")));
  {
    capz::AtomicDir out(dir.file("a/"), false, capz::frames_go_beside);
    capz::write_file(out.temp_dir() + "/0.pcd", {1, 2}, false);
    capz::write_file(out.temp_dir() + "/1.pcd", {3}, false);
    out.commit();
  }
  EXPECT_EQ(names_in(dir.path() / "a"),
            (std::vector<std::string>{"0.pcd", "1.pcd", "sub", "sub.capz"}));
  EXPECT_EQ(names_in(dir.path()), std::vector<std::string>{"a"});
  EXPECT_FALSE(capz::frames_go_beside(dir.file("a")));  // it holds frames now
  EXPECT_THROW(capz::AtomicDir(dir.file("a"), false, capz::frames_go_beside), capz::Error);

  fs::create_directories(dir.path() / "b" / "1.pcd");  // a subfolder named as a frame
  {
    capz::AtomicDir out(dir.file("b"), false, capz::frames_go_beside);
    capz::write_file(out.temp_dir() + "/0.pcd", {1}, false);
    capz::write_file(out.temp_dir() + "/1.pcd", {2}, false);
    try {
      out.commit();
      ADD_FAILURE() << "b/1.pcd was written over";
    } catch (const capz::Error& e) {
      EXPECT_NE(std::string(e.what()).find("holds 1.pcd already"), std::string::npos) << e.what();
    }
  }
  EXPECT_EQ(names_in(dir.path() / "b"), std::vector<std::string>{"1.pcd"});
  EXPECT_EQ(names_in(dir.path()), (std::vector<std::string>{"a", "b"}));
  // A folder holding anything else is an existing output, as before.
  fs::create_directories(dir.path() / "c");
  capz_test::put(dir.path() / "c" / "notes.txt", "x");
  EXPECT_FALSE(capz::frames_go_beside(dir.file("c")));
  EXPECT_THROW(capz::AtomicDir(dir.file("c"), false, capz::frames_go_beside), capz::Error);
}

namespace {

int g_asked = 0;  // how often takes_files below was asked
bool takes_files(const std::string& path) {
  ++g_asked;
  return capz::frames_go_beside(path);
}

}  // namespace

// Listing a folder is what frames_go_beside costs (a folder of an archive tree may hold
// thousands of archives): with overwrite an AtomicDir does not ask it to open, only to commit.
TEST(AtomicDirBeside, GivenOverwriteThenTheFolderIsAskedOnlyToCommit) {
  capz_test::TempDir dir;
  fs::create_directories(dir.path() / "a");
  capz_test::put(dir.path() / "a" / "0.pcd", "old frame");
  g_asked = 0;
  {
    capz::AtomicDir out(dir.file("a"), true, takes_files);
    EXPECT_EQ(g_asked, 0);
    capz::write_file(out.temp_dir() + "/1.pcd", {1}, false);
    out.commit();
  }
  EXPECT_GE(g_asked, 1);
  EXPECT_EQ(names_in(dir.path() / "a"), std::vector<std::string>{"1.pcd"});
  EXPECT_EQ(names_in(dir.path()), std::vector<std::string>{"a"});
}

// check_output_free asks `takes_files` only of an existing output it would refuse.
TEST(AtomicDirBeside, GivenCheckOutputFreeThenTheFolderIsAskedOnlyWhenItMatters) {
  capz_test::TempDir dir;
  fs::create_directories(dir.path() / "a" / "sub");
  capz_test::put(dir.path() / "a" / "sub.capz", "archive");
  fs::create_directories(dir.path() / "b");
  capz_test::put(dir.path() / "b" / "0.pcd", "frame");
  g_asked = 0;
  capz::check_output_free(dir.file("a"), true, takes_files);
  capz::check_output_free(dir.file("b"), true, takes_files);
  capz::check_output_free(dir.file("absent"), false, takes_files);
  EXPECT_EQ(g_asked, 0);
  capz::check_output_free(dir.file("a"), false, takes_files);  // takes files: no error
  EXPECT_EQ(g_asked, 1);
  EXPECT_THROW(capz::check_output_free(dir.file("b"), false, takes_files), capz::Error);
  EXPECT_EQ(g_asked, 2);
  EXPECT_THROW(capz::check_output_free(dir.file("a"), false), capz::Error);
}

// frames_go_beside's rule, entry by entry (readdir's types, a stat only where they are unknown):
// subfolders, hidden entries and regular .capz files in any case; not a symbolic link (to a
// folder or to an archive), a FIFO, another file; not a symbolic link to such a folder itself.
TEST(AtomicDirBeside, GivenEachKindOfEntryThenFramesGoBesideOnlyAmongArchivesAndFolders) {
  capz_test::TempDir dir;
  const fs::path a = dir.path() / "a";
  fs::create_directories(a / "sub");
  capz_test::put(a / "x.capz", "archive");
  capz_test::put(a / "Y.CAPZ", "archive");
  capz_test::put(a / ".hidden", "anything");
  fs::create_directories(a / ".git");
  EXPECT_TRUE(capz::frames_go_beside(a.string()));
  EXPECT_TRUE(capz::frames_go_beside(a.string() + "/"));
  fs::create_directory_symlink(a, dir.path() / "link");
  EXPECT_FALSE(capz::frames_go_beside(dir.file("link")));  // the folder itself a link
  const auto fails_with = [&](const fs::path& extra, const std::function<void()>& make) {
    make();
    EXPECT_FALSE(capz::frames_go_beside(a.string())) << extra;
    fs::remove(extra);
    EXPECT_TRUE(capz::frames_go_beside(a.string())) << extra;
  };
  fails_with(a / "l.capz", [&] { fs::create_symlink(a / "x.capz", a / "l.capz"); });
  fails_with(a / "ld", [&] { fs::create_directory_symlink(a / "sub", a / "ld"); });
  fails_with(a / "f.capz", [&] { ASSERT_EQ(::mkfifo((a / "f.capz").c_str(), 0600), 0); });
  fails_with(a / "0.pcd", [&] { capz_test::put(a / "0.pcd", "frame"); });
  EXPECT_FALSE(capz::frames_go_beside(dir.file("absent")));
  EXPECT_FALSE(capz::frames_go_beside((a / "x.capz").string()));  // a file, not a folder
}
