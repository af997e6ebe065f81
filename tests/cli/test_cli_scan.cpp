// `capz compress`, `info` and `decompress` on a folder of PCD frames of their own point counts
// (a ragged take, docs/FORMAT.md "Scans (format 1.1)"), run through the built binary; single frame
// files and negative zeros (the CliScanSingle tests).
#include <gtest/gtest.h>
#include <sys/wait.h>

#include <cmath>
#include <cstdlib>
#include <cstring>
#include <filesystem>
#include <fstream>
#include <string>

#include "capz/codec.h"
#include "capz/io.h"
#include "test_util.h"

namespace {

namespace fs = std::filesystem;

// Runs `capz <args>`; returns the exit status, stdout and stderr into *out.
int capz_run(const std::string& args, const capz_test::TempDir& dir, std::string* out) {
  const std::string o = dir.file("stdout");
  const int rc = std::system((std::string(CAPZ_CLI) + " " + args + " >" + o + " 2>&1").c_str());
  *out = capz_test::file_text(o);
  return WIFEXITED(rc) ? WEXITSTATUS(rc) : -1;
}

// An ASCII PCD frame of n points on a helix, point 1 NaN.
void write_frame(const std::string& path, size_t n, double phase) {
  std::ofstream f(path);
  f << "# .PCD v0.7\nVERSION 0.7\nFIELDS x y z\nSIZE 4 4 4\nTYPE F F F\nCOUNT 1 1 1\n"
    << "WIDTH " << n << "\nHEIGHT 1\nVIEWPOINT 0 0 0 1 0 0 0\nPOINTS " << n << "\nDATA ascii\n";
  for (size_t i = 0; i < n; ++i) {
    if (i == 1) {
      f << "nan nan nan\n";
      continue;
    }
    const double a = phase + 0.013 * static_cast<double>(i);
    f << 20 * std::cos(a) << " " << 20 * std::sin(a) << " " << 0.001 * static_cast<double>(i)
      << "\n";
  }
}

TEST(CliScan, CompressInfoDecompressAFolderOfFramesOfTheirOwnSize) {
  capz_test::TempDir dir("capz_cli_scan");
  const std::string in = dir.file("scan");
  fs::create_directories(in);
  write_frame(in + "/0001.pcd", 300, 0.0);
  write_frame(in + "/0002.pcd", 417, 0.5);
  std::string out;
  ASSERT_EQ(
      capz_run("compress " + in + " -o " + dir.file("s.capz") + " --max-error 1mm", dir, &out), 0)
      << out;
  ASSERT_EQ(capz_run("info " + dir.file("s.capz"), dir, &out), 0) << out;
  EXPECT_NE(out.find("2 frames of their own point counts, 717 points in all"), std::string::npos)
      << out;
  // PCD frames carry no units: metres assumed, as the compress line says, not "units unknown".
  EXPECT_NE(out.find("points in all, m (assumed: PCD frames carry no units"), std::string::npos)
      << out;
  EXPECT_NE(out.find("bound 0.001 m per coordinate"), std::string::npos) << out;
  EXPECT_EQ(out.find("units unknown"), std::string::npos) << out;
  ASSERT_EQ(
      capz_run("decompress " + dir.file("s.capz") + " -o " + dir.file("back") + "/", dir, &out), 0)
      << out;
  // The line gives the frames' total, not "2 frames x 0 points".
  EXPECT_NE(out.find(": 2 frames of their own point counts, 717 points in all"), std::string::npos)
      << out;
  EXPECT_EQ(out.find("x 0 points"), std::string::npos) << out;
  ASSERT_EQ(capz_run("decompress --json -f " + dir.file("s.capz") + " -o " + dir.file("back") + "/",
                     dir, &out),
            0)
      << out;
  EXPECT_NE(out.find("\"points\":0,\"total_points\":717"), std::string::npos) << out;
  const capz::Take a = capz::read_take(in), b = capz::read_take(dir.file("back"));
  ASSERT_TRUE(b.ragged());
  ASSERT_EQ(b.frame_offsets, a.frame_offsets);
  ASSERT_EQ(b.valid, a.valid);
  EXPECT_EQ(b.valid[1], 0);
  for (size_t i = 0; i < a.xyz.size(); ++i) {
    if (!a.valid[i / 3]) continue;
    EXPECT_LE(std::fabs(a.xyz[i] - b.xyz[i]), 0.001) << i;
  }
}

// --lossless (docs/FORMAT.md "Lossless ragged streams"): info names the original's size and
// hash, verify decodes it, test rebuilds the frame files in memory, decompress gives every frame
// file back byte for byte.
TEST(CliScan, LosslessGivesEveryFrameFileBackByteForByte) {
  capz_test::TempDir dir("capz_cli_scan_lossless");
  const std::string in = dir.file("scan");
  fs::create_directories(in);
  write_frame(in + "/0001.pcd", 300, 0.0);
  write_frame(in + "/0002.pcd", 417, 0.5);
  write_frame(in + "/0003.pcd", 52, 1.0);
  std::string out;
  const std::string z = dir.file("l.capz");
  ASSERT_EQ(capz_run("compress " + in + " -o " + z + " --lossless", dir, &out), 0) << out;
  EXPECT_NE(out.find("lossless (float32"), std::string::npos) << out;  // -bits, or a split
  ASSERT_EQ(capz_run("info " + z, dir, &out), 0) << out;
  EXPECT_NE(out.find("rebuilt byte for byte"), std::string::npos) << out;
  EXPECT_NE(out.find("3 frames of their own point counts, 769 points in all"), std::string::npos)
      << out;
  ASSERT_EQ(capz_run("verify " + z, dir, &out), 0) << out;
  EXPECT_NE(out.find("ok, 3 frames of their own point counts, 769 points in all"),
            std::string::npos)
      << out;
  ASSERT_EQ(capz_run("test " + z, dir, &out), 0) << out;
  EXPECT_NE(out.find("original rebuilt"), std::string::npos) << out;
  ASSERT_EQ(capz_run("decompress " + z + " -o " + dir.file("back") + "/", dir, &out), 0) << out;
  for (const char* name : {"0001.pcd", "0002.pcd", "0003.pcd"})
    EXPECT_EQ(capz_test::file_text(in + "/" + name),
              capz_test::file_text(dir.file("back") + "/" + name))
        << name;
  EXPECT_EQ(std::distance(fs::directory_iterator(dir.file("back")), fs::directory_iterator()), 3);
}

// capz verify --against the folder of an archive made with --drop-fields (data/scan_small, real
// sweeps with seven fields besides x y z, and data/lidar_small, frames of one count): the
// promise holds for what the archive keeps, and the fields left out are named as such, not
// reported as a difference. Without --drop-fields nothing is said of fields.
TEST(CliScan, VerifyNamesFieldsLeftOutByDropFieldsAndHolds) {
  capz_test::TempDir dir("capz_cli_scan_verify");
  for (const char* sample : {"scan_small", "lidar_small"}) {
    SCOPED_TRACE(sample);
    const std::string src = std::string(CAPZ_REPO_DATA) + "/" + sample;
    const std::string z = dir.file(std::string(sample) + ".capz");
    std::string out;
    ASSERT_EQ(
        capz_run("compress -f " + src + " -o " + z + " --max-error 1cm --drop-fields", dir, &out),
        0)
        << out;
    EXPECT_EQ(capz_run("verify " + z + " --against " + src, dir, &out), 0) << out;
    EXPECT_NE(out.find("bound 0.01 m holds"), std::string::npos) << out;
    EXPECT_EQ(out.find("DOES NOT HOLD"), std::string::npos) << out;
    EXPECT_NE(out.find(" not in the archive (left out by compress --drop-fields), not compared"),
              std::string::npos)
        << out;
    EXPECT_NE(out.find("fields: intensity "), std::string::npos) << out;
    EXPECT_EQ(capz_run("verify --json " + z + " --against " + src, dir, &out), 0) << out;
    EXPECT_NE(out.find("\"ok\":true"), std::string::npos) << out;
    EXPECT_NE(out.find("\"dropped_fields\":[\"intensity\","), std::string::npos) << out;
    EXPECT_EQ(capz_run("verify " + z, dir, &out), 0) << out;
    EXPECT_NE(out.find(std::string(sample) == "scan_small"
                           ? "ok, 4 frames of their own point counts, 7150 points in all"
                           : "ok, 6 frames x 512 points"),
              std::string::npos)
        << out;
  }
  // Fields kept: verify compares them and names none as left out.
  const std::string src = std::string(CAPZ_REPO_DATA) + "/lidar_small";
  std::string out;
  ASSERT_EQ(
      capz_run("compress -f " + src + " -o " + dir.file("k.capz") + " --max-error 1cm", dir, &out),
      0)
      << out;
  EXPECT_EQ(capz_run("verify " + dir.file("k.capz") + " --against " + src, dir, &out), 0) << out;
  EXPECT_EQ(out.find("not in the archive"), std::string::npos) << out;
  EXPECT_EQ(capz_run("verify --json " + dir.file("k.capz") + " --against " + src, dir, &out), 0)
      << out;
  EXPECT_NE(out.find("\"dropped_fields\":[]"), std::string::npos) << out;
}

// --point-order any: info says the order is not the source's, verify pairs the points as sets
// and holds, the default says "kept"; a bad value and --lossless are refused by name.
TEST(CliScan, PointOrderAnyIsShownVerifiedAndRefusedWithLossless) {
  capz_test::TempDir dir("capz_cli_scan_order");
  const std::string src = std::string(CAPZ_REPO_DATA) + "/scan_small";
  const std::string z = dir.file("any.capz"), k = dir.file("kept.capz");
  std::string out;
  ASSERT_EQ(
      capz_run("compress -f " + src + " -o " + z + " --max-error 1mm --point-order any", dir, &out),
      0)
      << out;
  ASSERT_EQ(capz_run("info " + z, dir, &out), 0) << out;
  EXPECT_NE(out.find("point order: reordered (--point-order any)"), std::string::npos) << out;
  ASSERT_EQ(capz_run("info --json " + z, dir, &out), 0) << out;
  EXPECT_NE(out.find("\"point_order\":\"reordered\""), std::string::npos) << out;
  EXPECT_EQ(capz_run("verify " + z + " --against " + src, dir, &out), 0) << out;
  EXPECT_NE(out.find("bound 0.001 m holds"), std::string::npos) << out;
  ASSERT_EQ(capz_run("compress -f " + src + " -o " + k + " --max-error 1mm", dir, &out), 0) << out;
  ASSERT_EQ(capz_run("info " + k, dir, &out), 0) << out;
  EXPECT_NE(out.find("point order: kept"), std::string::npos) << out;
  EXPECT_NE(capz_run("compress -f " + src + " -o " + z + " --max-error 1mm --point-order some", dir,
                     &out),
            0);
  EXPECT_NE(out.find("--point-order wants kept or any, got 'some'"), std::string::npos) << out;
  EXPECT_NE(
      capz_run("compress -f " + src + " -o " + z + " --lossless --point-order any", dir, &out), 0);
  EXPECT_NE(out.find("--point-order any with --lossless"), std::string::npos) << out;
}

// --point-order any on a folder of frames of one count, unorganized (data/lidar_small: 6 x 512
// points): the points are reordered as a scan's (they stayed in their order through the per-index
// coder alone), and verify against the fixed-size folder compares the frames as the ragged ones
// the archive decodes to (it refused: "6 frames of their own point counts ... 6 frames x 512").
TEST(CliScan, PointOrderAnyReordersFramesOfOneCountAndVerifyHolds) {
  capz_test::TempDir dir("capz_cli_scan_order_fixed");
  const std::string src = std::string(CAPZ_REPO_DATA) + "/lidar_small";
  const std::string z = dir.file("any.capz");
  std::string out;
  ASSERT_EQ(capz_run("compress -f " + src + " -o " + z + " --max-error 0.01 --point-order any", dir,
                     &out),
            0)
      << out;
  ASSERT_EQ(capz_run("info " + z, dir, &out), 0) << out;
  EXPECT_NE(out.find("point order: reordered (--point-order any)"), std::string::npos) << out;
  EXPECT_NE(out.find("windows:     1 of up to "), std::string::npos) << out;
  ASSERT_EQ(capz_run("list " + z, dir, &out), 0) << out;  // a ragged take's points: all of them
  EXPECT_NE(out.find("frames 6 points 3072 in all analog 0"), std::string::npos) << out;
  EXPECT_EQ(capz_run("verify " + z + " --against " + src, dir, &out), 0) << out;
  EXPECT_NE(out.find("bound 0.01 m holds"), std::string::npos) << out;
  ASSERT_EQ(capz_run("decompress " + z + " -o " + dir.file("back") + " -q", dir, &out), 0) << out;
  const std::string text = capz_test::file_text(dir.file("back/sweep_00003.pcd"));
  EXPECT_NE(text.find("WIDTH 512\nHEIGHT 1\n"), std::string::npos);
}

// --lossless --attr-error: the positions bit for bit and the named float fields within their
// bound, with no residue (the frame files cannot come back byte for byte; a residue spent the
// bound: the archive was larger than --lossless alone); verify holds; the other fields exact.
TEST(CliScan, LosslessWithAttrErrorKeepsPositionsBitsAndBoundsTheFields) {
  capz_test::TempDir dir("capz_cli_scan_lossless_attr");
  const std::string src = std::string(CAPZ_REPO_DATA) + "/lidar_small";
  const std::string z = dir.file("b.capz"), l = dir.file("l.capz");
  std::string out;
  ASSERT_EQ(capz_run("compress -f " + src + " -o " + z + " --lossless --attr-error intensity=0.01",
                     dir, &out),
            0)
      << out;
  ASSERT_EQ(capz_run("compress -f " + src + " -o " + l + " --lossless", dir, &out), 0) << out;
  EXPECT_LT(fs::file_size(z), fs::file_size(l));
  ASSERT_EQ(capz_run("info " + z, dir, &out), 0) << out;
  EXPECT_EQ(out.find("HASH"), std::string::npos) << out;
  EXPECT_EQ(capz_run("verify " + z + " --against " + src, dir, &out), 0) << out;
  const capz::Take a = capz::read_take(src);
  ASSERT_EQ(capz_run("decompress " + z + " -o " + dir.file("back") + " -q", dir, &out), 0) << out;
  const capz::Take b = capz::read_take(dir.file("back"));
  ASSERT_EQ(a.xyz.size(), b.xyz.size());
  for (size_t i = 0; i < a.xyz.size(); ++i) {
    if (a.valid[i / 3]) {
      ASSERT_EQ(a.xyz[i], b.xyz[i]) << i;
    }
  }
  for (size_t k = 0; k < a.attributes.size(); ++k) {
    if (a.attributes[k].name == "intensity") continue;
    EXPECT_EQ(a.attributes[k].data, b.attributes[k].data) << a.attributes[k].name;
  }
  // --analog-max-error on frames that hold no analog channel: a note, as for a fixed take; with
  // --lossless refused, as for a C3D (it was ignored without a word).
  ASSERT_EQ(capz_run("compress -f " + std::string(CAPZ_REPO_DATA) + "/scan_small -o " + z +
                         " --max-error 0.01 --analog-max-error V=0.1",
                     dir, &out),
            0)
      << out;
  EXPECT_NE(out.find("--analog-max-error V names no analog channel"), std::string::npos) << out;
  EXPECT_EQ(capz_run("compress -f " + std::string(CAPZ_REPO_DATA) + "/scan_small -o " + z +
                         " --lossless --analog-max-error V=0.1",
                     dir, &out),
            6)
      << out;
}

// --no-check on a scan folder: the windows are not decoded again, so the report's error is not
// measured (it was: each window was still decoded for the report, and --no-check saved nothing);
// the same archive as with the check, which verify then measures.
TEST(CliScan, NoCheckDoesNotDecodeAndSaysTheErrorIsNotMeasured) {
  capz_test::TempDir dir("capz_cli_scan_nocheck");
  const std::string src = std::string(CAPZ_REPO_DATA) + "/scan_small";
  const std::string a = dir.file("a.capz"), b = dir.file("b.capz");
  std::string out;
  ASSERT_EQ(capz_run("compress -f " + src + " -o " + a + " --max-error 1mm --no-check", dir, &out),
            0)
      << out;
  EXPECT_NE(out.find("max error not measured (--no-check), bound 0.001 m"), std::string::npos)
      << out;
  ASSERT_EQ(
      capz_run("compress -f " + src + " -o " + b + " --max-error 1mm --no-check --json", dir, &out),
      0)
      << out;
  EXPECT_NE(out.find("\"max_error_per_coordinate\":null"), std::string::npos) << out;
  ASSERT_EQ(capz_run("compress -f " + src + " -o " + b + " --max-error 1mm", dir, &out), 0) << out;
  EXPECT_NE(out.find("max error 0.000"), std::string::npos) << out;
  EXPECT_TRUE(capz_test::file_text(a) == capz_test::file_text(b));
  EXPECT_EQ(capz_run("verify " + a + " --against " + src, dir, &out), 0) << out;
  EXPECT_NE(out.find("bound 0.001 m holds"), std::string::npos) << out;
}

void put(const std::string& path, const std::string& bytes) {
  std::ofstream f(path, std::ios::binary);
  f << bytes;
}

// A frame's double x y z on the 0.01 grid, with negative zeros, as ascii PLY text or binary.
const char* const kRows[] = {"1.100000 -0.000000 2.250000", "-0 0.100000 -3.500000",
                             "0.000000 4.010000 -0.000000", "5.500000 -0.000000 7.750000"};

std::string ascii_ply(size_t n) {
  std::string s = "ply\nformat ascii 1.0\nelement vertex " + std::to_string(n) +
                  "\nproperty double x\nproperty double y\nproperty double z\nend_header\n";
  for (size_t i = 0; i < n; ++i) s += std::string(kRows[i]) + "\n";
  return s;
}

std::string binary_ply(size_t n) {
  std::string s = "ply\nformat binary_little_endian 1.0\nelement vertex " + std::to_string(n) +
                  "\nproperty double x\nproperty double y\nproperty double z\nend_header\n";
  for (size_t i = 0; i < n; ++i) {
    char a[32], b[32], c[32];
    if (std::sscanf(kRows[i], "%31s %31s %31s", a, b, c) != 3) return "";
    for (const char* t : {a, b, c}) {
      const double d = std::strtod(t, nullptr);
      char bytes[8];
      std::memcpy(bytes, &d, 8);
      s.append(bytes, 8);
    }
  }
  return s;
}

}  // namespace

// compress --rm of a single sweep (a real Helios 16P frame of data/scan_small) whose stream
// holds one ragged frame (the scan coder wins on it): the written archive read back decodes to
// the fixed one-frame take the reader gives the file, so the check passes and the input goes.
// Before, the check compared the stream's ragged header with the file's fixed one and kept it.
TEST(CliScan, RmOfASingleSweepCodedAsOneRaggedFrame) {
  capz_test::TempDir dir("capz_cli_scan_rm");
  const std::string in = dir.file("sweep.pcd"), z = dir.file("sweep.capz");
  fs::copy_file(std::string(CAPZ_REPO_DATA) + "/scan_small/1691031766781547066.pcd", in);
  std::string out;
  ASSERT_EQ(capz_run("compress " + in + " -o " + z + " --max-error 1mm --rm", dir, &out), 0) << out;
  EXPECT_FALSE(fs::exists(in));
  ASSERT_EQ(capz_run("info " + z, dir, &out), 0) << out;
  EXPECT_NE(out.find("SCNW"), std::string::npos) << out;  // the one-ragged-frame stream
}

// A single sweep coded losslessly as one ragged frame (SCNW) decompresses to its file byte for
// byte: its residue is rebuilt from the fixed one-frame take the stream reads as (a PCD layout
// as wide as its points; before, the rebuild wrote a header of no points and failed).
TEST(CliScan, LosslessSingleSweepComesBackByteForByte) {
  capz_test::TempDir dir("capz_cli_scan_one_lossless");
  const std::string in = std::string(CAPZ_REPO_DATA) + "/scan_small/1691031766781547066.pcd";
  const std::string z = dir.file("sweep.capz"), back = dir.file("back.pcd");
  std::string out;
  ASSERT_EQ(capz_run("compress -q " + in + " -o " + z + " --lossless", dir, &out), 0) << out;
  ASSERT_EQ(capz_run("info " + z, dir, &out), 0) << out;
  EXPECT_NE(out.find("SCNW"), std::string::npos) << out;  // the one-ragged-frame stream
  ASSERT_EQ(capz_run("decompress -q " + z + " -o " + back, dir, &out), 0) << out;
  EXPECT_EQ(capz_test::file_text(back), capz_test::file_text(in));
}

// `capz info` of a lossless ragged archive says what its windows' float32 split is (FORMAT.md
// "Lossless ragged streams"): the grid 2^-E of each split and how many windows use it, as the
// JSON's float32_split_windows counts them (key: E, -128 for plain float32 bits, -127 for raw
// windows: a window of 1,500-1,900 points may code smaller as LZMA2 of its bits, FORMAT.md "Raw
// windows"), rather than a bare "float32-bits". An archive at a bound has no split and says
// nothing of one.
TEST(CliScan, InfoDescribesTheFloat32SplitOfALosslessArchive) {
  capz_test::TempDir dir("capz_cli_scan_split_info");
  const std::string src = std::string(CAPZ_REPO_DATA) + "/scan_small", z = dir.file("s.capz");
  std::string out, json;
  ASSERT_EQ(capz_run("compress -q " + src + " -o " + z + " --lossless --window 1", dir, &out), 0)
      << out;
  ASSERT_EQ(capz_run("info --json " + z, dir, &json), 0) << json;
  ASSERT_EQ(capz_run("info " + z, dir, &out), 0) << out;
  const size_t at = json.find("\"float32_split_windows\":{");
  ASSERT_NE(at, std::string::npos) << json;
  const std::string counts = json.substr(at, json.find('}', at) - at);
  size_t windows = 0, plain = 0, grids = 0, raw = 0;
  for (size_t p = counts.find('{') + 1; p < counts.size();) {  // "E":n pairs
    const size_t q = counts.find('"', p + 1);
    const int e = std::stoi(counts.substr(p + 1, q - p - 1));
    const size_t n = std::stoul(counts.substr(q + 2));
    windows += n;
    if (e == capz::kPlainFloat32WindowsKey) {
      plain = n;
    } else if (e == capz::kRawWindowsKey) {  // raw windows (FORMAT.md "Raw windows")
      raw = n;
    } else {
      ++grids;
      EXPECT_NE(out.find((e > 0 ? "2^-" + std::to_string(e) : "2^" + std::to_string(-e)) + " ("),
                std::string::npos)
          << out;
    }
    p = counts.find(',', q);
    if (p == std::string::npos) break;
    ++p;
  }
  EXPECT_EQ(windows, 4u) << json;  // one window a frame
  ASSERT_GT(grids, 0u) << "no window of scan_small is split any more: " << json;
  EXPECT_NE(out.find("float32 split on the grid"), std::string::npos) << out;
  EXPECT_EQ(out.find("float32-bits") == std::string::npos, plain == 0) << out;
  EXPECT_EQ(
      out.find("raw bits through LZMA2 in " + std::to_string(raw) + " window") == std::string::npos,
      raw == 0)
      << out;
  if (grids > 1) {
    EXPECT_NE(out.find("float32 split on the grids"), std::string::npos) << out;
  }

  ASSERT_EQ(capz_run("compress -q -f " + src + " -o " + z + " -e 1mm", dir, &out), 0) << out;
  ASSERT_EQ(capz_run("info --json " + z, dir, &json), 0) << json;
  EXPECT_EQ(json.find("float32_split_windows"), std::string::npos) << json;
  ASSERT_EQ(capz_run("info " + z, dir, &out), 0) << out;
  EXPECT_EQ(out.find("float32 split"), std::string::npos) << out;
}

TEST(CliScanSingle, RaggedDoublePLYFoldersWithNegativeZerosComeBackByteForByte) {
  capz_test::TempDir dir("capz_cli_nz");
  std::string out;
  for (const char* form : {"ascii", "binary"}) {
    const std::string in = dir.file(form), back = dir.file(std::string(form) + "_back");
    fs::create_directories(in);
    for (size_t f = 0; f < 3; ++f)
      put(in + "/" + std::to_string(f) + ".ply",
          form[0] == 'a' ? ascii_ply(2 + f) : binary_ply(2 + f));
    const std::string z = dir.file(std::string(form) + ".capz");
    ASSERT_EQ(capz_run("compress " + in + " -o " + z + " --lossless", dir, &out), 0) << out;
    EXPECT_NE(out.find("lossless (decimal-grid)"), std::string::npos) << out;
    ASSERT_EQ(capz_run("decompress -q " + z + " -o " + back + "/", dir, &out), 0) << out;
    for (size_t f = 0; f < 3; ++f) {
      const std::string n = "/" + std::to_string(f) + ".ply";
      EXPECT_EQ(std::system(("cmp -s " + in + n + " " + back + n).c_str()), 0) << form << n;
    }
    ASSERT_EQ(capz_run("verify " + z + " --against " + in, dir, &out), 0) << out;
  }
}

// `capz info` of a one-frame archive coded by the scan coder (one ragged frame, SCNW) shows the
// fixed frame that decompress and every reader give: "1 frames x 4 points", JSON points 4 and an
// unorganized layout as wide, no "of their own point counts". With --lossless --rm the file goes
// once the archive rebuilds it (before, the check looked for a folder and kept the file).
TEST(CliScanSingle, OneFrameArchiveIsShownAsTheReaderGivesItAndRmChecksTheFile) {
  capz_test::TempDir dir("capz_cli_one");
  const std::string in = dir.file("one.pcd"), z = dir.file("one.capz"), back = dir.file("b.pcd");
  std::string text =
      "# .PCD v0.7\nVERSION 0.7\nFIELDS x y z\nSIZE 8 8 8\nTYPE F F F\nCOUNT 1 1 1\n"
      "WIDTH 4\nHEIGHT 1\nVIEWPOINT 0 0 0 1 0 0 0\nPOINTS 4\nDATA ascii\n";
  for (const char* row : kRows) text += std::string(row) + "\n";
  put(in, text);
  std::string out;
  ASSERT_EQ(capz_run("compress --lossless --rm " + in + " -o " + z, dir, &out), 0) << out;
  EXPECT_FALSE(fs::exists(in)) << out;
  ASSERT_EQ(capz_run("info " + z, dir, &out), 0) << out;
  EXPECT_NE(out.find("SCNW"), std::string::npos) << out;  // the one-ragged-frame stream
  EXPECT_NE(out.find("take:        1 frames x 4 points"), std::string::npos) << out;
  EXPECT_EQ(out.find("of their own point counts"), std::string::npos) << out;
  EXPECT_NE(out.find("layout:      unorganized"), std::string::npos) << out;
  ASSERT_EQ(capz_run("info --json " + z, dir, &out), 0) << out;
  EXPECT_NE(out.find("\"points\":4,"), std::string::npos) << out;
  EXPECT_NE(out.find("\"width\":4,"), std::string::npos) << out;
  ASSERT_EQ(capz_run("decompress -q " + z + " -o " + back, dir, &out), 0) << out;
  EXPECT_EQ(capz_test::file_text(back), text);
  ASSERT_EQ(capz_run("decompress --json -f " + z + " -o " + back, dir, &out), 0) << out;
  EXPECT_NE(out.find("\"points\":4,"), std::string::npos) << out;
}

// A PLY of x y z alone (no other property) compresses as one file, at a bound and losslessly;
// before, the scan coder's trial had no point layout for it ("frame-file source without a PCD
// layout").
TEST(CliScanSingle, PLYOfXYZAloneCompresses) {
  capz_test::TempDir dir("capz_cli_xyz_ply");
  const std::string in = dir.file("xyz.ply");
  put(in, ascii_ply(4));
  std::string out;
  ASSERT_EQ(capz_run("compress -e 1mm " + in + " -o " + dir.file("a.capz"), dir, &out), 0) << out;
  ASSERT_EQ(capz_run("compress --lossless " + in + " -o " + dir.file("l.capz"), dir, &out), 0)
      << out;
  ASSERT_EQ(capz_run("decompress -q " + dir.file("l.capz") + " -o " + dir.file("b.ply"), dir, &out),
            0)
      << out;
  EXPECT_EQ(capz_test::file_text(dir.file("b.ply")), capz_test::file_text(in));
}

// The compress line of a lossless folder whose windows take a float32 split names the grids as
// `capz info`'s coding line does, not a bare "float32-split".
TEST(CliScanSingle, CompressLineNamesTheFloat32SplitGrids) {
  capz_test::TempDir dir("capz_cli_split_line");
  const std::string src = std::string(CAPZ_REPO_DATA) + "/scan_small", z = dir.file("s.capz");
  std::string line, info;
  ASSERT_EQ(capz_run("compress " + src + " -o " + z + " --lossless --window 1", dir, &line), 0)
      << line;
  ASSERT_EQ(capz_run("info " + z, dir, &info), 0) << info;
  const size_t at = info.find("coding:      float32 split on the grid");
  ASSERT_NE(at, std::string::npos) << info;
  const size_t from = at + std::strlen("coding:      ");
  const std::string split = info.substr(from, info.find(", lossless", from) - from);
  EXPECT_NE(line.find("lossless (" + split + ")"), std::string::npos) << line << "\n" << split;
  EXPECT_EQ(line.find("(float32-split)"), std::string::npos) << line;
  ASSERT_EQ(
      capz_run("compress --json -f " + src + " -o " + z + " --lossless --window 1", dir, &line), 0)
      << line;
  EXPECT_NE(line.find("\"float32_split_windows\":{"), std::string::npos) << line;
}
