// `capz compress` and `decompress` of PLY and KITTI .bin frames (folders and single files,
// fixed and ragged takes; docs/FORMAT.md "Scans (format 1.1)", frame-file sources): the frames
// come back in their own format, under their own names, with their own PLY header, every
// coordinate within the bound after float32 rounding and every field byte for byte.
#include <gtest/gtest.h>
#include <sys/wait.h>

#include <cmath>
#include <cstdlib>
#include <cstring>
#include <filesystem>
#include <string>
#include <vector>

#include "capz/io.h"
#include "capz/tool/file.h"
#include "support/float32.h"
#include "test_util.h"

namespace {

namespace fs = std::filesystem;

int capz_run(const std::string& args, const capz_test::TempDir& dir, std::string* out) {
  const capz_test::CliResult r = capz_test::run_command(CAPZ_CLI, args, dir.file("stdout"));
  *out = r.out;
  return r.status;
}

// A take of frames with the given point counts (a spiral, point 1 of each frame a gap), with an
// intensity field, for the PLY and .bin writers.
capz::Take spiral(const std::vector<size_t>& counts, capz::Format format) {
  capz::Take t;
  t.format = format;
  capz_test::resize_frames(&t, counts);
  capz::PointAttribute in{"intensity", 'F', 4, 1, {}};
  for (size_t i = 0; i < t.total_points(); ++i) {
    const double a = 0.011 * static_cast<double>(i);
    t.xyz[3 * i] = capz_test::float32_value(25 * std::cos(a));
    t.xyz[3 * i + 1] = capz_test::float32_value(25 * std::sin(a));
    t.xyz[3 * i + 2] = static_cast<float>(-1.5 + 0.003 * static_cast<double>(i % 211));
    t.valid[i] = 1;
    const float v = static_cast<float>(i % 255) / 255.0f;
    uint8_t b[4];
    std::memcpy(b, &v, 4);
    in.data.insert(in.data.end(), b, b + 4);
  }
  for (size_t f = 0; f < t.frames; ++f)
    if (t.frame_points(f) > 1) t.valid[t.frame_begin(f) + 1] = 0;
  t.attributes = {in};
  if (format == capz::Format::kPLYFolder) {
    auto x = std::make_shared<capz::PLYExtra>();
    x->fields = {{"x", 'F', 4, 1}, {"y", 'F', 4, 1}, {"z", 'F', 4, 1}, {"intensity", 'F', 4, 1}};
    x->type_names = {"float", "float", "float", "float32"};
    x->comments = {"capz test frames"};
    x->obj_info = {"spiral"};
    t.ply = x;
  }
  return t;
}

// The bytes of a PLY file through its end_header line.
std::string ply_header(const std::string& path) {
  const std::string s = capz_test::file_text(path);
  const size_t e = s.find("end_header\n");
  return e == std::string::npos ? s : s.substr(0, e + 11);
}

std::vector<std::string> names_in(const std::string& dir) {
  std::vector<std::string> n;
  for (const auto& e : fs::directory_iterator(dir)) n.push_back(e.path().filename().string());
  std::sort(n.begin(), n.end());
  return n;
}

// `back` holds what `in` held: the same file names (a folder) and PLY headers, the same frames
// and gaps, every coordinate within `bound` (the files store float32), and with `fields` every
// field byte for byte.
void expect_same_frames(const std::string& in, const std::string& back, double bound, bool fields) {
  if (fs::is_directory(in)) {
    ASSERT_EQ(names_in(back), names_in(in));
    for (const std::string& n : names_in(in)) {
      if (n.size() > 4 && n.substr(n.size() - 4) == ".ply" && fields) {
        EXPECT_EQ(ply_header(back + "/" + n), ply_header(in + "/" + n)) << n;
      }
    }
  } else if (in.size() > 4 && in.substr(in.size() - 4) == ".ply" && fields) {
    EXPECT_EQ(ply_header(back), ply_header(in));
  }
  const capz::Take a = capz::read_take(in), b = capz::read_take(back);
  EXPECT_EQ(b.format, a.format);
  ASSERT_EQ(b.frames, a.frames);
  ASSERT_EQ(b.total_points(), a.total_points());
  for (size_t f = 0; f < a.frames; ++f) ASSERT_EQ(b.frame_points(f), a.frame_points(f)) << f;
  ASSERT_EQ(b.valid, a.valid);
  double worst = 0;
  for (size_t i = 0; i < a.xyz.size(); ++i)
    if (a.valid[i / 3]) worst = std::max(worst, std::fabs(a.xyz[i] - b.xyz[i]));
  EXPECT_LE(worst, bound);
  EXPECT_GT(worst, 0.0);  // a bound, not a lossless copy
  if (!fields) return;
  ASSERT_EQ(b.attributes.size(), a.attributes.size());
  for (size_t k = 0; k < a.attributes.size(); ++k)
    EXPECT_EQ(b.attributes[k].data, a.attributes[k].data) << a.attributes[k].name;
}

// compress IN at 1 mm (with `extra` options), decompress to BACK, compare.
void round_trip(const capz_test::TempDir& dir, const std::string& in, const std::string& back,
                const std::string& extra, bool fields) {
  SCOPED_TRACE(in);
  std::string out;
  std::string z = back;
  while (!z.empty() && z.back() == '/') z.pop_back();
  z += ".capz";
  ASSERT_EQ(capz_run("compress " + in + " -o " + z + " --max-error 1mm " + extra, dir, &out), 0)
      << out;
  ASSERT_EQ(capz_run("info " + z, dir, &out), 0) << out;
  const capz::Take a = capz::read_take(in);
  EXPECT_NE(out.find(capz::format_name(a.format)), std::string::npos) << out;
  // verify holds every field to the original: not for an archive without them.
  if (fields) {
    ASSERT_EQ(capz_run("verify " + z + " --against " + in, dir, &out), 0) << out;
  }
  ASSERT_EQ(capz_run("decompress " + z + " -o " + back, dir, &out), 0) << out;
  expect_same_frames(in, back, 0.001, fields);
}

TEST(CliScanFormats, PLYFoldersOfEachEncodingComeBackInTheirOwnFormat) {
  capz_test::TempDir dir("capz_cli_ply");
  for (const char* enc : {"ascii", "binary_little_endian", "binary_big_endian"}) {
    SCOPED_TRACE(enc);
    capz::WriteOptions wo;
    wo.ply_encoding = enc;
    wo.folder_format = capz::Format::kPLYFolder;
    const std::string fixed = dir.file(std::string("fixed_") + enc);
    capz::write_take(spiral({400, 400, 400}, capz::Format::kPLYFolder), fixed, wo);
    round_trip(dir, fixed, dir.file(std::string("fixed_back_") + enc) + "/", "", true);
    // A ragged take, with its fields and without them (--drop-fields).
    const std::string ragged = dir.file(std::string("ragged_") + enc);
    capz::write_take(spiral({400, 517, 3, 260}, capz::Format::kPLYFolder), ragged, wo);
    round_trip(dir, ragged, dir.file(std::string("ragged_back_") + enc) + "/", "", true);
    round_trip(dir, ragged, dir.file(std::string("ragged_xyz_") + enc) + "/", "--drop-fields",
               false);
  }
}

TEST(CliScanFormats, BinFoldersAndSingleFilesComeBackInTheirOwnFormat) {
  capz_test::TempDir dir("capz_cli_bin");
  capz::WriteOptions wo;
  wo.folder_format = capz::Format::kBinFolder;
  const std::string fixed = dir.file("fixed");
  capz::write_take(spiral({300, 300}, capz::Format::kBinFolder), fixed, wo);
  round_trip(dir, fixed, dir.file("fixed_back") + "/", "", true);
  const std::string ragged = dir.file("ragged");
  capz::write_take(spiral({300, 411, 90}, capz::Format::kBinFolder), ragged, wo);
  round_trip(dir, ragged, dir.file("ragged_back") + "/", "", true);
  round_trip(dir, ragged, dir.file("ragged_xyz") + "/", "--drop-fields", false);
  // --frames: the frames asked for, under their own names.
  std::string out;
  ASSERT_EQ(capz_run("decompress " + dir.file("ragged_back.capz") + " --frames 1:2 -o " +
                         dir.file("part") + "/",
                     dir, &out),
            0)
      << out;
  const std::vector<std::string> all = names_in(ragged);
  ASSERT_EQ(all.size(), 3u);
  EXPECT_EQ(names_in(dir.file("part")), std::vector<std::string>(all.begin() + 1, all.end()));
  // Single frame files: one-frame takes, back as one file.
  capz::write_take(spiral({350}, capz::Format::kBinFolder), dir.file("one.bin"), wo);
  round_trip(dir, dir.file("one.bin"), dir.file("one_back.bin"), "", true);
  capz::write_take(spiral({350}, capz::Format::kPLYFolder), dir.file("one.ply"),
                   capz::WriteOptions());
  round_trip(dir, dir.file("one.ply"), dir.file("one_back.ply"), "", true);
}

// --lossless on single PLY and .bin files (FORMAT.md "Lossless frame-file streams"): each comes
// back byte for byte as one file, a trailing byte after the binary PLY body included.
TEST(CliScanFormats, LosslessGivesPLYAndBinFilesBackByteForByte) {
  capz_test::TempDir dir("capz_cli_lossless");
  capz::write_take(spiral({20}, capz::Format::kBinFolder), dir.file("a.bin"), capz::WriteOptions());
  capz::write_take(spiral({20}, capz::Format::kPLYFolder), dir.file("a.ply"), capz::WriteOptions());
  std::vector<uint8_t> ply = capz::read_file(dir.file("a.ply"));
  ply.push_back('\n');
  capz::write_file(dir.file("a.ply"), ply, true);
  std::string out;
  for (const char* f : {"a.bin", "a.ply"}) {
    const std::string back = dir.file(std::string("back_") + f);
    ASSERT_EQ(capz_run("compress --lossless " + dir.file(f) + " -o " + dir.file("l.capz") + " -f",
                       dir, &out),
              0)
        << out;
    ASSERT_EQ(capz_run("decompress " + dir.file("l.capz") + " -o " + back + " -f", dir, &out), 0)
        << out;
    EXPECT_EQ(capz::read_file(back), capz::read_file(dir.file(f))) << f;
  }
}

// Shared real sweeps: three frames of the 64-beam sequence as ascii PLY, binary PLY and .bin
// folders (ragged; every field kept), and one Velodyne sweep as a PLY file with every field.
TEST(CliScanFormats, SharedSweepsAsPLYAndBinComeBackWithinTheBound) {
  const std::string seq = capz_test::shared_data_or_skip("scan/pandar64-factory20");
  if (seq.empty()) return;
  const std::string one = capz_test::shared_data_or_skip("scan/single/velodyne-vlp16.pcd");
  if (one.empty()) return;
  capz_test::TempDir dir("capz_cli_shared_ply");
  const std::string pcd = dir.file("pcd");
  fs::create_directories(pcd);
  for (const char* n : {"01.pcd", "02.pcd", "03.pcd"}) fs::copy_file(seq + "/" + n, pcd + "/" + n);
  const capz::Take t = capz::read_take(pcd);
  ASSERT_TRUE(t.ragged());
  capz::WriteOptions wo;
  wo.folder_format = capz::Format::kPLYFolder;
  wo.ply_encoding = "ascii";
  capz::write_take(t, dir.file("ply_ascii"), wo);
  round_trip(dir, dir.file("ply_ascii"), dir.file("ply_ascii_back") + "/", "", true);
  wo.ply_encoding = "binary_little_endian";
  capz::write_take(t, dir.file("ply_bin"), wo);
  round_trip(dir, dir.file("ply_bin"), dir.file("ply_bin_back") + "/", "", true);
  capz::WriteOptions bo;
  bo.folder_format = capz::Format::kBinFolder;
  bo.drop_fields = true;
  capz::write_take(t, dir.file("bin"), bo);
  round_trip(dir, dir.file("bin"), dir.file("bin_back") + "/", "", true);
  wo.ply_encoding = "ascii";
  capz::write_take(capz::read_take(one), dir.file("vlp16.ply"), wo);
  round_trip(dir, dir.file("vlp16.ply"), dir.file("vlp16_back.ply"), "", true);
}

}  // namespace

// convert streams frame files into the output's temporary folder as it reads them: a frame
// that fails to read after others were written (the last of 20 binary PCD frames truncated
// mid-point: its header is read when the folder is opened, its data when its block of 16 is)
// stops it with an error naming that file, and no output folder, nor a temporary one, is left.
TEST(CliScanFormats, ConvertOfAFolderWithABadLastFrameLeavesNothing) {
  capz_test::TempDir dir("capz_cli_convert_atomic");
  capz::WriteOptions wo;
  wo.pcd_encoding = "binary";
  const std::string in = dir.file("in");
  std::vector<size_t> counts;
  for (size_t f = 0; f < 20; ++f) counts.push_back(200 + 7 * f);
  capz::write_take(spiral(counts, capz::Format::kPCDFolder), in, wo);
  const std::vector<std::string> names = names_in(in);
  ASSERT_EQ(names.size(), 20u);
  const std::string last = in + "/" + names.back();
  fs::resize_file(last, fs::file_size(last) - 6);
  for (const char* to : {"pcd", "ply", "bin"}) {
    std::string out;
    const std::string o = dir.file(std::string("out_") + to);
    EXPECT_NE(capz_run(std::string("convert ") + in + " " + o + "/ --to " + to +
                           (std::string(to) == "bin" ? " --drop-fields" : ""),
                       dir, &out),
              0)
        << out;
    EXPECT_NE(out.find(names.back()), std::string::npos) << out;
    EXPECT_FALSE(fs::exists(o)) << o;
  }
  size_t left = 0;  // only the input folder and the command's output file
  for (const fs::directory_entry& e : fs::directory_iterator(dir.file("")))
    left += e.path().filename() != "in" && e.path().filename() != "stdout";
  EXPECT_EQ(left, 0u);
}

// convert's summary line gives a ragged folder's shape as info does: its frames of their own
// counts and the points in all.
TEST(CliScanFormats, ConvertOfARaggedFolderSaysItsShape) {
  capz_test::TempDir dir("capz_cli_convert_shape");
  const std::string in = dir.file("in");
  capz::write_take(spiral({300, 310, 320}, capz::Format::kPCDFolder), in, capz::WriteOptions());
  std::string out;
  ASSERT_EQ(capz_run("convert " + in + " " + dir.file("out") + "/ --to ply", dir, &out), 0) << out;
  EXPECT_NE(out.find("3 frames of their own point counts, 930 points in all"), std::string::npos)
      << out;
}

// A folder path named like a frame file but ending in '/' is a folder (CLI.md): convert to
// "out.ply/" and decompress to "back.pcd/" write folders of frames (they were refused as single
// files: "a .ply file holds one frame and the take has 3"); without the '/' it stays a file.
TEST(CliScanFormats, AFolderPathNamedLikeAFrameFileEndingInASlashIsAFolder) {
  capz_test::TempDir dir("capz_cli_slash_folder");
  const std::string in = dir.file("in");
  capz::write_take(spiral({300, 310, 320}, capz::Format::kPCDFolder), in, capz::WriteOptions());
  std::string out;
  ASSERT_EQ(capz_run("convert " + in + " " + dir.file("out.ply") + "/ --to ply", dir, &out), 0)
      << out;
  EXPECT_TRUE(fs::is_directory(dir.file("out.ply")));
  EXPECT_EQ(capz::read_take(dir.file("out.ply")).frames, 3u);
  ASSERT_EQ(
      capz_run("compress " + in + " -o " + dir.file("a.capz") + " --max-error 1mm", dir, &out), 0)
      << out;
  ASSERT_EQ(
      capz_run("decompress " + dir.file("a.capz") + " -o " + dir.file("back.pcd") + "/", dir, &out),
      0)
      << out;
  EXPECT_TRUE(fs::is_directory(dir.file("back.pcd")));
  EXPECT_NE(capz_run("convert " + in + " " + dir.file("one.ply"), dir, &out), 0);
  EXPECT_NE(out.find("holds one frame"), std::string::npos) << out;
}
