// `capz compress -T N` and `capz decompress -T N`: the same files and reports for every N, and a
// corrupt window decoded by a worker is the one-line error (exit status 5) a serial run gives.
#include <gtest/gtest.h>

#include <algorithm>
#include <filesystem>
#include <string>
#include <vector>

#include "capz/tool/file.h"
#include "coding/container.h"
#include "test_util.h"

namespace {

using Result = capz_test::CliResult;

Result run(const capz_test::TempDir& dir, const std::string& args) {
  return capz_test::run_command(CAPZ_CLI, args, dir.file("cli.out"));
}

TEST(ThreadsCli, SameFilesAndReportsForEveryThreadCount) {
  if (!std::filesystem::exists(CAPZ_CLI)) GTEST_SKIP() << "capz CLI not built: " << CAPZ_CLI;
  capz_test::TempDir d("capz_threads_cli");
  const std::string in = std::string(CAPZ_REPO_DATA) + "/admarche2.c3d";
  std::vector<std::string> reports;
  for (const char* t : {"1", "2", "0"}) {
    const std::string z = d.file(std::string("t") + t + ".capz");
    const Result r = run(d, "compress '" + in + "' -o '" + z + "' --window 64 -T " + t);
    ASSERT_EQ(r.status, 0) << r.out;
    // The report names the output file; the rest must match (after the reader's warning).
    EXPECT_NE(r.out.find("capz compress: warning: "), std::string::npos) << r.out;
    const std::string report = capz_test::without_warnings(r.out);
    reports.push_back(report.substr(report.find(':')));
    EXPECT_TRUE(capz::read_file(z) == capz::read_file(d.file("t1.capz"))) << "-T " << t;
    EXPECT_EQ(reports.back(), reports.front()) << "-T " << t;
    const std::string c3d = d.file(std::string("t") + t + ".c3d");
    const Result dr = run(d, "decompress '" + d.file("t1.capz") + "' -o '" + c3d + "' -T " + t);
    ASSERT_EQ(dr.status, 0) << dr.out;
    EXPECT_TRUE(capz::read_file(c3d) == capz::read_file(d.file("t1.c3d"))) << "-T " << t;
    // Through the TRC writer, whose header names the file: one name, in a folder per count.
    const std::string folder = d.file(std::string("trc") + t);
    std::filesystem::create_directories(folder);
    const std::string trc = folder + "/take.trc";
    ASSERT_EQ(run(d, "decompress '" + d.file("t1.capz") + "' -o '" + trc + "' -T " + t).status, 0);
    EXPECT_TRUE(capz::read_file(trc) == capz::read_file(d.file("trc1/take.trc"))) << "-T " << t;
  }
  const Result bad = run(d, "compress '" + in + "' -o '" + d.file("x.capz") + "' -T -2");
  EXPECT_NE(bad.status, 0) << bad.out;
  EXPECT_FALSE(std::filesystem::exists(d.file("x.capz")));
}

TEST(ThreadsCli, CorruptWindowWithTwoThreadsIsTheSerialError) {
  if (!std::filesystem::exists(CAPZ_CLI)) GTEST_SKIP() << "capz CLI not built: " << CAPZ_CLI;
  capz_test::TempDir d("capz_threads_cli");
  const std::string in = std::string(CAPZ_REPO_DATA) + "/admarche2.c3d";
  const std::string z = d.file("a.capz");
  ASSERT_EQ(run(d, "compress '" + in + "' -o '" + z + "' --window 32").status, 0);
  std::vector<uint8_t> bytes = capz::read_file(z);
  // A byte inside the payload of the fourth POSW chunk: its CRC no longer holds.
  size_t off = capz::kFileHeaderBytes, n = 0, at = 0;
  while (off < bytes.size()) {
    const capz::Chunk c = capz::read_chunk(bytes.data(), bytes.size(), off, "a");
    if (c.type == "POSW" && n++ == 3) {
      at = static_cast<size_t>(c.payload - bytes.data()) + c.size / 2;
      break;
    }
    off = c.end;
  }
  ASSERT_GT(at, 0u);
  bytes[at] ^= 0x10;
  capz::write_file(z, bytes, true);
  std::string first;
  for (const char* t : {"1", "2", "8"}) {
    const std::string out = d.file(std::string("o") + t + ".trc");
    const Result r = run(d, "decompress '" + z + "' -o '" + out + "' -T " + t);
    EXPECT_EQ(r.status, 5) << r.out;
    EXPECT_EQ(std::count(r.out.begin(), r.out.end(), '\n'), 1) << r.out;
    EXPECT_NE(r.out.find("POSW"), std::string::npos) << r.out;
    EXPECT_FALSE(std::filesystem::exists(out)) << "partial output left with -T " << t;
    if (first.empty())
      first = r.out;
    else
      EXPECT_EQ(r.out, first) << "-T " << t;
  }
}

}  // namespace
