// Runs the built capz binary (CAPZ_CLI) on the shared real files: `capz info` (text and --json)
// and `capz convert` (round trips, refusal to overwrite, one-line errors, no partial output).
#include <gtest/gtest.h>
#include <sys/wait.h>

#include <algorithm>
#include <cctype>
#include <cmath>
#include <cstdio>
#include <cstdlib>
#include <cstring>
#include <filesystem>
#include <fstream>
#include <sstream>
#include <string>

#include "capz/io.h"
#include "test_util.h"

namespace fs = std::filesystem;

namespace {

const std::string kCli = CAPZ_CLI;

struct CliRun {
  int status = -1;
  std::string out, err;
};

using capz_test::file_text;

std::string quote(const std::string& s) {
  std::string q = "'";
  for (char c : s) q += c == '\'' ? std::string("'\\''") : std::string(1, c);
  return q + "'";
}

// Runs `capz <args>` (args already shell-quoted where needed), capturing stdout and stderr.
CliRun run_capz(const std::string& args) {
  static capz_test::TempDir io("capz_cli_io");
  const std::string out = io.file("stdout"), err = io.file("stderr");
  const std::string cmd = quote(kCli) + " " + args + " >" + quote(out) + " 2>" + quote(err);
  int rc = std::system(cmd.c_str());
  CliRun r;
  r.status = WIFEXITED(rc) ? WEXITSTATUS(rc) : -1;
  r.out = file_text(out);
  r.err = file_text(err);
  return r;
}

size_t lines(const std::string& s) {
  size_t n = 0;
  for (char c : s) n += c == '\n';
  return n;
}

// Minimal JSON syntax check (RFC 8259 grammar; numbers, strings with escapes, nesting).
class JsonCheck {
 public:
  explicit JsonCheck(const std::string& s) : s_(s) {}
  bool ok() {
    ws();
    if (!value()) return false;
    ws();
    return i_ == s_.size();
  }

 private:
  void ws() {
    while (i_ < s_.size() && std::strchr(" \t\r\n", s_[i_])) ++i_;
  }
  bool lit(const char* w) {
    size_t n = std::strlen(w);
    if (s_.compare(i_, n, w) != 0) return false;
    i_ += n;
    return true;
  }
  bool string() {
    if (s_[i_] != '"') return false;
    for (++i_; i_ < s_.size(); ++i_) {
      unsigned char c = static_cast<unsigned char>(s_[i_]);
      if (c == '"') {
        ++i_;
        return true;
      }
      if (c < 0x20) return false;
      if (c == '\\') {
        ++i_;
        if (i_ >= s_.size() || !std::strchr("\"\\/bfnrtu", s_[i_])) return false;
      }
    }
    return false;
  }
  bool number() {
    size_t b = i_;
    if (s_[i_] == '-') ++i_;
    while (i_ < s_.size() &&
           (std::isdigit(static_cast<unsigned char>(s_[i_])) || std::strchr(".eE+-", s_[i_])))
      ++i_;
    return i_ > b && std::isdigit(static_cast<unsigned char>(s_[i_ - 1]));
  }
  bool value() {
    ws();
    if (i_ >= s_.size()) return false;
    char c = s_[i_];
    if (c == '{' || c == '[') {
      const char close = c == '{' ? '}' : ']';
      ++i_;
      ws();
      if (s_[i_] == close) {
        ++i_;
        return true;
      }
      for (;;) {
        ws();
        if (c == '{') {
          if (!string()) return false;
          ws();
          if (s_[i_++] != ':') return false;
        }
        if (!value()) return false;
        ws();
        if (s_[i_] == ',') {
          ++i_;
          continue;
        }
        if (s_[i_] == close) {
          ++i_;
          return true;
        }
        return false;
      }
    }
    if (c == '"') return string();
    if (lit("true") || lit("false") || lit("null")) return true;
    return number();
  }
  const std::string& s_;
  size_t i_ = 0;
};

bool contains(const std::string& hay, const std::string& needle) {
  return hay.find(needle) != std::string::npos;
}

}  // namespace

TEST(CliInfo, DescribesATrcFile) {
  const std::string data = capz_test::shared_data_or_skip();
  if (data.empty()) return;
  CliRun r = run_capz("info " + quote(data + "/trc/opensim/walk_free_01.trc"));
  ASSERT_EQ(r.status, 0) << r.err;
  EXPECT_TRUE(contains(r.out, "format:    trc")) << r.out;
  EXPECT_TRUE(contains(r.out, "points:    41")) << r.out;
  EXPECT_TRUE(contains(r.out, "frames:    73 (first frame 185)")) << r.out;
  EXPECT_TRUE(contains(r.out, "rate:      60 Hz")) << r.out;
  EXPECT_TRUE(contains(r.out, "units:     mm")) << r.out;
  EXPECT_TRUE(contains(r.out, "gaps:      0.0% of samples")) << r.out;
  EXPECT_TRUE(contains(r.out, "labels:    R.ASIS, L.ASIS, V.Sacral")) << r.out;
  EXPECT_TRUE(contains(r.out, "(33 more; -v lists all)")) << r.out;
  EXPECT_TRUE(contains(r.out, "analog:    none")) << r.out;
  EXPECT_TRUE(contains(r.out, "- header says 900 frames, file holds 73")) << r.out;
  EXPECT_EQ(r.err, "");
  CliRun v = run_capz("info -v " + quote(data + "/trc/opensim/walk_free_01.trc"));
  EXPECT_FALSE(contains(v.out, "more; -v lists all")) << v.out;
}

TEST(CliInfo, DescribesAPcdFolderAndGaps) {
  const std::string data = capz_test::shared_data_or_skip();
  if (data.empty()) return;
  CliRun r = run_capz("info " + quote(data + "/pcd/pcow"));
  ASSERT_EQ(r.status, 0) << r.err;
  EXPECT_TRUE(contains(r.out, "format:    pcd-folder: binary PCD frames")) << r.out;
  EXPECT_TRUE(contains(r.out, "points:    2904")) << r.out;
  EXPECT_TRUE(contains(r.out, "frames:    204")) << r.out;
  EXPECT_TRUE(contains(r.out, "rate:      unknown")) << r.out;
  CliRun g = run_capz("info " + quote(data + "/trc/opensim/std_walking2_markers.trc"));
  EXPECT_TRUE(
      contains(g.out, "gaps:      50.7% of samples (2809 of 5544), 44 of 44 points have gaps"))
      << g.out;
}

TEST(CliInfo, DescribesAC3dFileWithItsVariantAndAnalogChannels) {
  const std::string data = capz_test::shared_data_or_skip();
  if (data.empty()) return;
  const std::string f = quote(data + "/c3d/c3dorg/sample_01/Eb015vi.c3d");
  CliRun r = run_capz("info " + f);
  ASSERT_EQ(r.status, 0) << r.err;
  EXPECT_TRUE(contains(r.out, "format:    c3d: DEC (85), int16 storage, scale 0.08333")) << r.out;
  EXPECT_TRUE(contains(r.out, "points:    26")) << r.out;
  EXPECT_TRUE(contains(r.out, "frames:    450")) << r.out;
  EXPECT_TRUE(contains(r.out, "rate:      50 Hz")) << r.out;
  EXPECT_TRUE(contains(r.out, "analog:    16 channels at 200 Hz (4 per frame)")) << r.out;
  CliRun j = run_capz("info --json " + f);
  ASSERT_EQ(j.status, 0) << j.err;
  EXPECT_TRUE(JsonCheck(j.out).ok()) << j.out;
  for (const char* k : {"\"processor\":\"DEC\"", "\"processor_type\":85", "\"storage\":\"int16\"",
                        "\"channels\":16", "\"samples_per_frame\":4"})
    EXPECT_TRUE(contains(j.out, k)) << k << "\n" << j.out;
  CliRun e = run_capz("info " + quote(data + "/c3d/btkdata/others/Empty.c3d"));
  EXPECT_NE(e.status, 0);
  EXPECT_EQ(lines(e.err), 1u) << e.err;
  EXPECT_TRUE(contains(e.err, "Empty.c3d")) << e.err;
}

// A unit written in Latin-1 (the degree sign as the single byte 0xB0, Mega Electronics) is shown
// as UTF-8: info's text stays valid UTF-8 for terminals and for scripts that grep it.
TEST(CliInfo, ShowsLatin1LabelsAndUnitsAsUtf8) {
  const std::string data = capz_test::shared_data_or_skip();
  if (data.empty()) return;
  const std::string f = quote(
      data + "/c3d/c3dorg/sample_35/Mega Electronics Isokinetic EMG Angle Torque Sample File.c3d");
  CliRun r = run_capz("info -v " + f);
  ASSERT_EQ(r.status, 0) << r.err;
  EXPECT_TRUE(contains(r.out, "units uV (2), \xC2\xB0 (1), Nm (1)")) << r.out;
  EXPECT_TRUE(contains(r.out, "- Angle: \xC2\xB0, ")) << r.out;
  for (size_t i = 0; i < r.out.size(); ++i) {  // no byte of a Latin-1 string left as it was
    if (static_cast<unsigned char>(r.out[i]) == 0xB0) {
      ASSERT_GT(i, 0u);
      ASSERT_EQ(static_cast<unsigned char>(r.out[i - 1]), 0xC2) << "byte " << i;
    }
  }
}

TEST(CliInfo, ReportsAC3dFilesRotations) {
  capz_test::TempDir d("capz_cli_rot");
  capz::Take t;  // rotations only: 2 segments x 3 samples per frame x 4 frames
  t.format = capz::Format::kC3D;
  t.frames = 4;
  t.rate = 100;
  t.rotations.segments = 2;
  t.rotations.samples_per_frame = 3;
  t.rotations.rate = 300;
  t.rotations.labels = {"pelvis", "thorax"};
  t.rotations.matrices.assign(4 * 3 * 2 * 16, 0.5f);
  t.rotations.reliability.assign(4 * 3 * 2, 1.0f);
  capz::write_c3d(t, d.file("rot.c3d"));
  CliRun r = run_capz("info " + quote(d.file("rot.c3d")));
  ASSERT_EQ(r.status, 0) << r.err;
  EXPECT_TRUE(contains(r.out, "frames:    4")) << r.out;
  EXPECT_TRUE(contains(r.out, "rotations: 2 segments x 12 samples at 300 Hz (3 per frame)"))
      << r.out;
  CliRun j = run_capz("info --json " + quote(d.file("rot.c3d")));
  EXPECT_TRUE(JsonCheck(j.out).ok()) << j.out;
  EXPECT_TRUE(contains(j.out, "\"rotations\":{\"segments\":2,\"samples\":12")) << j.out;
  EXPECT_TRUE(contains(j.out, "\"labels\":[\"pelvis\",\"thorax\"]")) << j.out;
}

// A C3D with rotations through the CLI: compress (no warning: they are stored), info and verify
// on the .capz, decompress to the same file; --rm removes the input once it is proved.
TEST(CliCompress, KeepsAC3dFilesRotations) {
  capz_test::TempDir d("capz_cli_rot_capz");
  for (size_t points : {size_t{0}, size_t{2}}) {
    SCOPED_TRACE(std::to_string(points) + " points");
    capz::Take t;
    t.format = capz::Format::kC3D;
    t.resize(50, points);
    t.rate = 100;
    t.units = "mm";
    for (size_t p = 0; p < points; ++p) t.labels.push_back("P" + std::to_string(p));
    for (size_t i = 0; i < t.xyz.size(); ++i) t.xyz[i] = 100 + static_cast<double>(i % 37);
    t.valid.assign(t.frames * points, 1);
    t.rotations.segments = 2;
    t.rotations.samples_per_frame = 3;
    t.rotations.rate = 300;
    t.rotations.labels = {"pelvis", "thorax"};
    for (size_t i = 0; i < 50 * 3 * 2 * 16; ++i)
      t.rotations.matrices.push_back(i % 16 == 15 ? 1.0f : 0.001f * static_cast<float>(i % 700));
    t.rotations.reliability.assign(50 * 3 * 2, 1.0f);
    t.rotations.matrices[40] = std::nanf("7");
    t.rotations.matrices[41] = -0.0f;
    const std::string c3d = d.file("rot" + std::to_string(points) + ".c3d");
    capz::WriteOptions wo;
    wo.c3d_float = true;
    capz::write_c3d(t, c3d, wo);
    const std::string capz = c3d + ".capz", back = c3d + ".back.c3d";
    CliRun c = run_capz("compress --lossless --window 16 " + quote(c3d) + " -o " + quote(capz));
    ASSERT_EQ(c.status, 0) << c.err;
    EXPECT_FALSE(contains(c.err, "rotation")) << c.err;
    CliRun i = run_capz("info " + quote(capz));
    ASSERT_EQ(i.status, 0) << i.err;
    EXPECT_TRUE(contains(i.out, "2 segments x 150 samples at 300 Hz (3 per frame), lossless"))
        << i.out;
    CliRun j = run_capz("info --json " + quote(capz));
    EXPECT_TRUE(JsonCheck(j.out).ok()) << j.out;
    EXPECT_TRUE(contains(j.out, "\"rotations\":{\"segments\":2,\"samples\":150")) << j.out;
    EXPECT_TRUE(contains(j.out, "\"ROTW\"")) << j.out;
    CliRun v = run_capz("verify " + quote(capz) + " --against " + quote(c3d));
    EXPECT_EQ(v.status, 0) << v.out << v.err;
    CliRun x = run_capz("decompress " + quote(capz) + " -o " + quote(back));
    ASSERT_EQ(x.status, 0) << x.err;
    EXPECT_EQ(file_text(back), file_text(c3d));
    // verify compares them: the original with one rotation bit changed does not match.
    capz::Take other = capz::read_c3d(c3d);
    other.rotations.reliability[7] = 0.5f;
    capz::WriteOptions ow = wo;
    ow.overwrite = true;
    capz::write_c3d(other, back, ow);
    CliRun bad = run_capz("verify " + quote(capz) + " --against " + quote(back));
    EXPECT_EQ(bad.status, 5) << bad.out << bad.err;
    EXPECT_TRUE(contains(bad.out, "rotation samples")) << bad.out;
    // At a bound, then --rm: the rotations are proved exact before the input goes.
    CliRun rm = run_capz("compress --rm -f " + quote(c3d) + " -o " + quote(capz));
    ASSERT_EQ(rm.status, 0) << rm.err;
    EXPECT_FALSE(std::filesystem::exists(c3d));
  }
}

TEST(CliInfo, JsonIsOneValidObjectWithTheFields) {
  const std::string data = capz_test::shared_data_or_skip();
  if (data.empty()) return;
  CliRun r = run_capz("info --json " + quote(data + "/c3d/btkdata/TRCSamples/Gait.trc"));
  ASSERT_EQ(r.status, 0) << r.err;
  EXPECT_EQ(lines(r.out), 1u);
  EXPECT_TRUE(JsonCheck(r.out).ok()) << r.out;
  for (const char* f : {"\"format\":\"trc\"", "\"points\":105", "\"frames\":487", "\"rate\":100",
                        "\"units\":\"mm\"", "\"gap_samples\":39015", "\"labels\":[\"R.Shoulder\"",
                        "\"path_file_type\":\"PathFileType\\t4\\t(X/Y/Z)\\tgait2.trc\"",
                        "\"warnings\":[\"header says 66 markers, file holds 105\""})
    EXPECT_TRUE(contains(r.out, f)) << f << "\n" << r.out;
  CliRun p = run_capz("info --json " + quote(data + "/pcd/horse-gallop"));
  EXPECT_TRUE(JsonCheck(p.out).ok()) << p.out;
  EXPECT_TRUE(contains(p.out, "\"rate\":null")) << p.out;
  EXPECT_TRUE(contains(p.out, "\"points\":8431")) << p.out;
}

TEST(CliInfo, JsonEscapesQuotesBackslashesAndLatin1Labels) {
  capz_test::TempDir d("capz_cli_json");
  std::ofstream(d.file("l.trc"), std::ios::binary)
      << "PathFileType\t4\t(X/Y/Z)\tl.trc\nDataRate\tNumFrames\tNumMarkers\tUnits\n100\t1\t3\tmm\n"
         "Frame#\tTime\tsay \"hi\"\t\t\tback\\slash\t\t\tcaf\xe9\t\t\tna\xc3\xafve\n\t\tX1\n"
         "1\t0\t1\t2\t3\t4\t5\t6\t7\t8\t9\t1\t2\t3\n";
  CliRun r = run_capz("info --json " + quote(d.file("l.trc")));
  ASSERT_EQ(r.status, 0) << r.err;
  EXPECT_TRUE(JsonCheck(r.out).ok()) << r.out;
  EXPECT_TRUE(contains(
      r.out, "\"labels\":[\"say \\\"hi\\\"\",\"back\\\\slash\",\"caf\\u00e9\",\"na\xc3\xafve\"]"))
      << r.out;
}

TEST(CliInfo, BadInputsGiveOneLineErrorsAndTheirExitStatus) {
  CliRun m = run_capz("info /nonexistent/file.trc");
  EXPECT_EQ(m.status, 2);
  EXPECT_EQ(lines(m.err), 1u) << m.err;
  CliRun u = run_capz("info");
  EXPECT_EQ(u.status, 1);
  CliRun h = run_capz("info --help");
  EXPECT_EQ(h.status, 0);
  EXPECT_TRUE(contains(h.out, "--json")) << h.out;
  const std::string data = capz_test::shared_data_or_skip();  // the rest needs the shared data
  if (data.empty()) return;
  CliRun e = run_capz("info " + quote(data + "/c3d/btkdata/TRCSamples/Truncated.trc"));
  EXPECT_EQ(e.status, 5);
  EXPECT_EQ(lines(e.err), 1u) << e.err;
  EXPECT_TRUE(contains(e.err, "Truncated.trc: file ends after line 2")) << e.err;
  EXPECT_EQ(e.out, "");
}

TEST(CliConvert, TrcToPcdToTrcKeepsEverySample) {
  const std::string data = capz_test::shared_data_or_skip();
  if (data.empty()) return;
  capz_test::TempDir d("capz_cli_conv");
  const std::string src = data + "/trc/opensim/dataWithNaNsWithSpaces.trc";
  CliRun a = run_capz("convert -q " + quote(src) + " " + quote(d.file("seq")));
  ASSERT_EQ(a.status, 0) << a.err;
  EXPECT_EQ(a.err, "");
  CliRun b = run_capz("convert --rate 100 --units mm " + quote(d.file("seq")) + " " +
                      quote(d.file("back.trc")));
  ASSERT_EQ(b.status, 0) << b.err;
  capz::Take t = capz::read_trc(src);
  capz::Take p = capz::read_pcd_folder(d.file("seq"));
  capz::Take u = capz::read_trc(d.file("back.trc"));
  capz_test::expect_same_samples(t, p);
  capz_test::expect_same_samples(t, u);
  EXPECT_EQ(u.rate, 100);
  EXPECT_EQ(u.units, "mm");
  EXPECT_EQ(p.pcd->frame_names.size(), t.frames);
}

TEST(CliConvert, C3dToTrcAndPcdAndBack) {
  const std::string data = capz_test::shared_data_or_skip();
  if (data.empty()) return;
  capz_test::TempDir d("capz_cli_conv");
  const std::string src = data + "/c3d/c3dorg/sample_01/Eb015pr.c3d";
  capz::Take t = capz::read_take(src);
  ASSERT_GT(t.gap_samples(), 0u);
  CliRun a = run_capz("convert -q " + quote(src) + " " + quote(d.file("e.trc")));
  ASSERT_EQ(a.status, 0) << a.err;
  CliRun b = run_capz("convert -q " + quote(src) + " " + quote(d.file("e/")));
  ASSERT_EQ(b.status, 0) << b.err;
  capz::Take trc = capz::read_trc(d.file("e.trc"));
  capz::Take pcd = capz::read_pcd_folder(d.file("e"));
  capz_test::expect_same_samples(t, trc);  // TRC text carries every double exactly
  capz_test::expect_same_samples(t, pcd);
  EXPECT_EQ(trc.labels, t.labels);
  EXPECT_EQ(trc.rate, t.rate);
  EXPECT_EQ(trc.units, t.units);
  // Back to C3D: same shape, gaps, labels and rate; positions within float precision.
  CliRun c = run_capz("convert -q " + quote(d.file("e.trc")) + " " + quote(d.file("back.c3d")));
  ASSERT_EQ(c.status, 0) << c.err;
  capz::Take u = capz::read_take(d.file("back.c3d"));
  ASSERT_EQ(u.frames, t.frames);
  ASSERT_EQ(u.points, t.points);
  EXPECT_EQ(u.valid, t.valid);
  EXPECT_EQ(u.labels, t.labels);
  EXPECT_EQ(u.rate, t.rate);
  double worst = 0;
  for (size_t i = 0; i < t.valid.size(); ++i)
    if (t.valid[i])
      for (int k = 0; k < 3; ++k)
        worst = std::max(worst, std::fabs(u.xyz[i * 3 + k] - t.xyz[i * 3 + k]) /
                                    std::max(1.0, std::fabs(t.xyz[i * 3 + k])));
  EXPECT_LT(worst, 1e-6);
}

// What TRC cannot hold is named on stderr, with the events the parameter section holds.
TEST(CliConvert, C3dToTrcNamesWhatTrcDoesNotKeep) {
  const std::string data = capz_test::shared_data_or_skip();
  if (data.empty()) return;
  capz_test::TempDir d("capz_cli_conv_notes");
  const std::string src = data + "/c3d/btkdata/PiG/PiG_Motion-FlatFoot-One.c3d";
  CliRun a = run_capz("convert " + quote(src) + " " + quote(d.file("p.trc")));
  ASSERT_EQ(a.status, 0) << a.err;
  EXPECT_NE(a.err.find("note: trc does not keep the 38 analog channels"), std::string::npos)
      << a.err;
  EXPECT_NE(a.err.find("note: trc does not keep the C3D parameter section (with its 8 events)"),
            std::string::npos)
      << a.err;
  CliRun b = run_capz("convert " + quote(src) + " " + quote(d.file("p.c3d")));
  ASSERT_EQ(b.status, 0) << b.err;
  EXPECT_EQ(b.err.find("does not keep"), std::string::npos) << b.err;
}

TEST(CliConvert, PcdFolderToPcdFolderKeepsNamesAndEncoding) {
  const std::string data = capz_test::shared_data_or_skip();
  if (data.empty()) return;
  capz_test::TempDir d("capz_cli_conv");
  CliRun a = run_capz("convert " + quote(data + "/pcd/horse-gallop") + " " +
                      quote(d.file("h") + "/") + " --pcd-encoding binary_compressed");
  ASSERT_EQ(a.status, 0) << a.err;
  capz::Take t = capz::read_pcd_folder(data + "/pcd/horse-gallop");
  capz::Take u = capz::read_pcd_folder(d.file("h"));
  capz_test::expect_same_samples(t, u);
  EXPECT_EQ(u.pcd->frame_names, t.pcd->frame_names);
  EXPECT_EQ(u.pcd->encoding, "binary_compressed");
}

TEST(CliConvert, RefusesToOverwriteWithoutForce) {
  const std::string data = capz_test::shared_data_or_skip();
  if (data.empty()) return;
  capz_test::TempDir d("capz_cli_conv");
  const std::string src = data + "/trc/opensim/init100.trc";
  const std::string out = d.file("out.trc");
  std::ofstream(out) << "keep me\n";
  CliRun r = run_capz("convert " + quote(src) + " " + quote(out));
  EXPECT_EQ(r.status, 1);
  EXPECT_EQ(lines(r.err), 1u) << r.err;
  EXPECT_TRUE(contains(r.err, "output exists (use -f to overwrite)")) << r.err;
  EXPECT_EQ(file_text(out), "keep me\n");
  CliRun f = run_capz("convert -q -f " + quote(src) + " " + quote(out));
  EXPECT_EQ(f.status, 0) << f.err;
  EXPECT_EQ(capz::read_trc(out).frames, 120u);
  EXPECT_EQ(std::distance(fs::directory_iterator(d.path()), fs::directory_iterator()), 1);
}

TEST(CliConvert, BadInputFailsInOneLineAndLeavesNoOutput) {
  capz_test::TempDir d("capz_cli_conv");
  std::ofstream(d.file("bad.trc"))
      << "PathFileType\t4\nDataRate\tNumFrames\n100\t2\nFrame#\tTime\tA\n"
         "\t\tX1\n1\t0\t1\t2\t3\n2\t0.01\t4\tfive\t6\n";
  CliRun r = run_capz("convert " + quote(d.file("bad.trc")) + " " + quote(d.file("out.trc")));
  EXPECT_EQ(r.status, 5);
  EXPECT_EQ(lines(r.err), 1u) << r.err;
  EXPECT_TRUE(contains(r.err, "bad.trc: line 7, column 4: 'five' is not a number")) << r.err;
  CliRun e = run_capz("convert " + quote(d.path().string()) + " " + quote(d.file("o.trc")));
  EXPECT_EQ(e.status, 3);
  EXPECT_TRUE(contains(e.err, "no .pcd files")) << e.err;
  // Only the bad input is left: no output, no temporary.
  EXPECT_EQ(std::distance(fs::directory_iterator(d.path()), fs::directory_iterator()), 1);
  const std::string data = capz_test::shared_data_or_skip();  // the rest needs the shared data
  if (data.empty()) return;
  CliRun n = run_capz("convert " + quote(data + "/c3d/btkdata/TRCSamples/Empty.trc") + " " +
                      quote(d.file("pcdout")));
  EXPECT_EQ(n.status, 3);
  EXPECT_EQ(lines(n.err), 1u) << n.err;
  CliRun x = run_capz("convert " + quote(data + "/trc/opensim/init100.trc") + " " +
                      quote(d.file("out.xyz")));
  EXPECT_EQ(x.status, 1);
  EXPECT_TRUE(contains(x.err, "cannot tell the output format")) << x.err;
  EXPECT_EQ(std::distance(fs::directory_iterator(d.path()), fs::directory_iterator()), 1);
}

TEST(CliConvert, HelpDocumentsEveryOption) {
  CliRun h = run_capz("convert --help");
  EXPECT_EQ(h.status, 0);
  for (const char* o : {"--force", "--pcd-encoding", "--c3d-float", "--rate", "--units", "--quiet",
                        "--verbose", "--help"})
    EXPECT_TRUE(contains(h.out, o)) << o;
  CliRun bad = run_capz("convert --pcd-encoding zip a.trc b/");
  EXPECT_EQ(bad.status, 6);
}

namespace {
// An organized 4 x 3 ASCII PCD folder of `frames` frames with rgb (U4), intensity (F4) and a
// 2-count descriptor (F4).
std::string make_fields_folder(const capz_test::TempDir& d, size_t frames) {
  const std::string dir = d.file("fields");
  fs::create_directory(dir);
  for (size_t f = 0; f < frames; ++f) {
    std::ofstream o(fs::path(dir) / ("f" + std::to_string(f) + ".pcd"));
    o << "VERSION 0.7\nFIELDS x y z rgb intensity desc\nSIZE 4 4 4 4 4 4\nTYPE F F F U F F\n"
         "COUNT 1 1 1 1 1 2\nWIDTH 4\nHEIGHT 3\nVIEWPOINT 0 0 0 1 0 0 0\nPOINTS 12\nDATA ascii\n";
    for (size_t p = 0; p < 12; ++p)
      o << p * 0.25 << " " << f * 0.5 << " 1.5 " << (p * 1000 + f) << " "
        << (p == 3 ? "nan" : "0.75") << " " << p << " -" << f << "\n";
  }
  return dir;
}
}  // namespace

TEST(CliFields, InfoListsThemAndNothingIsDroppedWithoutBeingAsked) {
  capz_test::TempDir d;
  const std::string dir = make_fields_folder(d, 3);
  CliRun i = run_capz("info " + quote(dir));
  ASSERT_EQ(i.status, 0) << i.err;
  EXPECT_NE(i.out.find("organized 4 x 3"), std::string::npos) << i.out;
  EXPECT_NE(i.out.find("x F4, y F4, z F4, rgb U4, intensity F4, desc F4x2"), std::string::npos)
      << i.out;
  CliRun j = run_capz("info --json " + quote(dir));
  EXPECT_NE(j.out.find("\"fields\":[{\"name\":\"x\""), std::string::npos) << j.out;
  EXPECT_NE(j.out.find("\"organized\":true"), std::string::npos) << j.out;

  // To C3D: refused, naming the fields, nothing written; with --drop-fields, one line names them.
  const std::string c3d = d.file("a.c3d");
  CliRun c = run_capz("convert " + quote(dir) + " " + quote(c3d) + " --rate 30 --units m");
  EXPECT_EQ(c.status, 1);
  EXPECT_NE(c.err.find("rgb, intensity, desc"), std::string::npos) << c.err;
  EXPECT_NE(c.err.find("--drop-fields"), std::string::npos) << c.err;
  EXPECT_FALSE(fs::exists(c3d));
  c = run_capz("convert " + quote(dir) + " " + quote(c3d) + " --rate 30 --units m --drop-fields");
  EXPECT_EQ(c.status, 0) << c.err;
  EXPECT_NE(c.err.find("dropped point fields: rgb, intensity, desc"), std::string::npos) << c.err;
  EXPECT_TRUE(fs::exists(c3d));

  // Through an archive: the fields come back, with the layout and the DATA encoding.
  const std::string z = d.file("f.capz"), back = d.file("back");
  CliRun k = run_capz("compress " + quote(dir) + " -o " + quote(z) + " --units m -e 0.001m -v");
  ASSERT_EQ(k.status, 0) << k.err;
  EXPECT_NE(k.out.find("point fields"), std::string::npos) << k.out;
  CliRun iz = run_capz("info " + quote(z));
  EXPECT_NE(iz.out.find("rgb U4, intensity F4, desc F4x2"), std::string::npos) << iz.out;
  CliRun x = run_capz("decompress " + quote(z) + " -o " + quote(back + "/"));
  ASSERT_EQ(x.status, 0) << x.err;
  const std::string src = file_text(dir + "/f1.pcd"), got = file_text(back + "/f1.pcd");
  EXPECT_NE(got.find("FIELDS x y z rgb intensity desc\n"), std::string::npos) << got;
  EXPECT_NE(got.find("HEIGHT 3\n"), std::string::npos) << got;
  EXPECT_NE(got.find("DATA ascii\n"), std::string::npos) << got;
  capz::Take a = capz::read_take(dir), b = capz::read_take(back);
  ASSERT_EQ(b.attributes.size(), 3u);
  for (size_t n = 0; n < 3; ++n) EXPECT_EQ(a.attributes[n].data, b.attributes[n].data) << n;
  // To C3D from the archive: refused without --drop-fields.
  CliRun y = run_capz("decompress " + quote(z) + " -o " + quote(d.file("z.c3d")));
  EXPECT_EQ(y.status, 1) << y.err;
  EXPECT_FALSE(fs::exists(d.file("z.c3d")));
  y = run_capz("decompress " + quote(z) + " -o " + quote(d.file("z.trc")) + " --drop-fields");
  EXPECT_EQ(y.status, 0) << y.err;
  EXPECT_NE(y.err.find("dropped point fields"), std::string::npos) << y.err;
  // --drop-fields on compress leaves them out.
  CliRun dz = run_capz("compress " + quote(dir) + " -o " + quote(d.file("nf.capz")) +
                       " --units m --lossless --drop-fields");
  ASSERT_EQ(dz.status, 0) << dz.err;
  CliRun inf = run_capz("info " + quote(d.file("nf.capz")));
  EXPECT_EQ(inf.out.find("rgb"), std::string::npos) << inf.out;
}
