// `capz compress`, `verify` and `decompress` on a folder of PCD frames of their own point counts
// with point fields (docs/FORMAT.md "Scans (format 1.1)": point fields of a ragged window), run
// through the built binary: the fields are kept, verify finds no difference, and a changed field
// value in the original is reported.
#include <gtest/gtest.h>
#include <sys/wait.h>

#include <cmath>
#include <cstdlib>
#include <filesystem>
#include <fstream>
#include <string>

#include "capz/io.h"
#include "test_util.h"

namespace {

namespace fs = std::filesystem;

// Runs `capz <args>`; returns the exit status, stdout and stderr into *out.
int capz_run(const std::string& args, const capz_test::TempDir& dir, std::string* out) {
  const capz_test::CliResult r = capz_test::run_command(CAPZ_CLI, args, dir.file("stdout"));
  *out = r.out;
  return r.status;
}

// An ASCII PCD frame of n points on a helix with intensity (F4), ring (U2) and a per-point time
// (F8); point 1 NaN. `bump` adds 1 to the intensity of point 5.
void write_frame(const std::string& path, size_t n, double phase, bool bump = false) {
  std::ofstream f(path);
  f << "# .PCD v0.7\nVERSION 0.7\nFIELDS x y z intensity ring time\nSIZE 4 4 4 4 2 8\n"
    << "TYPE F F F F U F\nCOUNT 1 1 1 1 1 1\nWIDTH " << n
    << "\nHEIGHT 1\nVIEWPOINT 0 0 0 1 0 0 0\nPOINTS " << n << "\nDATA ascii\n";
  f.precision(17);
  for (size_t i = 0; i < n; ++i) {
    const double a = phase + 0.013 * static_cast<double>(i);
    const int intensity = static_cast<int>(i * 7 % 101) + (bump && i == 5 ? 1 : 0);
    const double time = 1.69e9 + 1e-5 * static_cast<double>(i);
    if (i == 1)
      f << "nan nan nan";
    else
      f << 20 * std::cos(a) << " " << 20 * std::sin(a) << " " << 0.001 * static_cast<double>(i);
    f << " " << intensity << " " << i % 16 << " " << time << "\n";
  }
}

TEST(CliScanFields, FieldsOfFramesOfTheirOwnSizeAreKeptAndVerified) {
  capz_test::TempDir dir("capz_cli_scan_fields");
  const std::string in = dir.file("scan"), other = dir.file("other");
  fs::create_directories(in);
  fs::create_directories(other);
  write_frame(in + "/0001.pcd", 300, 0.0);
  write_frame(in + "/0002.pcd", 417, 0.5);
  write_frame(other + "/0001.pcd", 300, 0.0);
  write_frame(other + "/0002.pcd", 417, 0.5, true);
  const std::string z = dir.file("s.capz");
  std::string out;
  ASSERT_EQ(capz_run("compress " + in + " -o " + z + " --max-error 1mm", dir, &out), 0) << out;
  ASSERT_EQ(capz_run("info " + z, dir, &out), 0) << out;
  EXPECT_NE(out.find("intensity F4, ring U2, time F8"), std::string::npos) << out;
  EXPECT_NE(out.find("ATTR"), std::string::npos) << out;
  ASSERT_EQ(capz_run("verify " + z + " --against " + in, dir, &out), 0) << out;
  EXPECT_NE(out.find("holds"), std::string::npos) << out;
  EXPECT_EQ(out.find("differ"), std::string::npos) << out;
  // One intensity changed in the original: verify names the fields.
  EXPECT_NE(capz_run("verify " + z + " --against " + other, dir, &out), 0) << out;
  EXPECT_NE(out.find("point fields"), std::string::npos) << out;
  ASSERT_EQ(capz_run("decompress " + z + " -o " + dir.file("back") + "/", dir, &out), 0) << out;
  const capz::Take a = capz::read_take(in), b = capz::read_take(dir.file("back"));
  ASSERT_TRUE(b.ragged());
  ASSERT_EQ(b.frame_offsets, a.frame_offsets);
  ASSERT_EQ(b.valid, a.valid);
  ASSERT_EQ(b.attributes.size(), 3u);
  for (size_t k = 0; k < 3; ++k) EXPECT_EQ(b.attributes[k].data, a.attributes[k].data) << k;
  // --frames: the second frame alone, its fields those of the source's second frame.
  ASSERT_EQ(capz_run("decompress " + z + " --frames 1:2 -o " + dir.file("one") + "/", dir, &out), 0)
      << out;
  const capz::Take c = capz::read_take(dir.file("one"));
  ASSERT_EQ(c.total_points(), 417u);
  const size_t bpp = a.attributes[2].bytes_per_point();
  EXPECT_TRUE(std::equal(c.attributes[2].data.begin(), c.attributes[2].data.end(),
                         a.attributes[2].data.begin() + static_cast<std::ptrdiff_t>(300 * bpp)));
}

}  // namespace
