// Batches (docs/CLI.md, docs/ARCHIVE.md): many inputs, -r, --output-dir-mirror / -flat, -o and
// -c with one input only, a failure in the middle of a batch, -f, pipes, -T, --report, test and
// list over many archives, and the GNU parallel and Slurm recipes.
#include <gtest/gtest.h>
#include <sys/wait.h>

#include <algorithm>
#include <cctype>
#include <cstdlib>
#include <filesystem>
#include <fstream>
#include <map>
#include <sstream>
#include <string>
#include <vector>

#include "capz/io.h"
#include "capz/tool/file.h"
#include "test_util.h"

namespace fs = std::filesystem;

namespace {

struct Result {
  int status = -1;
  std::string out, err;
};

using capz_test::file_text;

// `command` run by bash in `dir`, stdin from /dev/null unless it says otherwise, stdout and
// stderr captured apart; `capz` in it is the binary under test (also $CAPZ).
Result shell(const std::string& dir, const std::string& command) {
  static capz_test::TempDir io("capz_cli_batch_io");
  static int n = 0;
  const std::string tag = std::to_string(n++);
  const std::string script = io.file("cmd" + tag + ".sh"), out = io.file("out" + tag),
                    err = io.file("err" + tag);
  std::ofstream(script) << "cd '" << dir << "' || exit 99\nexport CAPZ='" << CAPZ_CLI
                        << "'\ncapz() { \"$CAPZ\" \"$@\"; }\n"
                        << command << "\n";
  const std::string cmd = "bash '" + script + "' </dev/null >'" + out + "' 2>'" + err + "'";
  const int rc = std::system(cmd.c_str());
  return {WIFEXITED(rc) ? WEXITSTATUS(rc) : -1, file_text(out), file_text(err)};
}

size_t count_lines(const std::string& s) {
  return static_cast<size_t>(std::count(s.begin(), s.end(), '\n'));
}

std::vector<std::string> split_lines(const std::string& s) {
  std::vector<std::string> v;
  std::stringstream ss(s);
  for (std::string line; std::getline(ss, line);) v.push_back(line);
  return v;
}

std::string repo(const std::string& name) {
  return std::string(CAPZ_REPO_DATA) + "/" + name;
}

// A small tree of takes: t/s1/a.c3d, t/s1/e.c3d, t/s2/w.trc, t/s2/frames/*.pcd, t/s2/notes.txt.
void make_tree(const std::string& root) {
  fs::create_directories(root + "/t/s1");
  fs::create_directories(root + "/t/s2/frames");
  fs::copy_file(repo("admarche2.c3d"), root + "/t/s1/a.c3d");
  fs::copy_file(repo("EB015PI.c3d"), root + "/t/s1/e.c3d");
  fs::copy_file(repo("std_walking5_markers.trc"), root + "/t/s2/w.trc");
  for (const auto& f : fs::directory_iterator(repo("synth_wave")))
    if (f.path().extension() == ".pcd")
      fs::copy_file(f.path(), root + "/t/s2/frames/" + f.path().filename().string());
  std::ofstream(root + "/t/s2/notes.txt") << "not a take\n";
}

const std::vector<std::string> kTreeArchives = {"t/s1/a.c3d.capz", "t/s1/e.c3d.capz",
                                                "t/s2/frames.capz", "t/s2/w.trc.capz"};

// A flat JSON object (strings, numbers, true/false/null) parsed into text values: strings
// unescaped (\" \\ \/ \n \t and \u00XX), other values as written. Fails the test on bad JSON.
std::map<std::string, std::string> parse_object(const std::string& s) {
  std::map<std::string, std::string> m;
  size_t i = 0;
  auto ws = [&] {
    while (i < s.size() && std::isspace(static_cast<unsigned char>(s[i]))) ++i;
  };
  auto str = [&]() -> std::string {
    std::string v;
    if (s[i] != '"') throw std::runtime_error("string expected at " + std::to_string(i));
    for (++i; i < s.size() && s[i] != '"'; ++i) {
      if (s[i] != '\\') {
        v += s[i];
        continue;
      }
      const char e = s[++i];
      if (e == 'u') {
        v += static_cast<char>(std::stoi(s.substr(i + 1, 4), nullptr, 16));
        i += 4;
      } else {
        v += e == 'n' ? '\n' : e == 't' ? '\t' : e;
      }
    }
    if (i >= s.size()) throw std::runtime_error("unterminated string");
    ++i;
    return v;
  };
  ws();
  if (s[i++] != '{') throw std::runtime_error("object expected");
  for (ws(); s[i] != '}';) {
    const std::string k = str();
    ws();
    if (s[i++] != ':') throw std::runtime_error("':' expected after " + k);
    ws();
    if (s[i] == '"') {
      m[k] = str();
    } else {
      const size_t e = s.find_first_of(",}", i);
      m[k] = s.substr(i, e - i);
      i = e;
    }
    ws();
    if (s[i] == ',') ++i, ws();
  }
  return m;
}

}  // namespace

TEST(CliBatch, GivenManyInputsWithOneBadThenOthersWrittenAndExitNonZero) {
  capz_test::TempDir d("capz_cli_batch");
  const std::string dir = d.path().string();
  fs::copy_file(repo("admarche2.c3d"), d.file("a.c3d"));
  std::ofstream(d.file("bad.c3d")) << "this is not a C3D file at all, but it says .c3d";
  fs::copy_file(repo("std_walking5_markers.trc"), d.file("w.trc"));
  Result r = shell(dir, "capz compress a.c3d bad.c3d missing.trc w.trc");
  EXPECT_NE(r.status, 0);
  EXPECT_TRUE(fs::exists(d.file("a.c3d.capz")));
  EXPECT_TRUE(fs::exists(d.file("w.trc.capz")));
  EXPECT_FALSE(fs::exists(d.file("bad.c3d.capz")));
  EXPECT_FALSE(fs::exists(d.file("missing.trc.capz")));
  // One report line per good file on stdout, in input order; one error line per bad one.
  const std::vector<std::string> out = split_lines(r.out);
  ASSERT_EQ(out.size(), 2u) << r.out;
  EXPECT_EQ(out[0].rfind("a.c3d -> a.c3d.capz: ", 0), 0u) << r.out;
  EXPECT_EQ(out[1].rfind("w.trc -> w.trc.capz: ", 0), 0u) << r.out;
  // a.c3d's reader warning (4th words beyond 16 bits) as it is read, the errors in input order.
  EXPECT_NE(r.err.find("capz compress: warning: a.c3d: 2649 samples"), std::string::npos) << r.err;
  const std::vector<std::string> err = split_lines(capz_test::without_warnings(r.err));
  ASSERT_EQ(err.size(), 2u) << r.err;
  EXPECT_EQ(err[0].rfind("capz compress: error: bad.c3d: ", 0), 0u) << r.err;
  EXPECT_EQ(err[1].rfind("capz compress: error: missing.trc: ", 0), 0u) << r.err;
  // The exit status is the first failure's: bad.c3d is not a C3D it can read (3 or 5).
  EXPECT_TRUE(r.status == 3 || r.status == 5) << r.status << " " << r.err;

  // Existing outputs: refused without -f (each file one line, exit 1), replaced with -f.
  const auto before = fs::last_write_time(d.file("a.c3d.capz"));
  Result again = shell(dir, "capz compress -q a.c3d w.trc");
  EXPECT_EQ(again.status, 1);
  EXPECT_EQ(count_lines(again.err), 2u) << again.err;
  EXPECT_NE(again.err.find("a.c3d.capz"), std::string::npos) << again.err;
  EXPECT_EQ(fs::last_write_time(d.file("a.c3d.capz")), before);
  EXPECT_EQ(shell(dir, "capz compress -q -f a.c3d w.trc").status, 0);

  // decompress of many: a damaged archive in the middle, the others written.
  std::vector<uint8_t> b = capz::read_file(d.file("a.c3d.capz"));
  b.resize(b.size() / 2);
  capz::write_file(d.file("bad.capz"), b, false);  // a truncated copy of a.c3d.capz
  fs::create_directories(d.file("back"));
  Result dr =
      shell(dir, "capz decompress -q bad.capz a.c3d.capz w.trc.capz --output-dir-flat back");
  EXPECT_EQ(dr.status, 5) << dr.err;
  EXPECT_TRUE(fs::exists(d.file("back/a.c3d")));
  EXPECT_TRUE(fs::exists(d.file("back/w.trc")));
  EXPECT_EQ(count_lines(dr.err), 1u) << dr.err;
  EXPECT_NE(dr.err.find("bad.capz"), std::string::npos) << dr.err;
  EXPECT_EQ(std::distance(fs::directory_iterator(d.file("back")), fs::directory_iterator()), 2);
}

// The output folders a run makes (--output-dir-mirror, --output-dir-flat) for outputs it does not
// write (a bad input) are removed at its end, those it did not make kept, empty or not.
TEST(CliBatch, GivenFailedOutputsThenTheEmptyFoldersTheRunMadeAreRemoved) {
  capz_test::TempDir d("capz_cli_batch");
  const std::string dir = d.path().string();
  fs::create_directories(d.file("t/good"));
  fs::create_directories(d.file("t/bad/deeper"));
  fs::copy_file(repo("EB015PI.c3d"), d.file("t/good/e.c3d"));
  std::ofstream(d.file("t/bad/deeper/x.c3d")) << "this is not a C3D file at all";
  fs::create_directories(d.file("m/t/bad"));  // there before the run: kept
  Result r = shell(dir, "capz compress -r -q t --output-dir-mirror m");
  EXPECT_NE(r.status, 0);
  EXPECT_TRUE(fs::is_regular_file(d.file("m/t/good/e.c3d.capz")));
  EXPECT_FALSE(fs::exists(d.file("m/t/bad/deeper"))) << "left by a failed output";
  EXPECT_TRUE(fs::is_directory(d.file("m/t/bad")));
  // Every output failed: the flat folder and the mirror tree go, all of them made by the run.
  EXPECT_NE(shell(dir, "capz compress -q t/bad/deeper/x.c3d --output-dir-flat f/g").status, 0);
  EXPECT_FALSE(fs::exists(d.file("f")));
  // decompress: a truncated archive in a folder of its own, beside a good one, two at a time.
  std::vector<uint8_t> b = capz::read_file(d.file("m/t/good/e.c3d.capz"));
  b.resize(b.size() / 2);
  fs::create_directories(d.file("z/sub"));
  capz::write_file(d.file("z/sub/cut.c3d.capz"), b, false);
  EXPECT_EQ(shell(dir, "capz decompress -q -r -T 2 m/t/good z --output-dir-mirror back").status, 5);
  EXPECT_TRUE(fs::is_regular_file(d.file("back/m/t/good/e.c3d")));
  EXPECT_FALSE(fs::exists(d.file("back/z")));
  EXPECT_NE(shell(dir, "capz compress -r -q t/bad --output-dir-mirror n").status, 0);
  EXPECT_FALSE(fs::exists(d.file("n")));
}

TEST(CliBatch, GivenOneOutputOptionForManyInputsThenUsageErrorAndNothingWritten) {
  capz_test::TempDir d("capz_cli_batch");
  const std::string dir = d.path().string();
  fs::copy_file(repo("admarche2.c3d"), d.file("a.c3d"));
  fs::copy_file(repo("EB015PI.c3d"), d.file("e.c3d"));
  Result o = shell(dir, "capz compress a.c3d e.c3d -o x.capz");
  EXPECT_EQ(o.status, 1);
  EXPECT_NE(o.err.find("-o takes a single input"), std::string::npos) << o.err;
  Result c = shell(dir, "capz compress -c a.c3d e.c3d");
  EXPECT_EQ(c.status, 1);
  EXPECT_NE(c.err.find("-c takes a single input"), std::string::npos) << c.err;
  Result both = shell(dir, "capz compress a.c3d --output-dir-flat x --output-dir-mirror y");
  EXPECT_EQ(both.status, 1);
  EXPECT_EQ(std::distance(fs::directory_iterator(d.path()), fs::directory_iterator()), 2);
  // -o with one input still works (the single-file form).
  EXPECT_EQ(shell(dir, "capz compress -q a.c3d -o x.capz").status, 0);
  EXPECT_TRUE(fs::exists(d.file("x.capz")));
}

TEST(CliBatch, GivenTreeWhenRecursiveThenMirrorAndFlatFoldersAndLosslessBack) {
  capz_test::TempDir d("capz_cli_batch");
  const std::string dir = d.path().string();
  make_tree(dir);
  Result m = shell(dir, "capz compress -r -q --lossless t --output-dir-mirror m");
  ASSERT_EQ(m.status, 0) << m.err;
  for (const std::string& a : kTreeArchives)
    EXPECT_TRUE(fs::is_regular_file(d.file("m/" + a))) << a;
  EXPECT_FALSE(fs::exists(d.file("t/s1/a.c3d.capz")));  // nothing beside the inputs
  EXPECT_FALSE(fs::exists(d.file("m/t/s2/notes.txt.capz")));
  size_t files = 0;
  for (const auto& e : fs::recursive_directory_iterator(d.file("m")))
    files += e.is_regular_file() ? 1 : 0;
  EXPECT_EQ(files, kTreeArchives.size());

  Result f = shell(dir, "capz compress -r -q --lossless t/s1 t/s2 --output-dir-flat f");
  ASSERT_EQ(f.status, 0) << f.err;
  for (const char* a : {"a.c3d.capz", "e.c3d.capz", "w.trc.capz", "frames.capz"})
    EXPECT_TRUE(fs::is_regular_file(d.file(std::string("f/") + a))) << a;

  // Beside the inputs (the default), then decompress -r into a mirror: the files back exactly.
  ASSERT_EQ(shell(dir, "capz compress -r -q --lossless t").status, 0);
  for (const std::string& a : kTreeArchives) EXPECT_TRUE(fs::is_regular_file(d.file(a))) << a;
  Result back = shell(dir, "capz decompress -r -q t --output-dir-mirror back");
  ASSERT_EQ(back.status, 0) << back.err;
  for (const char* t : {"t/s1/a.c3d", "t/s1/e.c3d", "t/s2/w.trc"})
    EXPECT_EQ(capz::read_file(d.file(std::string("back/") + t)), capz::read_file(d.file(t))) << t;
  EXPECT_TRUE(fs::is_directory(d.file("back/t/s2/frames")));
  // Two inputs of one name into one flat folder: the second fails, the first is kept.
  fs::create_directories(d.file("u"));
  fs::copy_file(repo("EB015PI.c3d"), d.file("u/a.c3d"));
  Result clash = shell(dir, "capz compress -q t/s1/a.c3d u/a.c3d --output-dir-flat g");
  EXPECT_EQ(clash.status, 1);
  EXPECT_NE(clash.err.find("also the output of t/s1/a.c3d"), std::string::npos) << clash.err;
  EXPECT_TRUE(fs::exists(d.file("g/a.c3d.capz")));
  // A folder given to decompress without -r is one failure, not a walk.
  Result nr = shell(dir, "capz decompress -q t");
  EXPECT_EQ(nr.status, 1);
  EXPECT_NE(nr.err.find("use -r"), std::string::npos) << nr.err;
}

// A folder of frames holding a subfolder of frames (t/a/*.pcd, t/a/sub/*.pcd): its archive tree
// holds a.capz beside the folder a/ that holds sub.capz, so restoring a.capz meets a/ already
// there ("output exists", with -f "refusing to replace"). Both restored now, in place and into a
// mirror: the frames go in beside what a/ holds. A folder holding frames already still refuses.
TEST(CliBatch, GivenAFolderOfFramesHoldingASubfolderOfFramesThenDecompressRestoresBoth) {
  capz_test::TempDir d("capz_cli_batch");
  const std::string dir = d.path().string();
  fs::create_directories(d.file("t/a/sub"));
  std::vector<std::string> frames;
  for (const auto& f : fs::directory_iterator(repo("synth_wave")))
    if (f.path().extension() == ".pcd" && frames.size() < 3) {
      frames.push_back(f.path().filename().string());
      fs::copy_file(f.path(), d.file("t/a/" + frames.back()));
      fs::copy_file(f.path(), d.file("t/a/sub/" + frames.back()));
    }
  ASSERT_EQ(frames.size(), 3u);
  const auto same_frames = [&](const std::string& root) {
    for (const char* folder : {"/t/a/", "/t/a/sub/"})
      for (const std::string& f : frames)
        EXPECT_EQ(capz::read_file(d.file(root + folder + f)),
                  capz::read_file(d.file("t/a/sub/" + f)))
            << root << folder << f;
  };
  Result r = shell(dir, "capz compress -r -q --lossless t --output-dir-mirror m");
  ASSERT_EQ(r.status, 0) << r.err;
  ASSERT_TRUE(fs::is_regular_file(d.file("m/t/a/sub.capz")));
  r = shell(dir, "capz decompress -r -q m/t --output-dir-mirror back");
  EXPECT_EQ(r.status, 0) << r.err;
  same_frames("back/m");
  r = shell(dir, "capz decompress -r -q m/t");  // in place
  EXPECT_EQ(r.status, 0) << r.err;
  same_frames("m");
  EXPECT_TRUE(fs::is_regular_file(d.file("m/t/a/sub.capz")));
  // Through the writer too (a bound), with -f: nothing is replaced, so -f changes nothing.
  ASSERT_EQ(shell(dir, "capz compress -r -q t --output-dir-mirror lossy").status, 0);
  r = shell(dir, "capz decompress -r -q -f lossy/t");
  EXPECT_EQ(r.status, 0) << r.err;
  for (const char* folder : {"lossy/t/a/", "lossy/t/a/sub/"})
    EXPECT_EQ(capz::read_take(d.file(folder)).frames, frames.size()) << folder;
  // Once restored, a/ holds frames: a second run refuses it, with -f too (a/ holds more than
  // frames), and leaves it as it was.
  r = shell(dir, "capz decompress -q m/t/a.capz");
  EXPECT_EQ(r.status, 1);
  EXPECT_NE(r.err.find("output exists"), std::string::npos) << r.err;
  r = shell(dir, "capz decompress -q -f m/t/a.capz");
  EXPECT_EQ(r.status, 1);
  EXPECT_NE(r.err.find("refusing to replace"), std::string::npos) << r.err;
  same_frames("m");
}

// Frames that go in beside what a folder holds (a .capz archive, a hidden file): the report's
// bytes out are the frames', not the folder's whole (which counted the archive's bytes too).
TEST(CliBatch, GivenFramesDecompressedBesideAnArchiveThenBytesOutCountTheFramesOnly) {
  capz_test::TempDir d("capz_cli_batch");
  const std::string dir = d.path().string();
  fs::create_directories(d.file("t"));
  fs::create_directories(d.file("out"));
  size_t copied = 0;
  for (const auto& f : fs::directory_iterator(repo("synth_wave")))
    if (f.path().extension() == ".pcd" && copied < 3) {
      fs::copy_file(f.path(), d.file("t/" + f.path().filename().string()));
      ++copied;
    }
  ASSERT_EQ(shell(dir, "capz compress -q --lossless t -o t.capz").status, 0);
  fs::copy_file(d.file("t.capz"), d.file("out/held.capz"));
  { std::ofstream(d.file("out/.hidden")) << "not a frame"; }
  Result r = shell(dir, "capz decompress -q t.capz -o out --report d.jsonl");
  ASSERT_EQ(r.status, 0) << r.err;
  uint64_t frames = 0;
  for (const auto& f : fs::directory_iterator(d.file("t"))) frames += fs::file_size(f.path());
  std::map<std::string, std::string> dd = parse_object(file_text(d.file("d.jsonl")));
  EXPECT_EQ(std::stoull(dd["bytes_out"]), frames);
  EXPECT_TRUE(fs::is_regular_file(d.file("out/held.capz")));
}

TEST(CliBatch, GivenThreadCountsThenArchivesIdentical) {
  capz_test::TempDir d("capz_cli_batch");
  const std::string dir = d.path().string();
  make_tree(dir);
  for (const char* t : {"1", "2", "8", "0"}) {
    Result r =
        shell(dir, std::string("capz compress -r -q -T ") + t + " t --output-dir-mirror T" + t);
    ASSERT_EQ(r.status, 0) << t << ": " << r.err;
  }
  for (const std::string& a : kTreeArchives) {
    const std::vector<uint8_t> one = capz::read_file(d.file("T1/" + a));
    for (const char* t : {"2", "8", "0"})
      EXPECT_EQ(capz::read_file(d.file(std::string("T") + t + "/" + a)), one) << a << " -T " << t;
  }
  // Per-file lines come in input order whatever -T.
  Result one = shell(dir, "capz compress -r -T 1 t --output-dir-flat L1");
  Result four = shell(dir, "capz compress -r -T 4 t --output-dir-flat L4");
  ASSERT_EQ(one.status, 0);
  ASSERT_EQ(four.status, 0);
  auto names = [](const std::string& out) {
    std::vector<std::string> v;
    for (const std::string& l : split_lines(out)) v.push_back(l.substr(0, l.find(" -> ")));
    return v;
  };
  EXPECT_EQ(names(one.out), names(four.out));
  EXPECT_EQ(names(one.out).size(), kTreeArchives.size());
}

TEST(CliBatch, GivenPipesThenStdinToStdoutWithFormatFromBytes) {
  capz_test::TempDir d("capz_cli_batch");
  const std::string dir = d.path().string();
  fs::create_directories(d.file("tmp"));
  const std::string env = "TMPDIR='" + d.file("tmp") + "' ";
  for (const std::string take : {"admarche2.c3d", "std_walking5_markers.trc"}) {
    const std::string src = repo(take);
    // No input while stdin is a pipe, and '-': the same archive.
    Result a = shell(dir, env + "capz compress -v --lossless < '" + src + "' > x.capz");
    ASSERT_EQ(a.status, 0) << a.err;
    // With -v on stderr (after admarche2's reader warning, which names the input stdin).
    EXPECT_EQ(capz_test::without_warnings(a.err).rfind("stdin -> stdout: ", 0), 0u) << a.err;
    EXPECT_EQ(a.err.find("/stdin"), std::string::npos) << a.err;
    const Result quiet = shell(dir, env + "capz compress --lossless < '" + src + "' > x2.capz");
    EXPECT_EQ(capz_test::without_warnings(quiet.err), "") << quiet.err;
    Result b = shell(dir, env + "cat '" + src + "' | capz compress -q --lossless - > y.capz");
    ASSERT_EQ(b.status, 0) << b.err;
    EXPECT_EQ(capz::read_file(d.file("x.capz")), capz::read_file(d.file("y.capz")));
    // decompress of a pipe: the source's format, byte for byte (lossless).
    Result back = shell(dir, env + "cat x.capz | capz decompress -q > back");
    ASSERT_EQ(back.status, 0) << back.err;
    EXPECT_EQ(capz::read_file(d.file("back")), capz::read_file(src)) << take;
    // -c from a file, both ways.
    Result c = shell(dir, env + "capz compress -q -c --lossless '" + src + "' > z.capz");
    ASSERT_EQ(c.status, 0) << c.err;
    Result dc = shell(dir, env + "capz decompress -q -c z.capz > back2");
    ASSERT_EQ(dc.status, 0) << dc.err;
    EXPECT_EQ(capz::read_file(d.file("back2")), capz::read_file(src)) << take;
    // stdin to a file with -o.
    Result o = shell(dir, env + "capz compress -q --lossless -o o.capz < '" + src + "'");
    ASSERT_EQ(o.status, 0) << o.err;
    EXPECT_EQ(capz::read_file(d.file("o.capz")), capz::read_file(d.file("x.capz")));
    for (const char* f : {"x.capz", "x2.capz", "y.capz", "z.capz", "o.capz", "back", "back2"})
      fs::remove(d.file(f));
  }
  // Bytes of no take: not-our-format, nothing on stdout; an archive given to compress says so.
  Result bad = shell(dir, env + "echo 'hello' | capz compress > junk");
  EXPECT_EQ(bad.status, 3);
  EXPECT_NE(bad.err.find("stdin: not a C3D or TRC stream"), std::string::npos) << bad.err;
  EXPECT_EQ(fs::file_size(d.file("junk")), 0u);
  ASSERT_EQ(shell(dir, env + "capz compress -q -c '" + repo("admarche2.c3d") + "' > a.capz").status,
            0);
  Result twice = shell(dir, env + "capz compress < a.capz > junk");
  EXPECT_EQ(twice.status, 3);
  EXPECT_NE(twice.err.find("stdin: is a .capz archive"), std::string::npos) << twice.err;
  Result notz = shell(dir, env + "capz decompress < '" + repo("admarche2.c3d") + "' > junk");
  EXPECT_EQ(notz.status, 3);
  EXPECT_NE(notz.err.find("stdin: not a .capz archive"), std::string::npos) << notz.err;
  // A PCD sequence is a folder: it cannot go to stdout.
  ASSERT_EQ(shell(dir, env + "capz compress -q '" + repo("synth_wave") + "' -o wave.capz").status,
            0);
  Result pcd = shell(dir, env + "capz decompress -c wave.capz > junk");
  EXPECT_EQ(pcd.status, 1);
  EXPECT_NE(pcd.err.find("cannot go to stdout"), std::string::npos) << pcd.err;
  // '-' with other inputs is a usage error.
  EXPECT_EQ(shell(dir, env + "capz compress - a.capz < a.capz").status, 1);
  // Every temporary went.
  EXPECT_EQ(std::distance(fs::directory_iterator(d.file("tmp")), fs::directory_iterator()), 0);
}

TEST(CliBatch, GivenReportThenOneParsableLinePerFileInInputOrder) {
  capz_test::TempDir d("capz_cli_batch");
  const std::string dir = d.path().string();
  fs::copy_file(repo("admarche2.c3d"), d.file("a.c3d"));
  std::ofstream(d.file("bad.trc")) << "PathFileType\t4\t(X/Y/Z)\tbad.trc\nnothing else\n";
  fs::copy_file(repo("std_walking5_markers.trc"), d.file("w.trc"));
  Result r =
      shell(dir, "capz compress -q -T 2 --max-error 0.05mm a.c3d bad.trc w.trc --report r.jsonl");
  EXPECT_NE(r.status, 0);
  const std::vector<std::string> lines = split_lines(file_text(d.file("r.jsonl")));
  ASSERT_EQ(lines.size(), 3u);
  std::vector<std::map<std::string, std::string>> rec;
  for (const std::string& l : lines) {
    try {
      rec.push_back(parse_object(l));
    } catch (const std::exception& e) {
      FAIL() << e.what() << " in " << l;
    }
  }
  EXPECT_EQ(rec[0]["input"], "a.c3d");
  EXPECT_EQ(rec[1]["input"], "bad.trc");
  EXPECT_EQ(rec[2]["input"], "w.trc");
  for (int i : {0, 2}) {
    EXPECT_EQ(rec[i]["ok"], "true");
    EXPECT_EQ(rec[i]["error"], "null");
    EXPECT_EQ(rec[i]["output"], rec[i]["input"] + ".capz");
    EXPECT_EQ(std::stoull(rec[i]["bytes_in"]), fs::file_size(d.file(rec[i]["input"])));
    EXPECT_EQ(std::stoull(rec[i]["bytes_out"]), fs::file_size(d.file(rec[i]["output"])));
    EXPECT_NEAR(std::stod(rec[i]["ratio"]),
                std::stod(rec[i]["bytes_in"]) / std::stod(rec[i]["bytes_out"]), 1e-9);
    EXPECT_EQ(rec[i]["units"], "mm");
    EXPECT_DOUBLE_EQ(std::stod(rec[i]["bound"]), 0.05);
    EXPECT_LE(std::stod(rec[i]["max_error"]), 0.05);
    EXPECT_GT(std::stod(rec[i]["max_error"]), 0);
    EXPECT_EQ(rec[i]["checksum"].size(), 32u);  // the original's XXH3-128, hex
    EXPECT_GE(std::stod(rec[i]["seconds"]), 0);
    EXPECT_EQ(rec[i]["lossless"], "false");
  }
  EXPECT_EQ(rec[1]["ok"], "false");
  EXPECT_EQ(rec[1]["output"], "null");
  EXPECT_NE(rec[1]["error"].find("bad.trc"), std::string::npos);
  // The checksum is the one `capz list` shows.
  Result l = shell(dir, "capz list a.c3d.capz");
  EXPECT_NE(l.out.find("xxh3-128 " + rec[0]["checksum"]), std::string::npos) << l.out;
  // The report is not overwritten without -f: refused before any file is coded.
  fs::remove(d.file("a.c3d.capz"));
  Result again = shell(dir, "capz compress -q a.c3d --report r.jsonl");
  EXPECT_EQ(again.status, 1);
  EXPECT_FALSE(fs::exists(d.file("a.c3d.capz")));
  EXPECT_EQ(count_lines(file_text(d.file("r.jsonl"))), 3u);
  // decompress reports too: bytes of the archive in, of the take out.
  ASSERT_EQ(shell(dir, "capz compress -q --lossless a.c3d").status, 0);
  Result dr = shell(dir, "capz decompress -q a.c3d.capz -o b.c3d --report d.jsonl");
  ASSERT_EQ(dr.status, 0) << dr.err;
  std::map<std::string, std::string> dd = parse_object(file_text(d.file("d.jsonl")));
  EXPECT_EQ(dd["output"], "b.c3d");
  EXPECT_EQ(std::stoull(dd["bytes_out"]), fs::file_size(d.file("a.c3d")));
  EXPECT_EQ(dd["lossless"], "true");
  EXPECT_EQ(dd["bound"], "0");
}

TEST(CliBatch, GivenManyArchivesThenTestAndListOneLineEachAndRecursive) {
  capz_test::TempDir d("capz_cli_batch");
  const std::string dir = d.path().string();
  make_tree(dir);
  ASSERT_EQ(shell(dir, "capz compress -r -q --lossless -T 2 t").status, 0);
  Result t = shell(dir, "capz test -r -T 2 t");
  EXPECT_EQ(t.status, 0) << t.out << t.err;
  const std::vector<std::string> lines = split_lines(t.out);
  ASSERT_EQ(lines.size(), kTreeArchives.size()) << t.out;
  for (size_t i = 0; i < lines.size(); ++i)
    EXPECT_EQ(lines[i].rfind(kTreeArchives[i] + ": OK, ", 0), 0u) << lines[i];
  // A damaged archive among them: its line says FAILED, the others OK, exit status 1.
  std::vector<uint8_t> b = capz::read_file(d.file("t/s1/e.c3d.capz"));
  b[b.size() / 2] ^= 0x40;
  capz::write_file(d.file("t/s1/e.c3d.capz"), b, true);
  Result bad = shell(dir, "capz test -r t --report t.jsonl");
  EXPECT_EQ(bad.status, 1);
  EXPECT_EQ(count_lines(bad.out), kTreeArchives.size()) << bad.out;
  EXPECT_NE(bad.out.find("t/s1/e.c3d.capz: FAILED"), std::string::npos) << bad.out;
  EXPECT_NE(bad.out.find("t/s1/a.c3d.capz: OK"), std::string::npos) << bad.out;
  const std::vector<std::string> rep = split_lines(file_text(d.file("t.jsonl")));
  ASSERT_EQ(rep.size(), kTreeArchives.size());
  EXPECT_EQ(parse_object(rep[1])["ok"], "false");
  EXPECT_EQ(parse_object(rep[0])["ok"], "true");
  EXPECT_EQ(parse_object(rep[0])["checksum"].size(), 32u);
  // An existing report: refused without -f (status 1, nothing run), replaced with it.
  Result kept = shell(dir, "capz test t/s1/a.c3d.capz --report t.jsonl");
  EXPECT_EQ(kept.status, 1);
  EXPECT_EQ(kept.out, "");
  EXPECT_EQ(shell(dir, "capz test -f t/s1/a.c3d.capz --report t.jsonl").status, 0);
  EXPECT_EQ(count_lines(file_text(d.file("t.jsonl"))), 1u);
  // list over many, and a folder without -r is one failure.
  Result l = shell(dir, "capz list t/s1/a.c3d.capz t/s2/w.trc.capz t/s2/frames.capz");
  EXPECT_EQ(l.status, 0);
  EXPECT_EQ(count_lines(l.out), 3u) << l.out;
  EXPECT_NE(l.out.find("w.trc.capz: w.trc (trc)"), std::string::npos) << l.out;
  Result lr = shell(dir, "capz list -r t/s2");
  EXPECT_EQ(lr.status, 0);
  EXPECT_EQ(count_lines(lr.out), 2u) << lr.out;
  Result nr = shell(dir, "capz list t/s2");
  EXPECT_EQ(nr.status, 1);
  EXPECT_NE(nr.out.find("t/s2: FAILED: t/s2: is a folder (use -r"), std::string::npos) << nr.out;
}

// The progress line: on a terminal (util-linux `script` gives the run one), off with -q and
// when stderr is not a terminal.
TEST(CliBatch, GivenTerminalThenProgressLineUnlessQuiet) {
  if (std::system("command -v script >/dev/null 2>&1") != 0) {
    GTEST_SKIP() << "util-linux 'script' not found: no terminal to show the progress line on";
  }
  capz_test::TempDir d("capz_cli_batch");
  const std::string dir = d.path().string();
  make_tree(dir);
  Result tty = shell(dir, "script -qec \"$CAPZ compress -r t --output-dir-flat a\" /dev/null");
  ASSERT_EQ(tty.status, 0) << tty.out;
  EXPECT_NE(tty.out.find("capz compress: 4 / 4 files, "), std::string::npos) << tty.out;
  EXPECT_NE(tty.out.find(" MB/s"), std::string::npos) << tty.out;
  Result quiet = shell(dir, "script -qec \"$CAPZ compress -q -r t --output-dir-flat b\" /dev/null");
  ASSERT_EQ(quiet.status, 0) << quiet.out;
  EXPECT_EQ(quiet.out.find("files, "), std::string::npos) << quiet.out;
  Result pipe = shell(dir, "capz compress -r t --output-dir-flat c");
  ASSERT_EQ(pipe.status, 0);
  EXPECT_EQ(capz_test::without_warnings(pipe.err), "") << pipe.err;
}

// The readers' warnings and the notes of a batch come with their file's lines, in input order
// whatever -T, and on a terminal after the progress line is cleared, never glued to it.
TEST(CliBatch, GivenNotesOfSeveralFilesThenEachWithItsFileInInputOrder) {
  capz_test::TempDir d("capz_cli_batch");
  const std::string dir = d.path().string();
  make_tree(dir);
  // A warning of a.c3d's (4th words beyond 16 bits), and a note for each file: no channel is
  // named nosuch.
  const std::string args = " t --analog-max-error nosuch=1 --output-dir-flat ";
  const Result r = shell(dir, "capz compress -r -T 4" + args + "f");
  ASSERT_EQ(r.status, 0) << r.err;
  std::vector<std::string> inputs;  // in input order, from the per-file lines
  for (const std::string& l : split_lines(r.out)) inputs.push_back(l.substr(0, l.find(" -> ")));
  ASSERT_EQ(inputs.size(), kTreeArchives.size()) << r.out;
  std::vector<size_t> order;  // the input each stderr line names
  for (const std::string& l : split_lines(r.err)) {
    size_t i = 0;
    while (i < inputs.size() && l.find(": " + inputs[i] + ": ") == std::string::npos) ++i;
    ASSERT_LT(i, inputs.size()) << "names no input: " << l;
    order.push_back(i);
  }
  ASSERT_EQ(order.size(), kTreeArchives.size() + 1) << r.err;
  EXPECT_TRUE(std::is_sorted(order.begin(), order.end())) << r.err;

  if (std::system("command -v script >/dev/null 2>&1") != 0) {
    GTEST_SKIP() << "util-linux 'script' not found: no terminal to show the progress line on";
  }
  for (const char* t : {"1", "4"}) {
    const Result tty = shell(dir, std::string("script -qec \"$CAPZ compress -r -T ") + t + args +
                                      "tty" + t + "\" /dev/null");
    ASSERT_EQ(tty.status, 0) << tty.out;
    size_t lines = 0;
    for (size_t at = tty.out.find("capz compress: "); at != std::string::npos;
         at = tty.out.find("capz compress: ", at + 1)) {
      if (tty.out.compare(at, 21, "capz compress: note: ") != 0 &&
          tty.out.compare(at, 24, "capz compress: warning: ") != 0)
        continue;  // the progress line
      ++lines;
      const bool after_clear = at >= 3 && tty.out.compare(at - 3, 3, "\033[K") == 0;
      const bool line_start = at > 0 && tty.out[at - 1] == '\n';
      EXPECT_TRUE(after_clear || line_start) << "-T " << t << ": " << tty.out.substr(0, at + 40);
    }
    EXPECT_EQ(lines, order.size()) << "-T " << t << ": " << tty.out;
  }
}

// docs/ARCHIVE.md, GNU parallel: the one-host recipe and --sshlogin with this host (':').
TEST(CliRecipes, GivenGnuParallelThenEveryTakeCompressed) {
  if (std::system("command -v parallel >/dev/null 2>&1") != 0) {
    GTEST_SKIP() << "GNU parallel not installed (Debian package 'parallel'): the recipe of "
                    "docs/ARCHIVE.md is not run";
  }
  capz_test::TempDir d("capz_cli_batch");
  const std::string dir = d.path().string();
  make_tree(dir);
  const std::string find = "find t -type f \\( -iname '*.c3d' -o -iname '*.trc' \\) -print0 | ";
  Result one = shell(dir, find + "parallel -0 -j2 --joblog j1 \"$CAPZ\" compress -q --lossless {}");
  ASSERT_EQ(one.status, 0) << one.err;
  for (const char* a : {"t/s1/a.c3d.capz", "t/s1/e.c3d.capz", "t/s2/w.trc.capz"})
    EXPECT_TRUE(fs::is_regular_file(d.file(a))) << a;
  Result failed = shell(dir, "awk -F'\\t' 'NR > 1 && $7 != 0 { print $9 }' j1");
  EXPECT_EQ(failed.status, 0);
  EXPECT_EQ(failed.out, "");  // no take failed
  EXPECT_EQ(shell(dir, "capz test -r t").status, 0);
  Result ssh = shell(dir, find +
                              "parallel -0 --sshlogin 2/: --joblog j2 \"$CAPZ\" compress -q "
                              "--output-dir-mirror m {}");
  ASSERT_EQ(ssh.status, 0) << ssh.err;
  for (const char* a : {"m/t/s1/a.c3d.capz", "m/t/s1/e.c3d.capz", "m/t/s2/w.trc.capz"})
    EXPECT_TRUE(fs::is_regular_file(d.file(a))) << a;
  // Rerun: every take refused (exists), the joblog says so.
  Result again = shell(dir, find + "parallel -0 -j2 \"$CAPZ\" compress -q {}");
  EXPECT_NE(again.status, 0);
}

// docs/ARCHIVE.md, Slurm: the task body run once per index with SLURM_ARRAY_TASK_ID set, as
// sbatch --array would; every take done exactly once.
TEST(CliRecipes, GivenSlurmArrayScriptThenEveryTakeDoneExactlyOnce) {
  capz_test::TempDir d("capz_cli_batch");
  const std::string dir = d.path().string();
  make_tree(dir);
  fs::copy_file(repo("Capture0004.c3d"), d.file("t/s1/c.c3d"));
  const std::string script = std::string(CAPZ_TEST_DIR) + "/../tools/slurm/capz-array.sh";
  ASSERT_TRUE(fs::exists(script)) << script;
  ASSERT_EQ(shell(dir,
                  "(find t -type f \\( -iname '*.c3d' -o -iname '*.trc' \\); find t -iname "
                  "'*.pcd' -printf '%h\\n' | sort -u) > takes.txt")
                .status,
            0);
  const std::vector<std::string> takes = split_lines(file_text(d.file("takes.txt")));
  ASSERT_EQ(takes.size(), 5u);
  const int K = 3;
  Result split = shell(dir, "'" + script + "' --split takes.txt " + std::to_string(K) + " lists");
  ASSERT_EQ(split.status, 0) << split.err;
  for (int i = 0; i < K; ++i) {
    Result r = shell(dir, "SLURM_ARRAY_TASK_ID=" + std::to_string(i) + " SLURM_CPUS_PER_TASK=2 '" +
                              script + "' lists --lossless --output-dir-mirror out");
    ASSERT_EQ(r.status, 0) << "task " << i << ": " << r.err;
  }
  std::map<std::string, int> done;
  for (int i = 0; i < K; ++i)
    for (const std::string& l :
         split_lines(file_text(d.file("lists/report." + std::to_string(i) + ".jsonl")))) {
      std::map<std::string, std::string> rec = parse_object(l);
      EXPECT_EQ(rec["ok"], "true") << l;
      ++done[rec["input"]];
    }
  EXPECT_EQ(done.size(), takes.size());
  for (const std::string& t : takes) {
    EXPECT_EQ(done[t], 1) << t;
    EXPECT_TRUE(fs::is_regular_file(d.file("out/" + t + ".capz"))) << t;
  }
  // Without SLURM_ARRAY_TASK_ID the task body refuses to guess.
  EXPECT_NE(shell(dir, "'" + script + "' lists").status, 0);
}
