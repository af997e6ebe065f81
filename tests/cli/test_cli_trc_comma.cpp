// Comma-separated TRC files (issue #38; data/comma_trc/, made by data/make_comma_trc.py from
// data/std_walking5_markers.trc): `info`, `compress`, `convert` and `decompress` take them,
// --lossless gives them back byte for byte at no more than the tab form's cost, `decompress` keeps
// the commas and `convert` writes tabs unless --trc-delimiter comma asks otherwise.
#include <gtest/gtest.h>

#include <filesystem>
#include <string>

#include "capz/io.h"
#include "capz/tool/file.h"
#include "test_util.h"

namespace fs = std::filesystem;

namespace {

using Result = capz_test::CliResult;

Result run(const std::string& args) {
  static capz_test::TempDir io("capz_cli_trc_comma_io");
  return capz_test::run_command(CAPZ_CLI, args, io.file("out"));
}

const std::string kData = CAPZ_REPO_DATA;
const char* const kVariants[] = {"pyomeca", "sheet", "sheet-crlf", "sheet-gen"};

std::string variant(const std::string& v) {
  return kData + "/comma_trc/std_walking5_markers." + v + ".trc";
}

std::string text_of(const std::string& path) {
  const std::vector<uint8_t> b = capz::read_file(path);
  return std::string(b.begin(), b.end());
}

}  // namespace

TEST(CliTrcComma, InfoReadsTheCommaForms) {
  for (const char* v : kVariants) {
    Result r = run("info '" + variant(v) + "'");
    ASSERT_EQ(r.status, 0) << v << ": " << r.out;
    EXPECT_NE(r.out.find("points:    40"), std::string::npos) << r.out;
    EXPECT_NE(r.out.find("frames:    112"), std::string::npos) << r.out;
    Result p = run("info --parameters '" + variant(v) + "'");
    ASSERT_EQ(p.status, 0) << p.out;
    EXPECT_NE(p.out.find("PathFileType        4 (X/Y/Z) ds_std_walking5_markers.trc\n"),
              std::string::npos)
        << p.out;
  }
}

TEST(CliTrcComma, LosslessGivesEachFormBackAtNoMoreThanTheTabForm) {
  capz_test::TempDir d("capz_cli_trc_comma");
  const std::string tab = kData + "/std_walking5_markers.trc";
  ASSERT_EQ(run("compress -q --lossless '" + tab + "' -o '" + d.file("tab.capz") + "'").status, 0);
  const uint64_t tab_size = fs::file_size(d.file("tab.capz"));
  for (const char* v : kVariants) {
    // The same take saved with commas, under the tab file's name (META keeps the name).
    fs::create_directories(d.file(v));
    const std::string in = d.file(std::string(v) + "/std_walking5_markers.trc");
    fs::copy_file(variant(v), in);
    const std::string z = d.file(std::string(v) + ".capz"), back = d.file(std::string(v) + ".trc");
    Result c = run("compress -q --lossless '" + in + "' -o '" + z + "'");
    ASSERT_EQ(c.status, 0) << v << ": " << c.out;
    ASSERT_EQ(run("decompress -q '" + z + "' -o '" + back + "'").status, 0);
    EXPECT_EQ(capz::read_file(back), capz::read_file(variant(v))) << v;
    // Issue #38: no more than the tab form. The padding is a width and CRLF a flag (FORMAT.md
    // 14.5), not bytes per line or per window.
    EXPECT_LE(fs::file_size(z), tab_size) << v << " vs the tab form's " << tab_size;
  }
}

TEST(CliTrcComma, DecompressKeepsCommasConvertWritesTabsUnlessAsked) {
  capz_test::TempDir d("capz_cli_trc_comma2");
  const std::string src = variant("pyomeca"), z = d.file("p.capz");
  ASSERT_EQ(run("compress -q -e 0.01mm '" + src + "' -o '" + z + "'").status, 0);
  ASSERT_EQ(run("decompress -q '" + z + "' -o '" + d.file("kept.trc") + "'").status, 0);
  EXPECT_EQ(text_of(d.file("kept.trc")).substr(0, 23), "PathFileType,4,(X/Y/Z),");
  ASSERT_EQ(
      run("decompress -q --trc-delimiter tab '" + z + "' -o '" + d.file("tabs.trc") + "'").status,
      0);
  EXPECT_EQ(text_of(d.file("tabs.trc")).find(','), std::string::npos);

  ASSERT_EQ(run("convert -q '" + src + "' '" + d.file("c.trc") + "'").status, 0);
  const std::string c = text_of(d.file("c.trc"));
  EXPECT_EQ(c.find(','), std::string::npos) << c.substr(0, 200);
  EXPECT_EQ(c.substr(0, 16), "PathFileType\t4\t(");
  ASSERT_EQ(run("convert -q --trc-delimiter comma '" + d.file("c.trc") + "' '" +
                d.file("again.trc") + "'")
                .status,
            0);
  capz::Take a = capz::read_trc(src), b = capz::read_trc(d.file("c.trc")),
             e = capz::read_trc(d.file("again.trc"));
  capz_test::expect_same_samples(a, b);
  capz_test::expect_same_samples(a, e);
  EXPECT_EQ(text_of(d.file("again.trc")).substr(0, 23), "PathFileType,4,(X/Y/Z),");
  Result bad = run("convert -q --trc-delimiter semicolon '" + src + "' '" + d.file("x.trc") + "'");
  EXPECT_NE(bad.status, 0);
  EXPECT_FALSE(fs::exists(d.file("x.trc")));
}
