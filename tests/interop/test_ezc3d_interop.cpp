// Interoperability (issues #13, #14): every shared C3D file that ezc3d reads is compressed by
// capz from the file (lossless, and at 0.1 mm) and decompressed as `capz compress` and
// `capz decompress` do; ezc3d must read the same thing from capz's file as from the original:
// shape, header, parameters, analog samples bit for bit, gaps at the same places, residuals, and
// points exact (lossless) or within the bound. ezc3d is a test oracle only
// (tests/interop/ezc3d.cmake); capz keeps its own reader.
//
// Files ezc3d refuses are listed and skipped; so are files capz cannot read (listed apart).
// Differences capz is known to make are registered in kKnownBad with their issue: they are
// still checked (a file must show exactly the registered classes, no more, and an entry whose
// difference has gone away fails too, so the list is kept true).
#include <gtest/gtest.h>

#include <algorithm>
#include <cstdio>
#include <cstdlib>
#include <filesystem>
#include <string>
#include <vector>

#include "capz/codec.h"
#include "capz/error.h"
#include "capz/io.h"
#include "capz/stream.h"
#include "capz/tool/file.h"
#include "capz/tool/original.h"
#include "interop/ezc3d_compare.h"
#include "interop/ezc3d_snapshot.h"
#include "test_util.h"

namespace fs = std::filesystem;
using namespace capz_interop;

namespace {

// Why capz differs, one reason per cause found, with the issue that tracks it.
const char* const kUnits =
    "POINT:UNITS absent: a bound in mm needs --units (capz refuses rather than guess; the CLI's "
    "default bound for such files is relative to the data)";
const char* const kEmptyHeader =
    "the header says 0 points and 0 frames, so ezc3d reads nothing; capz reads 701 frames x 40 "
    "points from the parameters (#14)";
const char* const kLayoutDisagrees =
    "the header and the parameters disagree on the frame layout (points, analog values per "
    "frame); capz follows the parameters and ezc3d the header, so at a bound bytes that capz "
    "quantises as coordinates are analog samples or 4th words to ezc3d (lossless: byte for "
    "byte)";

// Differences capz makes today, per file (relative to the shared c3d folder) and mode
// ("lossless", "0.1mm", or "*" for both): the classes allowed, why, and the issue that tracks it.
struct KnownBad {
  const char* file;
  const char* mode;
  unsigned classes;
  std::vector<const char*> why;
};
const std::vector<KnownBad> kKnownBad = {
    {"btkdata/others/561xxa01_anonym.C3D", "0.1mm", kRefused, {kUnits}},
    {"c3dorg/sample_16/basketball.c3d", "0.1mm", kRefused, {kUnits}},
    {"c3dorg/sample_16/giant.c3d", "0.1mm", kRefused, {kUnits}},
    {"c3dorg/sample_16/golf.c3d", "0.1mm", kRefused, {kUnits}},
    {"c3dorg/sample_20/phasespace_sample.c3d", "0.1mm", kRefused, {kUnits, kEmptyHeader}},
    {"c3dorg/sample_27/kyowadengyo.c3d", "0.1mm", kAnalog, {kLayoutDisagrees}},
    {"c3dorg/sample_28/dynamic.C3D", "0.1mm", kRefused, {kUnits}},
    {"c3dorg/sample_28/standing.C3D", "0.1mm", kRefused, {kUnits}},
    {"c3dorg/sample_28/type1.C3D", "0.1mm", kResiduals, {kLayoutDisagrees}},
};

const KnownBad* known_bad(const std::string& file, const std::string& mode) {
  for (const KnownBad& k : kKnownBad)
    if (file == k.file && (mode == k.mode || std::string(k.mode) == "*")) return &k;
  return nullptr;
}

// Files not given to ezc3d at all, with why: its reading of them tests nothing of capz.
struct Skipped {
  const char* file;
  const char* why;
};
const Skipped kEzc3dSkipped[] = {
    {"c3dorg/sample_11/evart.c3d",
     "ezc3d reads it inconsistently: the header says 17 analog samples per frame, ezc3d takes "
     "16 from ANALOG:RATE / POINT:RATE = 16.67, so frames after the first are misaligned and two "
     "reads differ"},
    {"c3dorg/sample_18/bad_parameter_section.c3d",
     "ezc3d grows past 6 GB of memory on its broken parameter section before it throws"},
    {"c3dorg/sample_22/BKINtechnologies.c3d",
     "ezc3d takes 12 GB of memory and minutes on it before it throws (\"Bad c3d formatting\")"},
};

const char* ezc3d_skipped(const std::string& file) {
  for (const Skipped& s : kEzc3dSkipped)
    if (file == s.file) return s.why;
  return nullptr;
}

std::vector<fs::path> shared_c3d_files(const fs::path& root) {
  std::vector<fs::path> out;
  for (const auto& e : fs::recursive_directory_iterator(root)) {
    std::string ext = e.path().extension().string();
    std::transform(ext.begin(), ext.end(), ext.begin(), ::tolower);
    if (e.is_regular_file() && ext == ".c3d") out.push_back(e.path());
  }
  std::sort(out.begin(), out.end());
  return out;
}

// capz's round trip of the file at `path` in one mode, as `capz compress` then `capz decompress`
// make it (the archive streamed from the file with its checksum and residue; the original
// rebuilt from it where the archive allows, else the decoded take written by the C3D writer),
// read back by ezc3d; a capz error becomes kRefused.
Diffs round_trip(const std::string& path, const std::string& units, size_t points,
                 const EzTake& original, bool lossless, const std::string& capz_path,
                 const std::string& out_path) {
  Diffs d;
  double bound = 0;
  try {
    capz::CompressOptions opts;
    opts.lossless = lossless;
    // As the CLI: a take without points has nothing to bound, whatever its units.
    if (!lossless) bound = opts.max_error = points == 0 ? 1.0 : capz::parse_length("0.1mm", units);
    std::unique_ptr<capz::FrameSource> src = capz::open_frames(path);
    capz::compress_stream(*src, opts, capz_path, true);
    src.reset();
    if (capz::can_rebuild(capz::original_info(capz_path), true)) {
      capz::rebuild_original(capz_path, out_path, true);
    } else {
      const std::vector<uint8_t> z = capz::read_file(capz_path);
      const capz::Take back = capz::decompress(z.data(), z.size(), path);
      capz::WriteOptions w;
      w.overwrite = true;
      capz::write_take(back, out_path, w);
    }
  } catch (const capz::Error& e) {
    d.add(kRefused, e.what());
    return d;
  }
  try {
    return compare(original, read_with_ezc3d(out_path), bound);
  } catch (const std::exception& e) {  // ezc3d refuses what capz wrote: a difference of shape
    d.add(kShape, std::string("ezc3d cannot read capz's C3D: ") + e.what());
    return d;
  }
}

// "ok", "known ... (why)", "FIXED ..." (a stale kKnownBad entry) or "FAIL ..." for one mode;
// the last two add a test failure.
std::string judge(const std::string& file, const std::string& mode, const Diffs& d) {
  const KnownBad* k = known_bad(file, mode);
  const unsigned allowed = k ? k->classes : 0;
  const unsigned unexpected = d.found & ~allowed, gone = allowed & ~d.found;
  EXPECT_EQ(unexpected, 0u) << file << " " << mode << ": " << d.describe();
  EXPECT_EQ(gone, 0u) << file << " " << mode << ": kKnownBad allows " << diff_names(gone)
                      << " but capz no longer differs there: remove it from the list";
  if (unexpected) return "FAIL " + d.describe();
  if (gone) return "FIXED " + diff_names(gone) + " (stale kKnownBad entry)";
  if (d.found) {
    std::string why;
    for (const char* w : k->why) why += (why.empty() ? "" : "; ") + std::string(w);
    return "known " + diff_names(d.found) + " (" + why + ")";
  }
  return "ok";
}

// Checks every C3D file under CAPZ_SHARED_DATA/c3d/<set>, lossless and at 0.1 mm, one line of
// output per file. CAPZ_INTEROP_ONLY=text checks only the paths that contain it.
void check_set(const std::string& set) {
  const fs::path root = fs::path(CAPZ_SHARED_DATA) / "c3d";
  if (!fs::is_directory(root / set)) GTEST_SKIP() << "no shared C3D data at " << root / set;
  const char* only = std::getenv("CAPZ_INTEROP_ONLY");
  capz_test::TempDir tmp("capz_interop");
  std::vector<std::string> ezc3d_refused, capz_refused;
  size_t checked = 0;
  for (const fs::path& path : shared_c3d_files(root / set)) {
    const std::string file = path.lexically_relative(root).generic_string();
    if (only && file.find(only) == std::string::npos) continue;
    if (const char* why = ezc3d_skipped(file)) {
      ezc3d_refused.push_back(file + ": not read (" + why + ")");
      continue;
    }
    EzTake original;
    try {
      original = read_with_ezc3d(path.string());
    } catch (const std::exception& e) {
      ezc3d_refused.push_back(file + ": " + e.what());
      continue;
    }
    capz::Take take;
    try {
      take = capz::read_take(path.string());
    } catch (const capz::Error& e) {
      capz_refused.push_back(file + ": " + e.what());
      continue;
    }
    ++checked;
    const std::string out = tmp.file("out.c3d"), z = tmp.file("out.capz");
    const std::string lossless =
        judge(file, "lossless",
              round_trip(path.string(), take.units, take.points, original, true, z, out));
    const Diffs d = round_trip(path.string(), take.units, take.points, original, false, z, out);
    char max[48];
    std::snprintf(max, sizeof max, "max error %.4g: ", d.max_point_error);
    const std::string at_bound = max + judge(file, "0.1mm", d);
    std::printf(
        "[interop] %s: %zu frames x %zu points, %zu analog x %zu | lossless: %s | "
        "0.1mm: %s\n",
        file.c_str(), original.frames, original.points, original.channels, original.subframes,
        lossless.c_str(), at_bound.c_str());
    std::fflush(stdout);  // progress shows as it goes
  }
  for (const std::string& s : ezc3d_refused)
    std::printf("[interop] ezc3d cannot read (skipped): %s\n", s.c_str());
  for (const std::string& s : capz_refused)
    std::printf("[interop] capz cannot read (skipped): %s\n", s.c_str());
  std::printf("[interop] %s: %zu files checked, %zu refused by ezc3d, %zu by capz\n", set.c_str(),
              checked, ezc3d_refused.size(), capz_refused.size());
  if (!only) {
    EXPECT_GT(checked, 0u);
  }
}

}  // namespace

TEST(Ezc3dInterop, C3DOrgSamplesReadBackTheSameInEzc3d) {
  check_set("c3dorg");
}
TEST(Ezc3dInterop, BtkSamplesReadBackTheSameInEzc3d) {
  check_set("btkdata");
}
