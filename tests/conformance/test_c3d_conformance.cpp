// Every shared C3D file (the c3d.org sample set and BTK's files under ../shared/data/c3d) either
// reads, with the shape, storage and gap count listed here, or fails with the specific error listed
// in kRejected; every readable file survives read -> write -> read exactly; the five encodings of
// c3dorg/sample_01 give the same trial.
#include <gtest/gtest.h>

#include <algorithm>
#include <cmath>
#include <filesystem>
#include <map>
#include <set>
#include <string>
#include <vector>

#include "capz/error.h"
#include "capz/io.h"
#include "core/atomic_file.h"
#include "support/c3d_compare.h"
#include "test_util.h"

namespace fs = std::filesystem;
using namespace capz;
using capz::testing_support::expect_same_groups;
using capz::testing_support::expect_same_take;

namespace {

const std::string kRoot = std::string(CAPZ_SHARED_DATA) + "/c3d";

struct Readable {
  const char* path;  // relative to ../shared/data/c3d
  int processor;     // 84 Intel, 85 DEC, 86 MIPS
  bool float_storage;
  size_t frames, points;
  int channels;
  size_t gaps;          // gap samples
  const char* warning;  // a warning that must be present ("" = the file must read without any)
};

// Files the reader must refuse, and why.
struct Rejected {
  const char* path;
  ErrorCode code;
  const char* message;
};
const Rejected kRejected[] = {
    // A 0-byte file.
    {"btkdata/others/Empty.c3d", ErrorCode::kNotOurFormat, "empty file (0 bytes)"},
    // Two blocks of zeros but the 0x50 key: no processor type, no points, no data block.
    {"c3dorg/simple.c3d", ErrorCode::kUnsupportedVersion, "unknown processor type 0"},
};

// Quirks worth knowing (see docs/C3D.md): sgi_* hold one little-endian parameter offset;
// TYPE-2/TYPE-4 have parameters of a group that is never declared; the Phoenix files
// (sample_13) have POINT:DATA_START 0/1 and POINT:FRAMES one more than the header; sample_18's
// parameter section runs into the data section; MotionMonitor puts the channel count in header
// word 3; Biogesta (sample_30) writes 1.7e38 in the 4th word of every valid sample.
const Readable kReadable[] = {
    {"btkdata/PiG/PiG_Calibration-FlatFoot-Full.c3d", 84, true, 94, 137, 38, 0, ""},
    {"btkdata/PiG/PiG_Calibration-FlatFoot-Hole.c3d", 84, true, 300, 203, 38, 19935, ""},
    {"btkdata/PiG/PiG_Calibration-FlatFoot-One.c3d", 84, true, 1, 138, 38, 0, ""},
    {"btkdata/PiG/PiG_Calibration2-NoOption.c3d", 84, true, 208, 161, 28, 204, ""},
    {"btkdata/PiG/PiG_Calibration3_FF.c3d", 84, true, 95, 66, 0, 4, ""},
    {"btkdata/PiG/PiG_Calibration3_FF_N18.c3d", 84, true, 95, 66, 0, 4, ""},
    {"btkdata/PiG/PiG_Calibration3_noFF.c3d", 84, true, 95, 66, 0, 4, ""},
    {"btkdata/PiG/PiG_Motion-FlatFoot-Full.c3d", 84, true, 315, 193, 38, 6048, ""},
    {"btkdata/PiG/PiG_Motion-FlatFoot-Hole.c3d", 84, true, 320, 193, 38, 6489, ""},
    {"btkdata/PiG/PiG_Motion-FlatFoot-One.c3d", 84, true, 255, 193, 38, 3063, ""},
    {"btkdata/PiG/PiG_Motion3_FF.c3d", 84, true, 293, 97, 34, 4429, ""},
    {"btkdata/PiG/PiG_Motion3_FF_N18.c3d", 84, true, 293, 92, 34, 3289, ""},
    {"btkdata/PiG/PiG_Motion3_noFF.c3d", 84, true, 293, 97, 34, 4526, ""},
    {"btkdata/c3d.org/sample08/TESTAPI.c3d", 84, false, 450, 26, 16, 226, ""},
    {"btkdata/others/1123x01EMG.c3d", 84, true, 4564, 0, 8, 0, ""},
    {"btkdata/others/561xxa01_anonym.C3D", 84, true, 361, 34, 18, 982, ""},
    {"btkdata/others/ADemo1_rewrite_c3d_pc_float.c3d", 84, true, 512, 24, 16, 85, ""},
    {"btkdata/others/ADemo1_rewrite_c3d_pc_integer.c3d", 84, false, 512, 24, 16, 85, ""},
    {"btkdata/others/Analysis.c3d", 85, true, 101, 24, 16, 2, ""},
    {"btkdata/others/FunctionalLHip.c3d", 85, true, 1577, 74, 36, 59926, ""},
    {"btkdata/others/FunctionalStatic.c3d", 85, true, 655, 116, 36, 20960, ""},
    {"btkdata/others/FunctionalWalk.c3d", 84, true, 438, 146, 36, 16671, ""},
    {"btkdata/others/Gait.c3d", 85, false, 487, 33, 28, 9682, ""},
    {"btkdata/others/MyCube.c3d", 84, true, 1, 14, 0, 0, ""},
    {"btkdata/others/Res16bits.c3d", 84, true, 100, 44, 81, 5, ""},
    {"btkdata/others/badParameterOffset.c3d", 84, true, 111, 41, 0, 222,
     "header scale -1 differs from POINT:SCALE -0.01"},
    {"btkdata/others/mocap36.c3d", 84, true, 1380, 36, 0, 8244, ""},
    {"btkdata/others/parameterOverflow.c3d", 85, true, 101, 142, 36, 11996, ""},
    {"btkdata/others/shd01.c3d", 84, true, 237, 27, 6, 0, ""},
    {"c3dorg/sample_00/Codamotion/codamotion_gaitwands_19970212.c3d", 84, true, 512, 24, 16, 85,
     ""},
    {"c3dorg/sample_00/Codamotion/codamotion_gaitwands_20150204.c3d", 84, true, 2001, 23, 48, 12620,
     ""},
    {"c3dorg/sample_00/Cometa Systems/EMG Data Cometa.c3d", 84, true, 199, 0, 24, 0, ""},
    {"c3dorg/sample_00/Innovative Sports Training/Gait with EMG.c3d", 84, true, 134, 24, 32, 24,
     ""},
    {"c3dorg/sample_00/Innovative Sports Training/Static Pose.c3d", 84, true, 120, 30, 32, 0, ""},
    {"c3dorg/sample_00/Motion Analysis Corporation/Sample_Jump2.c3d", 84, true, 264, 51, 16, 0, ""},
    {"c3dorg/sample_00/Motion Analysis Corporation/Walk1.c3d", 84, true, 151, 49, 18, 1208, ""},
    {"c3dorg/sample_00/NexGen Ergonomics/test1.c3d", 84, true, 721, 40, 0, 0, ""},
    {"c3dorg/sample_00/Vicon Motion Systems/pyCGM2 lower limb CGM24 Walking01.c3d", 84, true, 493,
     171, 6, 10563, ""},
    {"c3dorg/sample_01/Eb015pr.c3d", 84, true, 450, 26, 16, 226, ""},
    {"c3dorg/sample_01/Eb015si.c3d", 86, false, 450, 26, 16, 226, ""},
    {"c3dorg/sample_01/Eb015sr.c3d", 86, true, 450, 26, 16, 226, ""},
    {"c3dorg/sample_01/Eb015vi.c3d", 85, false, 450, 26, 16, 226, ""},
    {"c3dorg/sample_01/Eb015vr.c3d", 85, true, 450, 26, 16, 226, ""},
    {"c3dorg/sample_02/dec_int.c3d", 85, false, 89, 36, 16, 228, ""},
    {"c3dorg/sample_02/dec_real.c3d", 85, true, 89, 36, 16, 228, ""},
    {"c3dorg/sample_02/pc_int.c3d", 84, false, 89, 36, 16, 228, ""},
    {"c3dorg/sample_02/pc_real.c3d", 84, true, 89, 36, 16, 228, ""},
    {"c3dorg/sample_02/sgi_int.c3d", 86, false, 89, 36, 16, 228,
     "has a byte-swapped offset 16129; used as 319"},
    {"c3dorg/sample_02/sgi_real.c3d", 86, true, 89, 36, 16, 228,
     "has a byte-swapped offset 16129; used as 319"},
    {"c3dorg/sample_03/gait-pig-nz.c3d", 84, true, 301, 85, 18, 1996, ""},
    {"c3dorg/sample_03/gait-pig.c3d", 85, false, 142, 77, 30, 2355, ""},
    {"c3dorg/sample_03/gait-raw.c3d", 85, false, 142, 27, 30, 2089, ""},
    {"c3dorg/sample_04/sub_labels.c3d", 85, false, 333, 114, 36, 20815, ""},
    {"c3dorg/sample_06/MACsample.c3d", 86, false, 180, 33, 16, 3565,
     "differs from POINT:SCALE 0.0215412"},
    {"c3dorg/sample_07/16bitanalog.c3d", 84, true, 237, 27, 40, 6399, ""},
    {"c3dorg/sample_08/EB015PI.c3d", 84, false, 450, 26, 16, 226, ""},
    {"c3dorg/sample_08/TESTAPI.c3d", 84, false, 450, 26, 16, 226, ""},
    {"c3dorg/sample_08/TESTBPI.c3d", 84, false, 450, 26, 16, 226, ""},
    {"c3dorg/sample_08/TESTCPI.c3d", 84, false, 450, 26, 16, 226, ""},
    {"c3dorg/sample_08/TESTDPI.c3d", 84, false, 450, 26, 16, 226, ""},
    {"c3dorg/sample_09/PlugInC3D.c3d", 85, false, 281, 86, 36, 10441, ""},
    {"c3dorg/sample_09/VER4C3D.c3d", 85, false, 281, 18, 36, 1239, ""},
    {"c3dorg/sample_10/TYPE-2.C3D", 85, false, 199, 13, 6, 653,
     "9 parameter(s) name group id 7, which has no group entry"},
    {"c3dorg/sample_10/TYPE-2a.c3d", 85, false, 360, 25, 20, 6270, ""},
    {"c3dorg/sample_10/TYPE-3.c3d", 85, false, 515, 21, 28, 2989, ""},
    {"c3dorg/sample_10/TYPE-4.C3D", 85, false, 199, 13, 6, 653,
     "9 parameter(s) name group id 7, which has no group entry"},
    {"c3dorg/sample_10/TYPE-4a.c3d", 85, false, 360, 25, 20, 6270, ""},
    {"c3dorg/sample_11/2198928.c3d", 85, false, 189, 94, 40, 2419, ""},
    {"c3dorg/sample_11/evart.c3d", 85, false, 243, 22, 28, 677, ""},
    {"c3dorg/sample_13/Dance.c3d", 84, true, 499, 40, 8, 0, "POINT:DATA_START says 0"},
    {"c3dorg/sample_13/Dance1.c3d", 84, true, 498, 40, 8, 0, "POINT:DATA_START says 1"},
    {"c3dorg/sample_13/golfswing.c3d", 84, true, 514, 29, 8, 0, "POINT:DATA_START says 0"},
    {"c3dorg/sample_13/golfswing1.c3d", 84, true, 513, 29, 8, 0, "POINT:DATA_START says 1"},
    {"c3dorg/sample_14/sample14.c3d", 85, false, 186, 14, 32, 413, ""},
    {"c3dorg/sample_15/FP1.C3D", 84, true, 480, 8, 12, 0, ""},
    {"c3dorg/sample_15/FP2.C3D", 84, true, 480, 8, 12, 0, ""},
    {"c3dorg/sample_16/basketball.c3d", 84, true, 34, 22, 0, 748, ""},
    {"c3dorg/sample_16/giant.c3d", 84, true, 355, 29, 0, 10295, ""},
    {"c3dorg/sample_16/golf.c3d", 84, true, 137, 21, 0, 2877, ""},
    {"c3dorg/sample_17/128analogchannels.c3d", 84, true, 4038, 10, 128, 8405, ""},
    {"c3dorg/sample_18/bad_parameter_section.c3d", 84, false, 332, 45, 32, 6044,
     "(LABELS) has offset 199"},
    {"c3dorg/sample_20/phasespace_sample.c3d", 84, true, 701, 40, 0, 1281, ""},
    {"c3dorg/sample_21/sample21.c3d", 85, false, 574, 14, 12, 0, ""},
    {"c3dorg/sample_22/BKINtechnologies.c3d", 84, true, 5065, 2, 20, 0, ""},
    {"c3dorg/sample_23/Vicon_analysis.c3d", 84, true, 694, 89, 34, 26851, ""},
    {"c3dorg/sample_24/MotionMonitorC3D.c3d", 84, true, 840, 8, 16, 0,
     "ANALOG:USED 16 x 7 samples per frame fits the data"},
    {"c3dorg/sample_25/analogfpscale03.c3d", 84, true, 358, 18, 28, 714, ""},
    {"c3dorg/sample_25/analogfpscale04.c3d", 84, true, 397, 17, 28, 398, ""},
    {"c3dorg/sample_25/analogfpscale04i.c3d", 85, false, 397, 17, 28, 398, ""},
    {"c3dorg/sample_26/Capture0002.c3d", 84, true, 661, 18, 16, 818, ""},
    {"c3dorg/sample_26/Capture0003.c3d", 84, true, 589, 18, 16, 242, ""},
    {"c3dorg/sample_26/Capture0004.c3d", 84, true, 453, 18, 16, 60, ""},
    {"c3dorg/sample_26/Capture0008_Standing.c3d", 84, true, 2400, 18, 16, 0, ""},
    {"c3dorg/sample_26/Standing_Hybrid_1.c3d", 84, true, 1200, 37, 0, 0, ""},
    {"c3dorg/sample_26/Standing_Hybrid_2.c3d", 84, true, 1200, 37, 16, 34, ""},
    {"c3dorg/sample_26/Walking_Hybrid_1_1.c3d", 84, true, 672, 25, 16, 3902, ""},
    {"c3dorg/sample_26/Walking_Hybrid_1_2.c3d", 84, true, 599, 25, 16, 2048, ""},
    {"c3dorg/sample_26/Walking_Hybrid_1_3.c3d", 84, true, 626, 25, 16, 3111, ""},
    {"c3dorg/sample_26/Walking_Hybrid_1_4.c3d", 84, true, 649, 25, 16, 3600, ""},
    {"c3dorg/sample_26/Walking_Hybrid_1_5.c3d", 84, true, 646, 25, 16, 4075, ""},
    {"c3dorg/sample_26/Walking_Hybrid_2.c3d", 84, true, 541, 73, 16, 3567, ""},
    {"c3dorg/sample_27/kyowadengyo.c3d", 85, false, 152, 11, 24, 26,
     "header says 11 points, POINT:USED says 12"},
    {"c3dorg/sample_28/dynamic.C3D", 84, true, 296, 34, 6, 3572, ""},
    {"c3dorg/sample_28/standing.C3D", 84, true, 200, 38, 6, 1232, ""},
    {"c3dorg/sample_28/type1.C3D", 84, true, 296, 28, 6, 1796, ""},
    {"c3dorg/sample_30/admarche2.c3d", 84, true, 159, 17, 8, 54,
     "2649 samples have a 4th word beyond 16 bits"},
    {"c3dorg/sample_30/emgwl.c3d", 84, true, 501, 0, 4, 0, ""},
    {"c3dorg/sample_30/marche281.c3d", 84, true, 961, 29, 0, 0,
     "27869 samples have a 4th word beyond 16 bits"},
    {"c3dorg/sample_32/vicon_zerowire.c3d", 84, true, 306, 55, 13, 4655, ""},
    {"c3dorg/sample_33/bigparlove.c3d", 84, true, 323, 205, 30, 1798, ""},
    {"c3dorg/sample_34/AlbertoINT.c3d", 84, false, 4921, 40, 0, 0, ""},
    {"c3dorg/sample_34/AlbertoREAL.c3d", 84, false, 4921, 64, 0, 0, ""},
    {"c3dorg/sample_34/Basketball.c3d", 84, false, 774, 64, 0, 0, ""},
    {"c3dorg/sample_35/Mega Electronics Isokinetic EMG Angle Torque Sample File.c3d", 84, true, 29,
     0, 4, 0, ""},
    {"c3dorg/sample_37/ART-Human_2persons_integer.c3d", 84, false, 972, 126, 0, 0, ""},
    {"c3dorg/sample_37/ART-Human_hands_real_no6dof.c3d", 84, true, 969, 61, 0, 0, ""},
    {"c3dorg/sample_37/ART-Human_real.c3d", 84, true, 966, 63, 0, 0, ""},
    {"c3dorg/sample_37/ART-Human_tools_integer_6dofLimbs.c3d", 84, false, 1162, 37, 0, 0, ""},
};

std::vector<std::string> all_c3d_files() {
  std::vector<std::string> out;
  for (const auto& e : fs::recursive_directory_iterator(kRoot)) {
    if (!e.is_regular_file()) continue;
    std::string ext = e.path().extension().string();
    std::transform(ext.begin(), ext.end(), ext.begin(), ::tolower);
    if (ext == ".c3d") out.push_back(fs::relative(e.path(), kRoot).generic_string());
  }
  std::sort(out.begin(), out.end());
  return out;
}

bool has_warning(const Take& t, const std::string& part) {
  for (const auto& w : t.warnings)
    if (w.find(part) != std::string::npos) return true;
  return false;
}

// Skips the test (no shared data) or fails it (c3d/ missing from it) and returns.
#define SKIP_WITHOUT_DATA() \
  if (capz_test::shared_data_or_skip("c3d").empty()) return

}  // namespace

TEST(C3DConformance, EveryFileIsListedAsReadableOrRejected) {
  SKIP_WITHOUT_DATA();
  std::set<std::string> listed;
  for (const auto& r : kReadable) listed.insert(r.path);
  for (const auto& r : kRejected) listed.insert(r.path);
  std::vector<std::string> files = all_c3d_files();
  EXPECT_EQ(files.size(), listed.size());
  for (const auto& f : files) EXPECT_TRUE(listed.count(f)) << f << " is in neither table";
  for (const auto& f : listed)
    EXPECT_TRUE(std::find(files.begin(), files.end(), f) != files.end()) << f << " is missing";
}

TEST(C3DConformance, RejectedFilesFailWithTheirSpecificError) {
  SKIP_WITHOUT_DATA();
  for (const auto& r : kRejected) {
    std::string path = kRoot + "/" + r.path;
    try {
      read_c3d(path);
      ADD_FAILURE() << r.path << " was read but should be rejected";
    } catch (const Error& e) {
      EXPECT_EQ(e.code(), r.code) << r.path << ": " << e.what();
      std::string msg = e.what();
      EXPECT_NE(msg.find(r.message), std::string::npos) << msg;
      EXPECT_NE(msg.find(path), std::string::npos) << "message must name the file: " << msg;
    }
  }
}

// Reads each file, checks the table, writes it (Intel) to a temp folder, reads it back: the
// same take bit for bit, every parameter kept (only those the writer updates may change, and it
// may add what a valid file needs), no warnings; a second generation is byte-identical.
TEST(C3DConformance, ReadableFilesReadAndSurviveReadWriteRead) {
  SKIP_WITHOUT_DATA();
  capz_test::TempDir dir("capz_c3d_conf");
  const std::set<std::string> updated = {"POINT:DATA_START",
                                         "POINT:USED",
                                         "POINT:FRAMES",
                                         "POINT:SCALE",
                                         "POINT:LABELS",
                                         "POINT:LABELS2",
                                         "POINT:DESCRIPTIONS",
                                         "POINT:RATE",
                                         "POINT:UNITS",
                                         "ANALOG:USED",
                                         "ANALOG:LABELS",
                                         "ANALOG:RATE",
                                         "TRIAL:ACTUAL_START_FIELD",
                                         "TRIAL:ACTUAL_END_FIELD"};
  for (const auto& r : kReadable) {
    SCOPED_TRACE(r.path);
    Take t;
    try {
      t = read_c3d(kRoot + "/" + r.path);
    } catch (const Error& e) {
      ADD_FAILURE() << e.what();
      continue;
    }
    ASSERT_TRUE(t.c3d);
    EXPECT_EQ(t.c3d->processor, r.processor);
    EXPECT_EQ(t.c3d->float_storage, r.float_storage);
    EXPECT_EQ(t.frames, r.frames);
    EXPECT_EQ(t.points, r.points);
    EXPECT_EQ(t.analog.channels, r.channels);
    EXPECT_EQ(t.gap_samples(), r.gaps);
    EXPECT_EQ(t.xyz.size(), t.frames * t.points * 3);
    EXPECT_EQ(t.labels.size(), t.points);
    EXPECT_EQ(t.analog.values.size(),
              t.frames * static_cast<size_t>(t.analog.channels * t.analog.samples_per_frame));
    if (*r.warning) {
      EXPECT_TRUE(has_warning(t, r.warning)) << "expected warning: " << r.warning;
    } else {
      EXPECT_TRUE(t.warnings.empty()) << t.warnings.front();
    }
    for (size_t i = 0; i < t.frames * t.points; ++i)
      if (!t.valid[i]) {
        ASSERT_EQ(t.xyz[3 * i], 0.0);
      } else {
        ASSERT_TRUE(std::isfinite(t.xyz[3 * i]) && std::isfinite(t.xyz[3 * i + 1]) &&
                    std::isfinite(t.xyz[3 * i + 2]));
      }

    std::string out = dir.file("a.c3d"), out2 = dir.file("b.c3d");
    WriteOptions o;
    o.overwrite = true;
    write_c3d(t, out, o);
    Take back = read_c3d(out);
    expect_same_take(t, back);
    EXPECT_EQ(back.c3d->processor, 84);
    EXPECT_EQ(back.c3d->float_storage, t.c3d->float_storage);
    // Only a kept oddity of the parameter section may be reported again (parameters of an
    // undeclared group are written back as they were).
    for (const auto& w : back.warnings)
      EXPECT_TRUE(w.find("which has no group entry") != std::string::npos &&
                  std::find(t.warnings.begin(), t.warnings.end(), w) != t.warnings.end())
          << w;
    expect_same_groups(t.c3d->groups, back.c3d->groups, updated, /*b_may_add=*/true);

    write_c3d(back, out2, o);
    EXPECT_EQ(read_file(out), read_file(out2)) << "second generation differs";
  }
}

// c3dorg/sample_01: one trial in Intel/DEC/MIPS x float/int16 (the Intel int16 copy is
// sample_08/EB015PI.c3d). Coordinates agree within one int16 step, masks and labels exactly.
TEST(C3DConformance, Eb015EncodingsGiveTheSameTrial) {
  SKIP_WITHOUT_DATA();
  Take ref = read_c3d(kRoot + "/c3dorg/sample_01/Eb015pr.c3d");
  ASSERT_EQ(ref.c3d->processor, 84);
  ASSERT_TRUE(ref.c3d->float_storage);
  const double step = ref.c3d->point_scale;
  EXPECT_NEAR(step, 0.0833333, 1e-6);
  struct Enc {
    const char* path;
    int processor;
    bool float_storage;
  };
  const Enc encs[] = {{"c3dorg/sample_01/Eb015sr.c3d", 86, true},
                      {"c3dorg/sample_01/Eb015vr.c3d", 85, true},
                      {"c3dorg/sample_01/Eb015si.c3d", 86, false},
                      {"c3dorg/sample_01/Eb015vi.c3d", 85, false},
                      {"c3dorg/sample_08/EB015PI.c3d", 84, false}};
  for (const auto& e : encs) {
    SCOPED_TRACE(e.path);
    Take t = read_c3d(kRoot + "/" + e.path);
    EXPECT_EQ(t.c3d->processor, e.processor);
    EXPECT_EQ(t.c3d->float_storage, e.float_storage);
    ASSERT_EQ(t.frames, ref.frames);
    ASSERT_EQ(t.points, ref.points);
    EXPECT_EQ(t.valid, ref.valid);
    EXPECT_EQ(t.labels, ref.labels);
    EXPECT_EQ(t.c3d->camera_mask, ref.c3d->camera_mask);
    EXPECT_DOUBLE_EQ(t.rate, ref.rate);
    double worst = 0;
    for (size_t i = 0; i < t.xyz.size(); ++i)
      worst = std::max(worst, std::fabs(t.xyz[i] - ref.xyz[i]));
    EXPECT_LE(worst, step) << "largest coordinate difference " << worst;
    if (e.float_storage) {
      EXPECT_EQ(t.xyz, ref.xyz) << "float encodings hold the same floats";
    }
    ASSERT_EQ(t.analog.values.size(), ref.analog.values.size());
    double aw = 0;
    for (size_t i = 0; i < t.analog.values.size(); ++i)
      aw = std::max(aw, std::fabs(t.analog.values[i] - ref.analog.values[i]));
    EXPECT_LE(aw, 1.0) << "analog values differ by " << aw;
  }
}

// The samples bundled in data/ (see data/README.md) read cleanly; they run without shared data.
TEST(C3DConformance, BundledSamplesRead) {
  const std::string repo = CAPZ_REPO_DATA;
  Take eb = read_c3d(repo + "/EB015PI.c3d");
  EXPECT_TRUE(eb.warnings.empty());
  EXPECT_EQ(eb.frames, 450u);
  EXPECT_EQ(eb.points, 26u);
  EXPECT_EQ(eb.gap_samples(), 226u);
  EXPECT_EQ(eb.analog.channels, 16);
  EXPECT_EQ(eb.analog.samples_per_frame, 4);
  EXPECT_DOUBLE_EQ(eb.rate, 50);
  EXPECT_EQ(eb.units, "mm");
  ASSERT_EQ(eb.c3d->header_events.size(), 3u);
  EXPECT_EQ(eb.c3d->header_events[1].label, "RHS");
  EXPECT_FLOAT_EQ(eb.c3d->header_events[1].time, 5.4f);
  Take q = read_c3d(repo + "/Capture0004.c3d");
  EXPECT_TRUE(q.warnings.empty());
  EXPECT_EQ(q.frames, 453u);
  EXPECT_EQ(q.points, 18u);
  EXPECT_EQ(q.first_frame, 389);
  EXPECT_EQ(q.gap_samples(), 60u);
  EXPECT_TRUE(q.c3d->float_storage);
}
