// Memory of ragged takes (frames of their own point counts) bounded by a window, not by the
// take (docs/STREAMING.md): compress_stream on a folder of PCD sweeps, reading the archive back
// a window at a time, decompressing it to a PCD or a PLY folder (write_frames, as
// `capz decompress -o DIR/` does) and converting the folder between PCD, PLY and .bin frames
// (write_frames of open_frames, as `capz convert` does) peak at about the same heap for 4 frames
// as for 32. The heap is counted by the allocation hooks of this executable (alloc_counter.h);
// no time is measured.
#include <gtest/gtest.h>
#include <unistd.h>

#include <cmath>
#include <cstdio>
#include <cstring>
#include <filesystem>
#include <fstream>
#include <functional>
#include <memory>
#include <string>
#include <vector>

#include "alloc_counter.h"
#include "capz/codec.h"
#include "capz/stream.h"

namespace fs = std::filesystem;

namespace {

// A folder of `frames` binary PCD sweeps of a 16-beam spinning sensor, x y z intensity (F4)
// and `extra` F8 fields more (t0, t1, ...), frame f holding 3000 + 97 (f mod 4) points (a ragged
// take whose first 4 frames already have every count: a longer take's windows are no larger);
// NaN points now and then.
fs::path write_sweeps(const std::string& name, size_t frames, size_t extra = 0) {
  // Named for this process too: ctest -j runs this executable's tests side by side.
  const fs::path dir =
      fs::temp_directory_path() / ("capz_stream_mem_" + name + "_" + std::to_string(::getpid()));
  fs::remove_all(dir);
  fs::create_directories(dir);
  for (size_t f = 0; f < frames; ++f) {
    const size_t n = 3000 + 97 * (f % 4);
    std::vector<float> v;
    for (size_t i = 0; i < n; ++i) {
      const double az = 2 * M_PI * static_cast<double>(i / 16) / static_cast<double>(n / 16 + 1);
      const double el = (static_cast<double>(i % 16) - 7.5) * 0.035;
      const double r = 8 + 3 * std::sin(3 * az + 0.01 * static_cast<double>(f)) + 0.1 * (i % 5);
      const bool gap = i % 97 == 5;
      const float nan = std::nanf("");
      v.push_back(gap ? nan : static_cast<float>(r * std::cos(el) * std::cos(az)));
      v.push_back(gap ? nan : static_cast<float>(r * std::cos(el) * std::sin(az)));
      v.push_back(gap ? nan : static_cast<float>(r * std::sin(el)));
      v.push_back(static_cast<float>((i * 7 + f) % 256));
      for (size_t k = 0; k < extra; ++k) {  // an F8 as two floats' bytes
        const double t = static_cast<double>(f) + 1e-5 * static_cast<double>(i * (k + 1));
        float two[2];
        std::memcpy(two, &t, sizeof t);
        v.insert(v.end(), two, two + 2);
      }
    }
    char file[32];
    std::snprintf(file, sizeof file, "sweep_%04zu.pcd", f);
    std::string names = "x y z intensity", sizes = "4 4 4 4", types = "F F F F", counts = "1 1 1 1";
    for (size_t k = 0; k < extra; ++k)
      names += " t" + std::to_string(k), sizes += " 8", types += " F", counts += " 1";
    std::ofstream o(dir / file, std::ios::binary);
    o << "# .PCD v0.7\nVERSION 0.7\nFIELDS " << names << "\nSIZE " << sizes << "\nTYPE " << types
      << "\nCOUNT " << counts << "\nWIDTH " << n << "\nHEIGHT 1\nVIEWPOINT 0 0 0 1 0 0 0\nPOINTS "
      << n << "\nDATA binary\n";
    o.write(reinterpret_cast<const char*>(v.data()),
            static_cast<std::streamsize>(v.size() * sizeof(float)));
  }
  return dir;
}

struct Peaks {
  int64_t encode = 0, decode = 0, pcd_folder = 0, ply_folder = 0;
  int64_t pcd_to_ply = 0, ply_to_bin = 0, bin_to_pcd = 0;  // convert
};

// The heap peak of writing the frames `open` gives to the folder `dir` (replaced) in `format`,
// `block` frames at a time (0: the source's preferred block), as the CLI does; the folder then
// holds one file a frame.
int64_t folder_peak(const std::function<std::unique_ptr<capz::FrameSource>()>& open,
                    const fs::path& dir, capz::Format format, const std::string& ext,
                    size_t block = 0) {
  int64_t peak = 0;
  size_t frames = 0;
  {
    capz_test::AllocScope scope;
    std::unique_ptr<capz::FrameSource> src = open();
    frames = src->header().frames;
    capz::WriteOptions wo;
    wo.overwrite = true;
    wo.folder_format = format;
    capz::write_frames(*src, dir.string() + "/", wo, block);
    peak = scope.report().peak_bytes;
  }
  size_t files = 0;
  for (const fs::directory_entry& e : fs::directory_iterator(dir))
    files += e.path().extension() == ext;
  EXPECT_EQ(files, frames) << dir;
  return peak;
}

// The heap peak of decompressing `archive` to the folder `dir` as `capz decompress` does.
int64_t decompress_peak(const std::string& archive, const fs::path& dir, capz::Format format,
                        const std::string& ext) {
  const int64_t peak =
      folder_peak([&archive] { return capz::open_capz_frames(archive); }, dir, format, ext);
  fs::remove_all(dir);
  return peak;
}

// The heap peaks of `capz convert` (open_frames, write_frames; 4 frames a block where the CLI
// reads 16, so that the 4-frame take is one block) from the PCD folder `dir` to PLY frames, from
// those to .bin frames, and from those back to PCD frames.
void convert_peaks(const fs::path& dir, Peaks* p) {
  const fs::path ply = dir.string() + "_ply", bin = dir.string() + "_bin",
                 pcd = dir.string() + "_pcd";
  const auto from = [](const fs::path& in) {
    return [in] { return capz::open_frames(in.string()); };
  };
  p->pcd_to_ply = folder_peak(from(dir), ply, capz::Format::kPLYFolder, ".ply", 4);
  p->ply_to_bin = folder_peak(from(ply), bin, capz::Format::kBinFolder, ".bin", 4);
  p->bin_to_pcd = folder_peak(from(bin), pcd, capz::Format::kPCDFolder, ".pcd", 4);
  for (const fs::path& d : {ply, bin, pcd}) fs::remove_all(d);
}

// The heap peak of compressing the folder to `out` in windows of `window` frames (the
// self-check on, fields kept unless `drop`: --drop-fields).
int64_t encode_peak(const fs::path& dir, const std::string& out, bool lossless, size_t window,
                    bool drop = false) {
  capz_test::AllocScope scope;
  std::unique_ptr<capz::FrameSource> src = capz::open_frames(dir.string());
  capz::CompressOptions opts;
  opts.window_frames = window;
  opts.drop_fields = drop;
  if (lossless)
    opts.lossless = true;
  else
    opts.max_error = 1e-3;
  capz::compress_stream(*src, opts, out, true);
  return scope.report().peak_bytes;
}

// The heap peaks of compressing the folder (windows of 2 frames) and of reading the archive
// back window by window.
Peaks peaks_of(const fs::path& dir, bool lossless) {
  const std::string out = dir.string() + ".capz";
  Peaks p;
  p.encode = encode_peak(dir, out, lossless, 2);
  {
    capz_test::AllocScope scope;
    std::unique_ptr<capz::FrameSource> dec = capz::open_capz_frames(out);
    capz::FrameBlock b;
    const size_t block = dec->preferred_block();
    for (size_t f = 0; f < dec->header().frames; f += block) dec->read(f, block, &b);
    p.decode = scope.report().peak_bytes;
  }
  if (!lossless) {  // the PLY folder: no PLY layout in the header, the coordinates are prescanned
    p.pcd_folder = decompress_peak(out, dir.string() + "_pcd", capz::Format::kPCDFolder, ".pcd");
    p.ply_folder = decompress_peak(out, dir.string() + "_ply", capz::Format::kPLYFolder, ".ply");
    convert_peaks(dir, &p);
  }
  fs::remove(out);
  return p;
}

void expect_window_bounded(bool lossless) {
  const fs::path few = write_sweeps("few", 4), many = write_sweeps("many", 32);
  const Peaks a = peaks_of(few, lossless), b = peaks_of(many, lossless);
  std::printf("peak heap: 4 frames encode %lld, decode %lld; 32 frames encode %lld, decode %lld\n",
              static_cast<long long>(a.encode), static_cast<long long>(a.decode),
              static_cast<long long>(b.encode), static_cast<long long>(b.decode));
  // A take held whole would need 8x the frames' bytes (about 60 bytes a point: 400 KB a frame
  // read and coded); a window-bounded one the same, give or take the per-frame metadata (names,
  // offsets, index entries: under 1 KB a frame).
  const int64_t slack = int64_t{256} << 10;
  EXPECT_LT(b.encode, a.encode + a.encode / 4 + slack);
  EXPECT_LT(b.decode, a.decode + a.decode / 4 + slack);
  if (!lossless) {
    std::printf(
        "decompress to a folder: 4 frames PCD %lld, PLY %lld; 32 frames PCD %lld, PLY "
        "%lld\n",
        static_cast<long long>(a.pcd_folder), static_cast<long long>(a.ply_folder),
        static_cast<long long>(b.pcd_folder), static_cast<long long>(b.ply_folder));
    EXPECT_LT(b.pcd_folder, a.pcd_folder + a.pcd_folder / 4 + slack);
    EXPECT_LT(b.ply_folder, a.ply_folder + a.ply_folder / 4 + slack);
    std::printf(
        "convert: 4 frames PCD->PLY %lld, PLY->bin %lld, bin->PCD %lld; 32 frames %lld, %lld, "
        "%lld\n",
        static_cast<long long>(a.pcd_to_ply), static_cast<long long>(a.ply_to_bin),
        static_cast<long long>(a.bin_to_pcd), static_cast<long long>(b.pcd_to_ply),
        static_cast<long long>(b.ply_to_bin), static_cast<long long>(b.bin_to_pcd));
    EXPECT_LT(b.pcd_to_ply, a.pcd_to_ply + a.pcd_to_ply / 4 + slack);
    EXPECT_LT(b.ply_to_bin, a.ply_to_bin + a.ply_to_bin / 4 + slack);
    EXPECT_LT(b.bin_to_pcd, a.bin_to_pcd + a.bin_to_pcd / 4 + slack);
  }
  fs::remove_all(few);
  fs::remove_all(many);
}

}  // namespace

TEST(ScanStreamMemory, RaggedFolderAtABoundPeaksAsAShortOne) {
  expect_window_bounded(false);
}

// --lossless adds the frame files' residue (HASH over every file, PCDP per window).
TEST(ScanStreamMemory, RaggedFolderLosslessPeaksAsAShortOne) {
  expect_window_bounded(true);
}

// Peaks a (the reference) and b, printed, with b at most 5 % and 64 KiB above a.
void expect_peak_as(const char* what, int64_t a, int64_t b) {
  std::printf("peak heap, %s: %lld against %lld\n", what, static_cast<long long>(b),
              static_cast<long long>(a));
  EXPECT_LT(b, a + a / 20 + (int64_t{64} << 10)) << what;
}

// A window's self-check decode is not kept while the next window is coded (WindowChecks::release):
// 16 frames in windows of 4 peak as 4 frames in one window. Kept, it added about 27 bytes a
// point of a window to every later window's coding.
TEST(ScanStreamMemory, LaterWindowsPeakAsTheFirst) {
  const fs::path one = write_sweeps("one", 4), four = write_sweeps("four", 16);
  const std::string out = one.string() + ".capz";
  expect_peak_as("16 frames in four windows against 4 in one", encode_peak(one, out, false, 4),
                 encode_peak(four, out, false, 4));
  fs::remove(out);
  fs::remove_all(one);
  fs::remove_all(four);
}

// --drop-fields: the fields a window does not code are freed before its coding (but a ring or
// distance field, which steers the encoder: keep_hint_fields). 4 frames with four F8 fields more
// (32 bytes a point) peak as 4 frames without them; held, they added those bytes a point of the
// window to the coding's peak.
TEST(ScanStreamMemory, DroppedFieldsAreNotHeldWhileCoding) {
  const fs::path lean = write_sweeps("lean", 4), fat = write_sweeps("fat", 4, 4);
  const std::string out = lean.string() + ".capz";
  expect_peak_as("--drop-fields, four F8 fields more against none",
                 encode_peak(lean, out, false, 4, true), encode_peak(fat, out, false, 4, true));
  fs::remove(out);
  fs::remove_all(lean);
  fs::remove_all(fat);
}
