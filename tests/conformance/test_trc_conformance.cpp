// Every shared TRC file (OpenSim's and BTK's samples) either reads, with the shape and the
// warnings listed here, or fails with the specific error listed here; every readable file
// survives read -> write -> read exactly.
#include <gtest/gtest.h>

#include <algorithm>
#include <filesystem>
#include <fstream>
#include <set>
#include <string>
#include <vector>

#include "capz/error.h"
#include "capz/io.h"
#include "test_util.h"

namespace fs = std::filesystem;
using capz::ErrorCode;

namespace {

struct Expect {
  const char* path;  // relative to the shared data folder
  bool reads;        // false: must fail with `code` and a message containing `message`
  size_t frames, points;
  int64_t first_frame;
  double rate;
  const char* warning;  // a warning that must be present ("" = none required)
  ErrorCode code;
  const char* message;
};

// Files whose header disagrees with their body read what is there and say so in a warning.
const Expect kFiles[] = {
    {"trc/opensim/abdbonepin.trc",
     true,
     1991,
     11,
     0,
     100,
     "header says 3514 frames, file holds 1991",
     {},
     ""},
    {"trc/opensim/constraintTest.trc", true, 2105, 44, 1, 200, "", {}, ""},
    {"trc/opensim/dataWithBlanksForMissingMarkers.trc", true, 464, 40, 1, 250, "", {}, ""},
    {"trc/opensim/dataWithNaNsWithSpaces.trc", true, 427, 42, 1, 100, "", {}, ""},
    {"trc/opensim/init100.trc", true, 120, 22, 101, 120, "", {}, ""},
    {"trc/opensim/std_walking2_markers.trc", true, 126, 44, 1, 250, "", {}, ""},
    {"trc/opensim/std_walking5_markers.trc", true, 112, 40, 1, 250, "", {}, ""},
    {"trc/opensim/walk_free_01.trc",
     true,
     73,
     41,
     185,
     60,
     "header says 900 frames, file holds 73",
     {},
     ""},
    {"trc/opensim/walk_free_02.trc",
     true,
     75,
     41,
     258,
     60,
     "header says 900 frames, file holds 75",
     {},
     ""},
    {"trc/opensim/walk_free_03.trc",
     true,
     73,
     41,
     333,
     60,
     "header says 900 frames, file holds 73",
     {},
     ""},
    // NumMarkers 0 and no names, but rows hold up to 10 (37) unnamed markers.
    {"c3d/btkdata/TRCSamples/10002-20130626160334-Unnamed.trc",
     true,
     882,
     10,
     1,
     400,
     "header says 0 markers, file holds 10",
     {},
     ""},
    {"c3d/btkdata/TRCSamples/10002-20130731010438-Unnamed.trc",
     true,
     1313,
     37,
     1,
     400,
     "header says 0 markers, file holds 37",
     {},
     ""},
    {"c3d/btkdata/TRCSamples/Anto.trc", true, 128, 34, 1, 100, "", {}, ""},
    // Header says 66 markers, the names line holds 33, rows hold up to 105 markers.
    {"c3d/btkdata/TRCSamples/Gait.trc",
     true,
     487,
     105,
     1,
     100,
     "header says 66 markers, file holds 105",
     {},
     ""},
    {"c3d/btkdata/TRCSamples/Knee.trc", true, 200, 71, 1, 200, "", {}, ""},
    {"c3d/btkdata/TRCSamples/Res16bits.trc", true, 100, 44, 1, 100, "", {}, ""},
    // Names and header: 65 markers; every row holds 70.
    {"c3d/btkdata/TRCSamples/SprintCalib.trc",
     true,
     337,
     70,
     1,
     250,
     "header says 65 markers, file holds 70",
     {},
     ""},
    {"c3d/btkdata/TRCSamples/SprintMotion.trc", true, 788, 59, 1, 250, "", {}, ""},
    // 10 rows carry values for 1-2 markers beyond the 34 named ones.
    {"c3d/btkdata/TRCSamples/UpperLimbStatic.trc",
     true,
     146,
     36,
     1,
     100,
     "header says 34 markers, file holds 36",
     {},
     ""},
    {"c3d/btkdata/TRCSamples/MOTEK/T.trc", true, 89, 41, 1, 30, "", {}, ""},
    {"c3d/btkdata/TRCSamples/MOTEK/ballet_reduced.trc", true, 100, 41, 1, 30, "", {}, ""},
    {"c3d/btkdata/TRCSamples/Empty.trc", false, 0, 0, 0, 0, "", ErrorCode::kNotOurFormat,
     "empty file (0 bytes)"},
    {"c3d/btkdata/TRCSamples/Truncated.trc", false, 0, 0, 0, 0, "", ErrorCode::kCorrupt,
     "file ends after line 2: the header values (line 3) are missing"},
};

bool has_warning(const capz::Take& t, const std::string& needle) {
  for (const auto& w : t.warnings)
    if (w.find(needle) != std::string::npos) return true;
  return false;
}

}  // namespace

TEST(TrcConformance, TheTableCoversEverySharedTrcFile) {
  const std::string data = capz_test::shared_data_or_skip();
  if (data.empty()) return;
  std::set<std::string> listed, found;
  for (const auto& e : kFiles) listed.insert(e.path);
  for (const char* dir : {"trc/opensim", "c3d/btkdata/TRCSamples"}) {
    for (const auto& entry : fs::recursive_directory_iterator(data + "/" + dir)) {
      if (entry.path().extension() != ".trc") continue;
      std::string rel = fs::relative(entry.path(), data).string();
      EXPECT_TRUE(listed.count(rel)) << rel << " is not in the conformance table";
      found.insert(rel);
    }
  }
  // And the other way round: every listed file is there (an empty walk cannot pass).
  EXPECT_EQ(found, listed);
}

TEST(TrcConformance, EveryFileReadsOrFailsAsListed) {
  const std::string data = capz_test::shared_data_or_skip();
  if (data.empty()) return;
  for (const auto& e : kFiles) {
    SCOPED_TRACE(e.path);
    const std::string path = data + "/" + e.path;
    if (!e.reads) {
      try {
        capz::read_trc(path);
        ADD_FAILURE() << "read a file that should be rejected";
      } catch (const capz::Error& err) {
        EXPECT_EQ(err.code(), e.code) << err.what();
        EXPECT_NE(std::string(err.what()).find(e.message), std::string::npos) << err.what();
        EXPECT_EQ(std::string(err.what()).rfind(path, 0), 0u) << "message names the file";
      }
      continue;
    }
    capz::Take t = capz::read_trc(path);
    EXPECT_EQ(t.frames, e.frames);
    EXPECT_EQ(t.points, e.points);
    if (e.first_frame != 0) {
      EXPECT_EQ(t.first_frame, e.first_frame);
    }
    EXPECT_EQ(t.rate, e.rate);
    EXPECT_EQ(t.units, "mm");
    EXPECT_EQ(t.labels.size(), t.points);
    EXPECT_EQ(t.trc->times.size(), t.frames);
    if (*e.warning) {
      EXPECT_TRUE(has_warning(t, e.warning)) << "missing warning: " << e.warning;
    }
  }
}

TEST(TrcConformance, ValuesAndGapsMatchTheText) {
  const std::string data = capz_test::shared_data_or_skip();
  if (data.empty()) return;
  // abdbonepin.trc row 1: "0\t0\t246.329\t-29.647\t-6.82\t213.878..."
  capz::Take a = capz::read_trc(data + "/trc/opensim/abdbonepin.trc");
  EXPECT_EQ(a.first_frame, 0);
  EXPECT_EQ(a.labels[0], "gu");
  EXPECT_EQ(a.labels[10], "ijc");
  EXPECT_EQ(a.at(0, 0)[0], 246.329);
  EXPECT_EQ(a.at(0, 0)[2], -6.82);
  EXPECT_EQ(a.at(0, 1)[0], 213.878);
  EXPECT_EQ(a.trc->decimals, 3);
  // dataWithNaNsWithSpaces.trc row 1: "1\t0\t NaN\t...NaN\t1009.526917\t1016.496277\t-198.410294"
  capz::Take n = capz::read_trc(data + "/trc/opensim/dataWithNaNsWithSpaces.trc");
  EXPECT_EQ(n.labels[0], "LASI");
  EXPECT_FALSE(n.is_valid(0, 0));
  EXPECT_TRUE(n.is_valid(0, 1));
  EXPECT_EQ(n.at(0, 1)[0], 1009.526917);
  EXPECT_EQ(n.at(0, 1)[2], -198.410294);
  EXPECT_GT(n.gap_samples(), 0u);
  // dataWithBlanksForMissingMarkers.trc: the first row is all blanks; the last row is complete.
  capz::Take b = capz::read_trc(data + "/trc/opensim/dataWithBlanksForMissingMarkers.trc");
  for (size_t p = 0; p < b.points; ++p) EXPECT_FALSE(b.is_valid(0, p));
  EXPECT_TRUE(b.is_valid(b.frames - 1, 0));
  EXPECT_EQ(b.at(b.frames - 1, 0)[0], 1552.76050);
  EXPECT_EQ(b.trc->orig_num_frames, 1103);
  // std_walking2: names line has an extra tab before each name; names still come in order.
  capz::Take s = capz::read_trc(data + "/trc/opensim/std_walking2_markers.trc");
  EXPECT_EQ(s.labels[0], "RTH1");
  EXPECT_EQ(s.labels[1], "RFHD");
  // constraintTest: first line separated by blanks, padded header values.
  capz::Take c = capz::read_trc(data + "/trc/opensim/constraintTest.trc");
  EXPECT_EQ(c.at(0, 0)[0], 90.174);
  EXPECT_EQ(c.trc->times.back(), 10.52);
}

TEST(TrcConformance, ReadWriteReadIsExactForEveryReadableFile) {
  const std::string data = capz_test::shared_data_or_skip();
  if (data.empty()) return;
  capz_test::TempDir tmp("capz_trc_conf");
  for (const auto& e : kFiles) {
    if (!e.reads) continue;
    SCOPED_TRACE(e.path);
    capz::Take t = capz::read_trc(data + "/" + e.path);
    const std::string out = tmp.file("out.trc");
    capz::WriteOptions o;
    o.overwrite = true;
    capz::write_trc(t, out, o);
    capz::Take u = capz::read_trc(out);
    capz_test::expect_same_samples(t, u);
    for (size_t p = 0; p < t.points; ++p)
      if (!t.labels[p].empty()) {
        EXPECT_EQ(u.labels[p], t.labels[p]);
      }
    EXPECT_EQ(u.rate, t.rate);
    EXPECT_EQ(u.units, t.units);
    EXPECT_EQ(u.first_frame, t.first_frame);
    EXPECT_EQ(u.trc->times, t.trc->times);
    EXPECT_EQ(u.trc->frame_numbers, t.trc->frame_numbers);
    EXPECT_EQ(u.trc->decimals, t.trc->decimals);
  }
}

namespace {

// OpenSim's TRC reader splits rows at tabs, keeps empty fields between tabs and drops an empty
// field after the last tab; it wants exactly 2 + 3 * NumMarkers fields per row.
std::vector<std::string> opensim_tokens(const std::string& line) {
  std::vector<std::string> t;
  size_t start = 0, tab;
  while ((tab = line.find('\t', start)) != std::string::npos) {
    t.push_back(line.substr(start, tab - start));
    start = tab + 1;
  }
  if (start < line.size()) t.push_back(line.substr(start));
  return t;
}

std::vector<std::string> non_empty(std::vector<std::string> v) {
  v.erase(std::remove(v.begin(), v.end(), std::string()), v.end());
  return v;
}

}  // namespace

TEST(TrcConformance, WrittenFilesFollowTheLayoutOpenSimReads) {
  const std::string data = capz_test::shared_data_or_skip();
  if (data.empty()) return;
  capz_test::TempDir tmp("capz_trc_osim");
  for (const char* f : {"trc/opensim/dataWithBlanksForMissingMarkers.trc",
                        "c3d/btkdata/TRCSamples/10002-20130626160334-Unnamed.trc"}) {
    SCOPED_TRACE(f);
    capz::Take t = capz::read_trc(data + "/" + f);
    const std::string out = tmp.file("o.trc");
    capz::WriteOptions o;
    o.overwrite = true;
    capz::write_trc(t, out, o);
    std::ifstream in(out);
    std::string line;
    std::vector<std::string> lines;
    while (std::getline(in, line)) lines.push_back(line);
    ASSERT_GE(lines.size(), 6u);
    EXPECT_EQ(
        non_empty(opensim_tokens(lines[1])),
        (std::vector<std::string>{"DataRate", "CameraRate", "NumFrames", "NumMarkers", "Units",
                                  "OrigDataRate", "OrigDataStartFrame", "OrigNumFrames"}));
    std::vector<std::string> values = non_empty(opensim_tokens(lines[2]));
    ASSERT_EQ(values.size(), 8u);
    EXPECT_EQ(values[3], std::to_string(t.points));
    EXPECT_EQ(non_empty(opensim_tokens(lines[3])).size(), t.points + 2);
    std::vector<std::string> xyz = non_empty(opensim_tokens(lines[4]));
    ASSERT_EQ(xyz.size(), 3 * t.points);
    EXPECT_EQ(xyz.back(), "Z" + std::to_string(t.points));
    EXPECT_EQ(lines[5], "");
    size_t rows = 0;
    for (size_t i = 6; i < lines.size(); ++i, ++rows)
      ASSERT_EQ(opensim_tokens(lines[i]).size(), 2 + 3 * t.points) << "line " << i + 1;
    EXPECT_EQ(rows, t.frames);
  }
}
