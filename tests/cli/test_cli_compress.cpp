// The capz binary's compress / decompress / verify / info-on-.capz, on real shared files:
// exit statuses, the one-line report, default names, refusal to overwrite, --json.
#include <gtest/gtest.h>
#include <sys/wait.h>

#include <algorithm>
#include <cmath>
#include <cstdlib>
#include <filesystem>
#include <fstream>
#include <iterator>
#include <sstream>
#include <string>
#include <vector>

#include "capz/codec.h"
#include "capz/io.h"
#include "capz/metrics.h"
#include "capz/version.h"
#include "test_util.h"

namespace fs = std::filesystem;

namespace {

struct Result {
  int status = -1;
  std::string out;
};

// `capz <args>` with stdout captured (stderr to stdout too when `merge`); `env` ("NAME=VALUE ")
// is set for that one run. `exe`: the release binary, or CAPZ_CLI_FAULTS (the CLI with its test
// hook, tests/support/flip_written_byte.cpp).
Result capz_cli(const std::string& args, bool merge = false, const std::string& env = "",
                const std::string& exe = CAPZ_CLI) {
  static capz_test::TempDir io("capz_cli_compress_io");
  const std::string out = io.file("out");
  const std::string cmd =
      env + "'" + exe + "' " + args + " >'" + out + "'" + (merge ? " 2>&1" : " 2>/dev/null");
  const int rc = std::system(cmd.c_str());
  std::ifstream in(out);
  std::stringstream ss;
  ss << in.rdbuf();
  return {WIFEXITED(rc) ? WEXITSTATUS(rc) : -1, ss.str()};
}

const char* const kTrc = "trc/opensim/walk_free_01.trc";  // under the shared real data
const std::string kC3d = std::string(CAPZ_REPO_DATA) + "/EB015PI.c3d";

// `capz --version`: the library version and the .capz versions written and read (version.h).
TEST(CliVersion, GivenVersionThenLibraryAndFormatVersionsArePrinted) {
  auto text = [](capz::FormatVersion v) {
    return std::to_string(v.major) + "." + std::to_string(v.minor);
  };
  const std::string expected = std::string("capz ") + capz::version_string() + ", writes format " +
                               text(capz::kFormatWritten) + " (" + text(capz::kFormatScans) +
                               " for ragged frames and PLY or .bin sources), reads " +
                               text(capz::kFormatNewestRead) + "\n";
  EXPECT_EQ(expected,
            std::string("capz ") + capz::version_string() +
                ", writes format 1.0 (1.1 for ragged frames and PLY or .bin sources), reads 1.1\n");
  for (const char* flag : {"--version", "-V"}) {
    const Result r = capz_cli(flag);
    EXPECT_EQ(r.status, 0);
    EXPECT_EQ(r.out, expected);
  }
}

TEST(CliCompress, GivenTrcWhenCompressedWithDefaultsThenReportLineAndBoundHolds) {
  const std::string trc = capz_test::shared_data_or_skip(kTrc);
  if (trc.empty()) return;
  capz_test::TempDir d("capz_cli_compress");
  const std::string in = d.file("walk.trc");
  fs::copy_file(trc, in);
  Result r = capz_cli("compress '" + in + "'");
  ASSERT_EQ(r.status, 0) << r.out;
  EXPECT_TRUE(fs::exists(in + ".capz"));
  EXPECT_NE(r.out.find("bpvf"), std::string::npos);
  EXPECT_NE(r.out.find("max error"), std::string::npos);
  EXPECT_NE(r.out.find("KG"), std::string::npos);
  // Not overwritten without -f (exit 1), overwritten with it.
  EXPECT_EQ(capz_cli("compress '" + in + "'").status, 1);
  EXPECT_EQ(capz_cli("compress -f -q '" + in + "'").status, 0);
  // verify against the original: bound holds.
  Result v = capz_cli("verify '" + in + ".capz' --against '" + in + "'");
  EXPECT_EQ(v.status, 0) << v.out;
  EXPECT_NE(v.out.find("holds"), std::string::npos);
  // decompress: the default name is the source's (exists -> refused), -o writes a TRC.
  EXPECT_EQ(capz_cli("decompress '" + in + ".capz'").status, 1);
  ASSERT_EQ(capz_cli("decompress -q '" + in + ".capz' -o '" + d.file("back.trc") + "'").status, 0);
  capz::Take a = capz::read_take(in), b = capz::read_take(d.file("back.trc"));
  capz::ErrorStats e = capz::compare(a, b);
  EXPECT_LE(e.max_abs,
            0.1 + 1e-9);  // the file is in mm; default bound 0.1mm, written to its decimals
  EXPECT_EQ(e.mask_mismatches, 0u);
}

TEST(CliCompress, GivenC3DWhenCompressedWithJsonAndUnitsThenFieldsAndConversion) {
  capz_test::TempDir d("capz_cli_compress");
  const std::string out = d.file("e.capz");
  Result r = capz_cli("compress '" + kC3d + "' -o '" + out + "' --max-error 0.0005m --json");
  ASSERT_EQ(r.status, 0) << r.out;
  EXPECT_NE(r.out.find("\"max_error_target\":0.5"), std::string::npos) << r.out;
  EXPECT_NE(r.out.find("\"position_bytes\""), std::string::npos);
  EXPECT_NE(r.out.find("\"encode_mb_per_s\""), std::string::npos);
  Result i = capz_cli("info '" + out + "'");
  EXPECT_EQ(i.status, 0);
  EXPECT_NE(i.out.find("capz 1.0, "), std::string::npos) << i.out;
  EXPECT_NE(i.out.find("POSW"), std::string::npos);
  EXPECT_EQ(capz_cli("info --json '" + out + "'").status, 0);
  // Frame range decode to a C3D.
  EXPECT_EQ(capz_cli("decompress -q '" + out + "' --frames 100:50 -o '" + d.file("part.c3d") + "'")
                .status,
            0);
  EXPECT_EQ(capz::read_take(d.file("part.c3d")).frames, 50u);
  // Lossless: verify says exact.
  EXPECT_EQ(capz_cli("compress -q --lossless '" + kC3d + "' -o '" + d.file("l.capz") + "'").status,
            0);
  EXPECT_EQ(capz_cli("verify '" + d.file("l.capz") + "' --against '" + kC3d + "'").status, 0);
}

// --frames past the end said "the take has no frames: nothing to write"; now what was asked and
// what the take has, naming the archive. COUNT 0 asks for nothing (refused before any file);
// COUNT -1 is to the end; other negative numbers are refused (they were read as huge counts).
TEST(CliDecompress, GivenFramesPastTheEndOrNoneThenTheMessageSaysWhatTheTakeHas) {
  capz_test::TempDir d("capz_cli_compress");
  const std::string x = d.file("e.capz"), part = d.file("part.c3d");
  ASSERT_EQ(capz_cli("compress -q '" + kC3d + "' -o '" + x + "'").status, 0);
  const size_t frames = capz::read_take(kC3d).frames;
  const std::string past = std::to_string(frames) + ":40";
  Result r = capz_cli("decompress -q '" + x + "' --frames " + past + " -o '" + part + "'", true);
  EXPECT_EQ(r.status, 1) << r.out;
  EXPECT_NE(r.out.find("e.capz: --frames " + past + " is past the end: the take has " +
                       std::to_string(frames) + " frames (0.." + std::to_string(frames - 1) + ")"),
            std::string::npos)
      << r.out;
  r = capz_cli("decompress -q '" + x + "' --frames 3:0 -o '" + part + "'", true);
  EXPECT_EQ(r.status, 1) << r.out;
  EXPECT_NE(r.out.find("--frames 3:0 asks for no frames"), std::string::npos) << r.out;
  for (const char* bad : {"3:-5", "-2:5", "3:", "1:2x"}) {
    r = capz_cli("decompress -q '" + x + "' --frames=" + bad + " -o '" + part + "'", true);
    EXPECT_EQ(r.status, 1) << bad << ": " << r.out;
    EXPECT_NE(r.out.find("--frames wants FIRST:COUNT"), std::string::npos) << r.out;
  }
  EXPECT_FALSE(fs::exists(part));
  r = capz_cli("decompress -q '" + x + "' --frames 3:-1 -o '" + part + "'", true);
  ASSERT_EQ(r.status, 0) << r.out;
  EXPECT_EQ(capz::read_take(part).frames, frames - 3);
}

TEST(CliCompress, GivenBadRequestsThenOneLineErrorsAndStatuses) {
  capz_test::TempDir d("capz_cli_compress");
  EXPECT_EQ(
      capz_cli("compress '" + kC3d + "' -o '" + d.file("x.capz") + "' --lossless --max-error 1mm")
          .status,
      1);
  Result bad =
      capz_cli("compress '" + kC3d + "' -o '" + d.file("x.capz") + "' --max-error 3furlongs", true);
  EXPECT_EQ(bad.status, 6);
  EXPECT_EQ(std::count(bad.out.begin(), bad.out.end(), '\n'), 1) << bad.out;
  EXPECT_FALSE(fs::exists(d.file("x.capz")));
  // A damaged archive: status 5, nothing written.
  ASSERT_EQ(capz_cli("compress -q '" + kC3d + "' -o '" + d.file("y.capz") + "'").status, 0);
  {
    std::fstream f(d.file("y.capz"), std::ios::in | std::ios::out | std::ios::binary);
    f.seekp(2000);
    f.put('\x55');
  }
  EXPECT_EQ(capz_cli("verify '" + d.file("y.capz") + "'").status, 5);
  EXPECT_EQ(capz_cli("decompress '" + d.file("y.capz") + "' -o '" + d.file("y.c3d") + "'").status,
            5);
  EXPECT_FALSE(fs::exists(d.file("y.c3d")));
  EXPECT_EQ(capz_cli("decompress '" + kC3d + "' -o '" + d.file("z.c3d") + "'").status, 3);
}

// --memlimit: a take that needs more memory than the limit is refused in one line with status 8
// and nothing written (decompress, also of a frame range, and verify); the limit's spellings; a
// bad one is status 6 before any file is read.
TEST(CliCompress, GivenMemlimitBelowWhatTheArchiveNeedsThenStatus8AndNothingWritten) {
  capz_test::TempDir d("capz_cli_memlimit");
  ASSERT_EQ(capz_cli("compress -q '" + kC3d + "' -o '" + d.file("x.capz") + "'").status, 0);
  const std::string x = "'" + d.file("x.capz") + "'";
  Result r = capz_cli("decompress " + x + " -o '" + d.file("x.c3d") + "' --memlimit 2K", true);
  EXPECT_EQ(r.status, 8) << r.out;
  EXPECT_EQ(std::count(r.out.begin(), r.out.end(), '\n'), 1) << r.out;
  EXPECT_NE(r.out.find("memory limit"), std::string::npos) << r.out;
  EXPECT_FALSE(fs::exists(d.file("x.c3d")));
  EXPECT_EQ(capz_cli("decompress " + x + " -o '" + d.file("x.c3d") + "' --memlimit 2K --frames 0:5")
                .status,
            8);
  EXPECT_FALSE(fs::exists(d.file("x.c3d")));
  EXPECT_EQ(capz_cli("verify " + x + " --memlimit 2048").status, 8);
  for (const char* ok : {"64M", "1g", "0", "1073741824"})
    EXPECT_EQ(capz_cli("verify " + x + " --memlimit " + ok).status, 0) << ok;
  EXPECT_EQ(capz_cli("decompress " + x + " -o '" + d.file("x.c3d") + "' --memlimit 8M").status, 0);
  EXPECT_TRUE(fs::exists(d.file("x.c3d")));
  for (const char* bad : {"lots", "-1", "5X", "99999999999T", ""}) {
    EXPECT_EQ(capz_cli("decompress " + x + " -o '" + d.file("y.c3d") + "' --memlimit '" + bad + "'")
                  .status,
              6)
        << bad;
    EXPECT_EQ(capz_cli("verify " + x + " --memlimit '" + bad + "'").status, 6) << bad;
  }
  EXPECT_FALSE(fs::exists(d.file("y.c3d")));
}

std::vector<char> file_bytes(const std::string& path) {
  std::ifstream f(path, std::ios::binary);
  return std::vector<char>(std::istreambuf_iterator<char>(f), std::istreambuf_iterator<char>());
}

// --rm deletes IN only after OUT, read back from disk and decoded, reproduces it. The check's
// failure is provoked with CAPZ_TEST_FLIP_WRITTEN_BYTE in the CLI built for the tests (a bit of
// OUT on disk is flipped first, as a disk returning bad data would): then IN stays
// byte-identical, the bad OUT is removed, and one line on stderr says so, status 5. The release
// binary has no such hook: the same variable leaves it working. Without the fault the check passes
// on real files, lossy (bound), lossless and a KG target with a transform (no bound: the KG target
// is checked), TRC and C3D with analog channels and parameters, and IN is removed.
TEST(CliCompress, GivenRmWhenWrittenOutputReadsBackWrongThenInputKeptElseRemoved) {
  capz_test::TempDir d("capz_cli_compress");
  struct Case {
    std::string src, name, opts;
  };
  std::vector<Case> cases = {{kC3d, "eb.c3d", "--max-error 1mm --codec ts"},
                             {kC3d, "eb2.c3d", "--lossless"},
                             {kC3d, "eb3.c3d", "--kg-error 0.5 --codec ts"}};
  // The TRC cases need the shared data; without it the bundled C3D cases still run and the
  // test reports itself skipped.
  const std::string trc = capz_test::shared_data_or_skip(kTrc);
  if (!trc.empty()) {
    cases.push_back({trc, "walk.trc", "--max-error 0.5mm"});
    cases.push_back({trc, "walk2.trc", "--lossless"});
  }
  for (const Case& c : cases) {
    SCOPED_TRACE(c.name + " " + c.opts);
    const std::string in = d.file(c.name), out = in + ".capz";
    fs::copy_file(c.src, in);
    const std::vector<char> before = file_bytes(in);
    // The size of OUT, to flip a byte in its middle (in the position data) as well as near the
    // start (the file header and HEAD).
    ASSERT_EQ(capz_cli("compress -q " + c.opts + " '" + in + "'").status, 0);
    const size_t size = fs::file_size(out);
    for (size_t at : {size_t{9}, size / 2, size - 3}) {
      Result r =
          capz_cli("compress -f --rm " + c.opts + " '" + in + "'", true,
                   "CAPZ_TEST_FLIP_WRITTEN_BYTE=" + std::to_string(at) + " ", CAPZ_CLI_FAULTS);
      EXPECT_EQ(r.status, 5) << r.out;
      const std::string lines = capz_test::without_warnings(r.out);  // walk.trc's header
      EXPECT_EQ(std::count(lines.begin(), lines.end(), '\n'), 1) << r.out;
      EXPECT_NE(r.out.find("kept despite --rm"), std::string::npos) << r.out;
      ASSERT_TRUE(fs::exists(in));
      EXPECT_TRUE(file_bytes(in) == before);
      EXPECT_FALSE(fs::exists(out));
    }
    Result r = capz_cli("compress --rm " + c.opts + " '" + in + "'", true,
                        "CAPZ_TEST_FLIP_WRITTEN_BYTE=9 ");
    EXPECT_EQ(r.status, 0) << r.out;
    EXPECT_FALSE(fs::exists(in));
    ASSERT_TRUE(fs::exists(out));
    // What --rm let go is really in OUT.
    fs::copy_file(c.src, in);
    EXPECT_EQ(capz_cli("verify '" + out + "' --against '" + in + "'").status, 0);
  }
}

}  // namespace

// --rm on a PCD folder: its frame files go only once the archive gives them back (lossless:
// byte for byte through the checksum; at a bound: every field and gap, coordinates within it);
// the folder goes too when nothing else is left in it. With --drop-fields it is refused.
TEST(CliCompress, GivenRmOnAPcdFolderThenFramesGoOnlyWhenTheArchiveGivesThemBack) {
  capz_test::TempDir d("capz_cli_rm_pcd");
  const std::string src = std::string(CAPZ_REPO_DATA) + "/lidar_small";
  std::vector<std::string> names;
  for (const auto& e : fs::directory_iterator(src)) names.push_back(e.path().filename().string());
  std::sort(names.begin(), names.end());
  ASSERT_GE(names.size(), 2u);
  const auto fresh = [&](const std::string& dir) {
    fs::remove_all(dir);
    fs::create_directories(dir);
    for (const std::string& n : names) fs::copy_file(src + "/" + n, dir + "/" + n);
  };

  // Lossless: the folder is gone, and what comes back is the frames, byte for byte.
  const std::string a = d.file("a"), az = d.file("a.capz");
  fresh(a);
  Result r = capz_cli("compress -q --lossless --rm '" + a + "' -o '" + az + "'", true);
  ASSERT_EQ(r.status, 0) << r.out;
  EXPECT_FALSE(fs::exists(a));
  ASSERT_EQ(capz_cli("decompress -q '" + az + "' -o '" + a + "/'").status, 0);
  for (const std::string& n : names)
    EXPECT_TRUE(file_bytes(a + "/" + n) == file_bytes(src + "/" + n)) << n;

  // At a bound, with another file in the folder: the frames go, the folder and that file stay,
  // and one line says so.
  const std::string b = d.file("b"), bz = d.file("b.capz");
  fresh(b);
  { std::ofstream(b + "/notes.txt") << "calibration 3\n"; }
  r = capz_cli("compress --max-error 0.01 --rm '" + b + "' -o '" + bz + "'", true);
  ASSERT_EQ(r.status, 0) << r.out;
  EXPECT_NE(r.out.find("the folder is kept, as it holds other files"), std::string::npos) << r.out;
  for (const std::string& n : names) EXPECT_FALSE(fs::exists(b + "/" + n)) << n;
  EXPECT_TRUE(fs::exists(b + "/notes.txt"));
  fresh(d.file("b_src"));
  EXPECT_EQ(capz_cli("verify '" + bz + "' --against '" + d.file("b_src") + "'").status, 0);

  // An archive that reads back wrong keeps every frame, and is removed.
  const std::string c = d.file("c"), cz = d.file("c.capz");
  fresh(c);
  ASSERT_EQ(capz_cli("compress -q --lossless '" + c + "' -o '" + cz + "'").status, 0);
  const size_t size = fs::file_size(cz);
  r = capz_cli("compress -f --lossless --rm '" + c + "' -o '" + cz + "'", true,
               "CAPZ_TEST_FLIP_WRITTEN_BYTE=" + std::to_string(size / 2) + " ", CAPZ_CLI_FAULTS);
  EXPECT_EQ(r.status, 5) << r.out;
  EXPECT_NE(r.out.find("kept despite --rm"), std::string::npos) << r.out;
  EXPECT_FALSE(fs::exists(cz));
  for (const std::string& n : names)
    EXPECT_TRUE(file_bytes(c + "/" + n) == file_bytes(src + "/" + n)) << n;

  // --drop-fields leaves fields out: --rm would lose them, so it is refused before anything.
  r = capz_cli("compress --drop-fields --rm '" + c + "' -o '" + cz + "'", true);
  EXPECT_EQ(r.status, 1) << r.out;
  EXPECT_NE(r.out.find("--drop-fields"), std::string::npos) << r.out;
  EXPECT_FALSE(fs::exists(cz));
  EXPECT_EQ(fs::exists(c + "/" + names[0]), true);
}

// A C3D whose samples are all marked absent but hold coordinates (SIMI, sample_16): at a bound a
// note says they are not kept; --lossless keeps them.
TEST(CliCompress, GivenAbsentSamplesWithCoordinatesThenANoteAtABound) {
  const std::string giant = capz_test::shared_data_or_skip("c3d/c3dorg/sample_16/giant.c3d");
  if (giant.empty()) return;
  capz_test::TempDir d("capz_cli_absent");
  Result r = capz_cli("compress '" + giant + "' -o '" + d.file("g.capz") + "'", true);
  ASSERT_EQ(r.status, 0) << r.out;
  EXPECT_NE(r.out.find("10295 samples marked absent (negative residual) hold coordinates"),
            std::string::npos)
      << r.out;
  r = capz_cli("compress --lossless '" + giant + "' -o '" + d.file("l.capz") + "'", true);
  ASSERT_EQ(r.status, 0) << r.out;
  EXPECT_EQ(r.out.find("marked absent"), std::string::npos) << r.out;
}

// Decompressing to a format that cannot hold the analog channels or the parameter section says
// so, once a thing, unless -q; to the source's format nothing is said.
TEST(CliCompress, GivenDecompressToTrcThenNotesNameWhatTrcDoesNotKeep) {
  capz_test::TempDir d("capz_cli_dropped");
  Result r = capz_cli("compress -q '" + kC3d + "' -o '" + d.file("e.capz") + "'", true);
  ASSERT_EQ(r.status, 0) << r.out;
  r = capz_cli("decompress '" + d.file("e.capz") + "' -o '" + d.file("e.trc") + "'", true);
  ASSERT_EQ(r.status, 0) << r.out;
  const std::string note = "capz decompress: note: " + d.file("e.capz") + ": trc does not keep ";
  EXPECT_NE(r.out.find(note + "the 16 analog channels\n"), std::string::npos) << r.out;
  EXPECT_NE(r.out.find(note + "the C3D parameter section\n"), std::string::npos) << r.out;
  r = capz_cli("decompress '" + d.file("e.capz") + "' -o '" + d.file("e.c3d") + "'", true);
  ASSERT_EQ(r.status, 0) << r.out;
  EXPECT_EQ(r.out.find("does not keep"), std::string::npos) << r.out;
  r = capz_cli("decompress -q -f '" + d.file("e.capz") + "' -o '" + d.file("e.trc") + "'", true);
  ASSERT_EQ(r.status, 0) << r.out;
  EXPECT_EQ(r.out.find("does not keep"), std::string::npos) << r.out;
}

// --analog-max-error (docs/FORMAT.md 5.7): bounds by unit and by label, reported by info and
// verify, kept through decompress and --rm; bad requests are one-line errors.
TEST(CliCompress, GivenAnalogMaxErrorThenInfoVerifyAndDecompressKeepTheBounds) {
  capz_test::TempDir d("capz_cli_analog");
  const std::string in = d.file("fp.c3d"), out = d.file("fp.c3d.capz");
  fs::copy_file(kC3d, in);
  // The force channels of EB015PI say "nt" and "ntmm"; "N" and "Nmm" name them too.
  Result r = capz_cli("compress '" + in + "' --analog-max-error N=0.5,Nmm=50 --analog-max-error " +
                          "Parsec=2 -o '" + out + "'",
                      true);
  ASSERT_EQ(r.status, 0) << r.out;
  EXPECT_NE(r.out.find("--analog-max-error Parsec names no analog channel"), std::string::npos)
      << r.out;
  Result i = capz_cli("info '" + out + "'");
  ASSERT_EQ(i.status, 0);
  EXPECT_NE(i.out.find("4 lossless; within 0.5 nt: FX1"), std::string::npos) << i.out;
  EXPECT_NE(i.out.find("within 50 ntmm: MX1"), std::string::npos) << i.out;
  Result j = capz_cli("info --json '" + out + "'");
  EXPECT_NE(j.out.find("\"analog_bounds\":[{\"channel\":"), std::string::npos) << j.out;
  EXPECT_NE(j.out.find("\"unit\":\"nt\",\"bound\":0.5"), std::string::npos) << j.out;
  Result v = capz_cli("verify '" + out + "' --against '" + in + "'");
  EXPECT_EQ(v.status, 0) << v.out;
  EXPECT_NE(v.out.find("the lossy channels within their bounds"), std::string::npos) << v.out;
  // Written back: the C3D's analog samples are the archive's (lossy) ones, within the bounds.
  ASSERT_EQ(capz_cli("decompress -q '" + out + "' -o '" + d.file("back.c3d") + "'").status, 0);
  const capz::Take a = capz::read_take(in), b = capz::read_take(d.file("back.c3d"));
  const std::vector<capz::AnalogPhysics> phys = capz::analog_physics(a);
  ASSERT_EQ(a.analog.values.size(), b.analog.values.size());
  size_t moved = 0;
  for (size_t k = 0; k < a.analog.values.size(); ++k) {
    const size_t c = k % phys.size();
    const double bound = phys[c].unit == "nt" ? 0.5 : phys[c].unit == "ntmm" ? 50 : 0;
    const double err = std::fabs(a.analog.values[k] - b.analog.values[k]) * phys[c].factor;
    ASSERT_LE(err, bound) << "channel " << c << " sample " << k / phys.size();
    moved += err > 0;
  }
  EXPECT_GT(moved, 0u);
  // --rm accepts the archive (the promise includes the bounds) and removes the input.
  const std::string in2 = d.file("fp2.c3d");
  fs::copy_file(kC3d, in2);
  EXPECT_EQ(capz_cli("compress -q --rm '" + in2 + "' --analog-max-error N=0.5").status, 0);
  EXPECT_FALSE(fs::exists(in2));
  // Usage errors: bad syntax; --lossless with a bound.
  Result bad =
      capz_cli("compress '" + in + "' --analog-max-error N -o '" + d.file("x.capz") + "'", true);
  EXPECT_NE(bad.status, 0);
  EXPECT_NE(bad.out.find("--analog-max-error wants KEY=BOUND"), std::string::npos) << bad.out;
  Result both = capz_cli(
      "compress '" + in + "' --lossless --analog-max-error N=1 -o '" + d.file("y.capz") + "'",
      true);
  EXPECT_NE(both.status, 0);
  EXPECT_NE(both.out.find("cannot be given with --analog-max-error"), std::string::npos)
      << both.out;
  EXPECT_FALSE(fs::exists(d.file("y.capz")));
}
