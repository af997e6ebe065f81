// Interoperability (issues #13, #14): every shared C3D file that ezc3d reads is read by capz,
// compressed (lossless, and at 0.1 mm), decompressed and written back as C3D; ezc3d must read
// the same thing from capz's file as from the original: shape, header, parameters, analog
// samples bit for bit, gaps at the same places, residuals, and points exact (lossless) or within
// the bound. ezc3d is a test oracle only (tests/interop/ezc3d.cmake); capz keeps its own reader.
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
#include "interop/ezc3d_compare.h"
#include "interop/ezc3d_snapshot.h"
#include "test_util.h"

namespace fs = std::filesystem;
using namespace capz_interop;

namespace {

// Why capz differs, one reason per cause found, with the issue that tracks it.
const char* const kZeroIsGap =
    "capz reads (0,0,0) and NaN samples whose 4th word is valid as gaps and writes them as gaps "
    "(4th word -1); ezc3d reads them as valid samples (#14: nothing dropped)";
const char* const kDataStartMoves =
    "capz rebuilds the parameter section without the original spare blocks, so POINT:DATA_START "
    "moves (#14: parameter section verbatim)";
const char* const kDecFloatWord =
    "a DEC float file comes back Intel; ezc3d reads a float 4th word as two int16 halves, whose "
    "bits change with the processor type (#14: DEC comes back DEC)";
const char* const kIntPairWord =
    "the float 4th word holds two int16 (0x7f00 0x7f00), not a float value: capz writes it back as "
    "0 (#14: residual words exact)";
const char* const kWord150 =
    "header word 150 (event label flag) other than 0x3039 is written as 0 (#14: header kept)";
const char* const kEventDisplayBytes =
    "header event display bytes past the event count are written as 0; ezc3d reads display flags "
    "as 16-bit words, so it sees them (#14: header kept)";
const char* const kEventLabelBlank =
    "header event labels lose their leading blank (\" TE0\" comes back \"TE0 \") (#14: header "
    "kept)";
const char* const kUnits =
    "POINT:UNITS absent or unknown (\"mete\"): capz refuses a bound in mm (#14: units)";
const char* const kPointParams =
    "the original lacks POINT parameters (SCALE, RATE, UNITS, LABELS, FRAMES): ezc3d shows "
    "defaults of its own (no description, 0 x 0 char arrays), capz writes its own with "
    "descriptions; not a capz fault";
const char* const kNoAnalogSpf =
    "no analog channels: header word 10 (analog samples per frame) 1 is written as 0 (#14: header "
    "kept)";
const char* const kAnalogUsed =
    "the header says no analog values but ANALOG:USED = 6: capz follows the parameters and writes "
    "6 channels (#14)";
const char* const kFramesFromParams =
    "capz reads 152 frames x 11 points from the parameters where the header (and ezc3d) say 145 x "
    "12 (#14)";
const char* const kEmptyHeader =
    "the header says 0 points and 0 frames, so ezc3d reads nothing; capz reads 701 frames x 40 "
    "points from the parameters (#14)";
const char* const kFloatSwitch =
    "coordinates at the int16 limit decode one count beyond it at the bound, so the writer "
    "switches to float storage (POINT:SCALE sign; #14 item 3 allows storage fields to change); "
    "ezc3d reads float 4th words as int16 halves, so residuals differ";

// Differences capz makes today, per file (relative to the shared c3d folder) and mode
// ("lossless", "0.1mm", or "*" for both): the classes allowed, why, and the issue that tracks it.
struct KnownBad {
  const char* file;
  const char* mode;
  unsigned classes;
  std::vector<const char*> why;
};
const std::vector<KnownBad> kKnownBad = {
    {"btkdata/others/1123x01EMG.c3d", "lossless", kParams, {kDataStartMoves, kPointParams}},
    {"btkdata/others/1123x01EMG.c3d", "0.1mm", kRefused, {kUnits}},
    {"btkdata/others/561xxa01_anonym.C3D", "lossless", kParams, {kPointParams}},
    {"btkdata/others/561xxa01_anonym.C3D", "0.1mm", kRefused, {kUnits}},
    {"btkdata/others/Analysis.c3d", "*", kGaps, {kZeroIsGap}},
    {"btkdata/others/FunctionalLHip.c3d",
     "*",
     kParams | kGaps | kResiduals,
     {kZeroIsGap, kDataStartMoves, kDecFloatWord}},
    {"btkdata/others/FunctionalStatic.c3d",
     "*",
     kParams | kGaps | kResiduals,
     {kZeroIsGap, kDataStartMoves, kDecFloatWord}},
    {"btkdata/others/Gait.c3d", "*", kHeader, {kWord150}},
    {"btkdata/others/Res16bits.c3d", "*", kHeader, {kWord150}},
    {"btkdata/others/parameterOverflow.c3d", "*", kGaps, {kZeroIsGap}},
    {"c3dorg/sample_00/Cometa Systems/EMG Data Cometa.c3d", "lossless", kParams, {kPointParams}},
    {"c3dorg/sample_00/Cometa Systems/EMG Data Cometa.c3d", "0.1mm", kRefused, {kUnits}},
    {"c3dorg/sample_00/Motion Analysis Corporation/Sample_Jump2.c3d", "*", kHeader, {kWord150}},
    {"c3dorg/sample_00/Motion Analysis Corporation/Walk1.c3d", "*", kHeader, {kWord150}},
    {"c3dorg/sample_00/Vicon Motion Systems/pyCGM2 lower limb CGM24 Walking01.c3d",
     "*",
     kGaps,
     {kZeroIsGap}},
    {"c3dorg/sample_01/Eb015vr.c3d", "*", kResiduals, {kDecFloatWord}},
    {"c3dorg/sample_02/dec_real.c3d", "*", kResiduals, {kDecFloatWord}},
    {"c3dorg/sample_03/gait-pig-nz.c3d", "*", kParams | kGaps, {kZeroIsGap, kDataStartMoves}},
    {"c3dorg/sample_03/gait-pig.c3d", "*", kParams | kGaps, {kZeroIsGap, kDataStartMoves}},
    {"c3dorg/sample_03/gait-raw.c3d", "*", kParams, {kDataStartMoves}},
    {"c3dorg/sample_04/sub_labels.c3d", "*", kParams | kGaps, {kZeroIsGap, kDataStartMoves}},
    {"c3dorg/sample_07/16bitanalog.c3d", "*", kParams | kGaps, {kZeroIsGap, kDataStartMoves}},
    {"c3dorg/sample_08/TESTBPI.c3d", "*", kParams, {kDataStartMoves}},
    {"c3dorg/sample_08/TESTCPI.c3d", "*", kParams, {kDataStartMoves}},
    {"c3dorg/sample_08/TESTDPI.c3d", "*", kParams, {kDataStartMoves}},
    {"c3dorg/sample_09/PlugInC3D.c3d", "*", kParams | kGaps, {kZeroIsGap, kDataStartMoves}},
    {"c3dorg/sample_09/VER4C3D.c3d", "*", kParams, {kDataStartMoves}},
    {"c3dorg/sample_10/TYPE-2a.c3d", "*", kParams, {kDataStartMoves}},
    {"c3dorg/sample_10/TYPE-3.c3d", "*", kParams, {kDataStartMoves}},
    {"c3dorg/sample_10/TYPE-4a.c3d", "*", kHeader, {kWord150}},
    {"c3dorg/sample_11/2198928.c3d", "*", kParams | kGaps, {kZeroIsGap, kDataStartMoves}},
    {"c3dorg/sample_13/Dance1.c3d", "*", kParams, {kDataStartMoves}},
    {"c3dorg/sample_13/golfswing1.c3d", "*", kParams, {kDataStartMoves}},
    {"c3dorg/sample_14/sample14.c3d", "*", kParams, {kDataStartMoves}},
    {"c3dorg/sample_15/FP1.C3D", "*", kHeader, {kEventDisplayBytes}},
    {"c3dorg/sample_15/FP2.C3D", "*", kHeader, {kEventDisplayBytes}},
    {"c3dorg/sample_16/basketball.c3d", "lossless", kParams, {kDataStartMoves, kPointParams}},
    {"c3dorg/sample_16/basketball.c3d", "0.1mm", kRefused, {kUnits}},
    {"c3dorg/sample_16/giant.c3d", "lossless", kParams, {kDataStartMoves, kPointParams}},
    {"c3dorg/sample_16/giant.c3d", "0.1mm", kRefused, {kUnits}},
    {"c3dorg/sample_16/golf.c3d", "lossless", kParams, {kDataStartMoves, kPointParams}},
    {"c3dorg/sample_16/golf.c3d", "0.1mm", kRefused, {kUnits}},
    {"c3dorg/sample_17/128analogchannels.c3d", "*", kParams | kGaps, {kZeroIsGap, kDataStartMoves}},
    {"c3dorg/sample_20/phasespace_sample.c3d",
     "lossless",
     kShape | kHeader | kParams,
     {kEmptyHeader}},
    {"c3dorg/sample_20/phasespace_sample.c3d", "0.1mm", kRefused, {kUnits, kEmptyHeader}},
    {"c3dorg/sample_21/sample21.c3d", "lossless", kHeader, {kWord150}},
    {"c3dorg/sample_21/sample21.c3d",
     "0.1mm",
     kHeader | kParams | kResiduals,
     {kWord150, kFloatSwitch}},
    {"c3dorg/sample_23/Vicon_analysis.c3d", "*", kParams | kGaps, {kZeroIsGap, kDataStartMoves}},
    {"c3dorg/sample_24/MotionMonitorC3D.c3d", "*", kParams, {kDataStartMoves}},
    {"c3dorg/sample_26/Capture0002.c3d", "*", kGaps, {kZeroIsGap}},
    {"c3dorg/sample_26/Capture0003.c3d", "*", kGaps, {kZeroIsGap}},
    {"c3dorg/sample_26/Capture0004.c3d", "*", kGaps, {kZeroIsGap}},
    {"c3dorg/sample_26/Standing_Hybrid_2.c3d", "*", kGaps, {kZeroIsGap}},
    {"c3dorg/sample_26/Walking_Hybrid_1_1.c3d", "*", kGaps, {kZeroIsGap}},
    {"c3dorg/sample_26/Walking_Hybrid_1_2.c3d", "*", kGaps, {kZeroIsGap}},
    {"c3dorg/sample_26/Walking_Hybrid_1_3.c3d", "*", kGaps, {kZeroIsGap}},
    {"c3dorg/sample_26/Walking_Hybrid_1_4.c3d", "*", kGaps, {kZeroIsGap}},
    {"c3dorg/sample_26/Walking_Hybrid_1_5.c3d", "*", kGaps, {kZeroIsGap}},
    {"c3dorg/sample_26/Walking_Hybrid_2.c3d", "*", kGaps, {kZeroIsGap}},
    {"c3dorg/sample_27/kyowadengyo.c3d",
     "*",
     kShape | kHeader | kParams,
     {kDataStartMoves, kFramesFromParams}},
    {"c3dorg/sample_28/dynamic.C3D", "lossless", kParams, {kPointParams}},
    {"c3dorg/sample_28/dynamic.C3D", "0.1mm", kRefused, {kUnits}},
    {"c3dorg/sample_28/standing.C3D", "lossless", kParams, {kPointParams}},
    {"c3dorg/sample_28/standing.C3D", "0.1mm", kRefused, {kUnits}},
    {"c3dorg/sample_28/type1.C3D", "*", kShape | kHeader | kParams, {kDataStartMoves, kAnalogUsed}},
    {"c3dorg/sample_30/admarche2.c3d", "*", kResiduals, {kIntPairWord}},
    {"c3dorg/sample_30/emgwl.c3d", "*", kHeader, {kEventLabelBlank}},
    {"c3dorg/sample_30/marche281.c3d", "*", kResiduals, {kIntPairWord}},
    {"c3dorg/sample_33/bigparlove.c3d", "*", kGaps, {kZeroIsGap}},
    {"c3dorg/sample_34/AlbertoINT.c3d",
     "*",
     kShape | kHeader | kParams,
     {kPointParams, kNoAnalogSpf}},
    {"c3dorg/sample_34/AlbertoREAL.c3d",
     "*",
     kShape | kHeader | kParams,
     {kPointParams, kNoAnalogSpf}},
    {"c3dorg/sample_34/Basketball.c3d",
     "*",
     kShape | kHeader | kParams,
     {kPointParams, kNoAnalogSpf}},
    {"c3dorg/sample_35/Mega Electronics Isokinetic EMG Angle Torque Sample File.c3d",
     "lossless",
     kParams,
     {kPointParams}},
    {"c3dorg/sample_35/Mega Electronics Isokinetic EMG Angle Torque Sample File.c3d",
     "0.1mm",
     kRefused,
     {kUnits}},
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

// capz's round trip of `take` in one mode, read back by ezc3d; a capz error becomes kRefused.
Diffs round_trip(const capz::Take& take, const EzTake& original, bool lossless,
                 const std::string& out_path) {
  Diffs d;
  double bound = 0;
  try {
    capz::CompressOptions opts;
    opts.lossless = lossless;
    if (!lossless) bound = opts.max_error = capz::parse_length("0.1mm", take.units);
    const std::vector<uint8_t> z = capz::compress(take, opts);
    const capz::Take back = capz::decompress(z.data(), z.size(), take.source);
    capz::WriteOptions w;
    w.overwrite = true;
    capz::write_take(back, out_path, w);
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
    const std::string out = tmp.file("out.c3d");
    const std::string lossless = judge(file, "lossless", round_trip(take, original, true, out));
    const Diffs d = round_trip(take, original, false, out);
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
