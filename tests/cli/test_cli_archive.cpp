// capz test and capz list (docs/CLI.md): one line per file, exit status 0 / 1, and decompress
// giving a --lossless C3D back byte for byte (--rm deleting only then), and a PCD folder.
#include <gtest/gtest.h>
#include <sys/wait.h>

#include <algorithm>
#include <cstdlib>
#include <filesystem>
#include <fstream>
#include <sstream>
#include <string>
#include <vector>

#include "capz/tool/file.h"
#include "corrupt/chunk_util.h"
#include "test_util.h"

namespace fs = std::filesystem;

namespace {

using Result = capz_test::CliResult;

Result run(const std::string& args) {
  static capz_test::TempDir io("capz_cli_archive_io");
  return capz_test::run_command(CAPZ_CLI, args, io.file("out"));
}

size_t lines(const std::string& s) {
  return static_cast<size_t>(std::count(s.begin(), s.end(), '\n'));
}

}  // namespace

TEST(CliArchive, LosslessRoundTripTestAndList) {
  capz_test::TempDir d("capz_cli_archive");
  const std::string src = std::string(CAPZ_REPO_DATA) + "/admarche2.c3d";
  const std::string in = d.file("a.c3d"), z = d.file("a.c3d.capz"), zb = d.file("b.capz");
  fs::copy_file(src, in);
  ASSERT_EQ(run("compress --lossless --rm -q '" + in + "' -o '" + z + "'").status, 0);
  EXPECT_FALSE(fs::exists(in));  // --rm: the archive rebuilt IN's bytes, hash checked
  ASSERT_EQ(run("compress -q '" + src + "' -o '" + zb + "'").status, 0);
  ASSERT_EQ(run("decompress -q '" + z + "'").status, 0);  // default OUT: a.c3d
  EXPECT_EQ(capz::read_file(in), capz::read_file(src));

  Result t = run("test '" + z + "' '" + zb + "'");
  EXPECT_EQ(t.status, 0) << t.out;
  EXPECT_EQ(lines(t.out), 2u) << t.out;
  EXPECT_NE(t.out.find(z + ": OK, 159 frames decoded, original rebuilt ("), std::string::npos)
      << t.out;
  // At a bound the archive rebuilds the C3D around regenerated frames: test checks its size.
  EXPECT_NE(t.out.find(zb +
                       ": OK, 159 frames decoded, not lossless: original rebuilt at the "
                       "bound (" +
                       std::to_string(fs::file_size(src)) + " bytes, size checked)"),
            std::string::npos)
      << t.out;

  Result l = run("list '" + z + "' '" + zb + "'");
  EXPECT_EQ(l.status, 0) << l.out;
  EXPECT_EQ(lines(l.out), 2u) << l.out;
  EXPECT_NE(l.out.find("admarche2.c3d (c3d) frames 159 points 17 analog 8"), std::string::npos)
      << l.out;
  EXPECT_NE(l.out.find("lossless ratio 0."), std::string::npos) << l.out;
  EXPECT_NE(l.out.find("max-error 0.1"), std::string::npos) << l.out;
}

TEST(CliArchive, TestAndListFailOnADamagedFile) {
  capz_test::TempDir d("capz_cli_archive_bad");
  const std::string src = std::string(CAPZ_REPO_DATA) + "/admarche2.c3d";
  const std::string z = d.file("a.capz"), bad = d.file("bad.capz");
  ASSERT_EQ(run("compress --lossless -q '" + src + "' -o '" + z + "'").status, 0);
  std::vector<uint8_t> b = capz::read_file(z);
  b[b.size() / 2] ^= 0x40;
  capz::write_file(bad, b, true);
  Result t = run("test '" + z + "' '" + bad + "'");
  EXPECT_EQ(t.status, 1) << t.out;
  EXPECT_EQ(lines(t.out), 2u) << t.out;
  EXPECT_NE(t.out.find(bad + ": FAILED"), std::string::npos) << t.out;
  Result l = run("list '" + d.file("missing.capz") + "'");
  EXPECT_EQ(l.status, 1) << l.out;
  EXPECT_EQ(lines(l.out), 1u) << l.out;
  // An archive needing more memory than --memlimit fails the same way, saying so; a bad size
  // is refused before any file.
  Result m = run("test '" + z + "' --memlimit 1K");
  EXPECT_EQ(m.status, 1) << m.out;
  EXPECT_NE(m.out.find(z + ": FAILED: "), std::string::npos) << m.out;
  EXPECT_NE(m.out.find("above the memory limit of 1.0 KiB"), std::string::npos) << m.out;
  EXPECT_EQ(run("test '" + z + "' --memlimit 64M").status, 0);
  EXPECT_EQ(run("test '" + z + "' --memlimit many").status, 6);
}

// A PCD folder whose frames capz's writer does not reproduce (a commented CRLF header, ASCII
// spellings, trailing bytes): --lossless gives every frame file back, test / list / info say so,
// and a frame whose rebuilt bytes differ fails decompress (status 5) naming the file.
TEST(CliArchive, PcdFolderComesBackByteForByte) {
  capz_test::TempDir d("capz_cli_archive_pcd");
  const std::string in = d.file("scan"), z = d.file("scan.capz"), out = d.file("back");
  fs::create_directories(in);
  const std::string h =
      "# scanner 7\r\nVERSION 0.7\r\nFIELDS x y z\r\nSIZE 4 4 4\r\nTYPE F F F\r\n"
      "COUNT 1 1 1\r\nWIDTH 2\r\nHEIGHT 1\r\nVIEWPOINT 0 0 0 1 0 0 0\r\n"
      "POINTS 2\r\nDATA ascii\r\n";
  const std::vector<std::string> frames = {h + "1.50 2 3\r\n4 5e+00 6\r\n",
                                           h + "1 2 3\r\n4 5 6\r\n\r\n  \n"};
  for (size_t f = 0; f < frames.size(); ++f) {
    std::ofstream o(in + "/f" + std::to_string(f) + ".pcd", std::ios::binary);
    o << frames[f];
  }
  ASSERT_EQ(run("compress --lossless -q '" + in + "' -o '" + z + "'").status, 0);
  ASSERT_EQ(run("decompress -q '" + z + "' -o '" + out + "/'").status, 0);
  for (size_t f = 0; f < frames.size(); ++f) {
    const std::vector<uint8_t> got = capz::read_file(out + "/f" + std::to_string(f) + ".pcd");
    EXPECT_EQ(std::string(got.begin(), got.end()), frames[f]);
  }
  Result t = run("test '" + z + "'");
  EXPECT_EQ(t.status, 0) << t.out;
  const size_t bytes = frames[0].size() + frames[1].size();
  EXPECT_NE(t.out.find(": OK, 2 frames decoded, original rebuilt (" + std::to_string(bytes) +
                       " bytes, xxh3-128 "),
            std::string::npos)
      << t.out;
  Result l = run("list '" + z + "'");
  EXPECT_NE(l.out.find("scan (pcd-folder) frames 2 points 2"), std::string::npos) << l.out;
  EXPECT_NE(l.out.find("lossless ratio "), std::string::npos) << l.out;
  EXPECT_EQ(l.out.find("xxh3-128 -"), std::string::npos) << l.out;
  Result i = run("info '" + z + "'");
  EXPECT_NE(i.out.find("rebuilt byte for byte (checksum checked)"), std::string::npos) << i.out;
  Result ij = run("info --json '" + z + "'");
  EXPECT_NE(ij.out.find("\"original\":{\"bytes\":" + std::to_string(bytes) + ",\"xxh3_128\":\""),
            std::string::npos)
      << ij.out;
  EXPECT_NE(ij.out.find("\"byte_exact\":true}"), std::string::npos) << ij.out;
  const std::string zb = d.file("scan_bound.capz");  // PCD at a bound: no original recorded
  ASSERT_EQ(run("compress -q --max-error 0.1 '" + in + "' -o '" + zb + "'").status, 0);
  EXPECT_NE(run("info --json '" + zb + "'").out.find("\"original\":null"), std::string::npos);

  // A bit of frame f0's recorded hash flipped (the chunk CRC fixed): its rebuilt bytes no longer
  // match it.
  std::vector<uint8_t> b = capz::read_file(z);
  const std::string tag = "PCDP";
  const auto it = std::search(b.begin(), b.end(), tag.begin(), tag.end());
  ASSERT_NE(it, b.end());
  const size_t at = static_cast<size_t>(it - b.begin());
  // Payload: window index (1 byte), then frame f0's record: varint size, hash.
  ASSERT_LT(frames[0].size(), 16384u);
  const size_t varint = frames[0].size() < 128 ? 1 : 2;
  b[at + 8 + 1 + varint] ^= 0x01;
  capz_test::fix_crc(&b, at);
  const std::string bad = d.file("bad.capz");
  capz::write_file(bad, b, true);
  Result r = run("decompress -q -f '" + bad + "' -o '" + d.file("bad_out") + "/'");
  EXPECT_EQ(r.status, 5) << r.out;
  EXPECT_NE(r.out.find("f0.pcd"), std::string::npos) << r.out;
  EXPECT_FALSE(fs::exists(d.file("bad_out")));
  EXPECT_EQ(run("test '" + bad + "'").status, 1);
}

// verify --against decoded the positions, not the residue: a lossless archive whose HASH, PCDR
// or PCDP was changed (its CRC recomputed: deliberate tampering) passed it while test and
// decompress refused. It now rebuilds the original as test does: exit status 5, naming it.
TEST(CliArchive, GivenALosslessArchiveWithItsResidueTamperedThenVerifyAgainstRefuses) {
  capz_test::TempDir d("capz_cli_archive");
  const std::string c3d = std::string(CAPZ_REPO_DATA) + "/EB015PI.c3d";
  const std::string frames = std::string(CAPZ_REPO_DATA) + "/synth_wave";
  struct Case {
    std::string original, chunk;
  };
  for (const Case& c : {Case{c3d, "HASH"}, Case{c3d, "C3DR"}, Case{frames, "HASH"},
                        Case{frames, "PCDR"}, Case{frames, "PCDP"}}) {
    const std::string z = d.file("ok.capz"), bad = d.file("bad.capz"),
                      what = c.chunk + " of " + c.original;
    ASSERT_EQ(run("compress -q -f --lossless '" + c.original + "' -o '" + z + "'").status, 0);
    Result r = run("verify '" + z + "' --against '" + c.original + "'");
    ASSERT_EQ(r.status, 0) << r.out;
    EXPECT_NE(r.out.find("  original: rebuilt from the residue, "), std::string::npos) << r.out;
    std::vector<uint8_t> b = capz::read_file(z);
    const size_t at = capz_test::find_chunk(b, c.chunk.c_str());
    ASSERT_NE(at, std::string::npos) << what;
    b[at + 8 + capz_test::chunk_len(b, at) - 1] ^= 0x01;  // the payload's last byte
    capz_test::fix_crc(&b, at);
    capz::write_file(bad, b, true);
    ASSERT_EQ(run("test '" + bad + "'").status, 1) << what;
    r = run("verify '" + bad + "' --against '" + c.original + "'");
    EXPECT_EQ(r.status, 5) << what << ": " << r.out;
    EXPECT_NE(r.out.find("capz verify: error: " + bad), std::string::npos) << what << ": " << r.out;
  }
}

// verify --against of a lossless archive also holds the --against file's bytes to the recorded
// hash: a frame file given a header comment decodes to the same take (it passed, exit 0), but it
// is not the file the archive rebuilds (exit 5, saying so).
TEST(CliArchive, GivenALosslessArchiveAndAnotherFileOfTheSameTakeThenVerifyAgainstRefuses) {
  capz_test::TempDir d("capz_cli_archive_hash");
  const std::string frames = d.file("frames"), z = d.file("l.capz");
  ASSERT_EQ(run("convert -q '" + std::string(CAPZ_REPO_DATA) + "/lidar_small' '" + frames +
                "' --pcd-encoding ascii")
                .status,
            0);
  ASSERT_EQ(run("compress -q --lossless '" + frames + "' -o '" + z + "'").status, 0);
  Result r = run("verify '" + z + "' --against '" + frames + "'");
  ASSERT_EQ(r.status, 0) << r.out;
  const std::string f = frames + "/sweep_00002.pcd";
  std::string text = capz_test::file_text(f);
  text.insert(text.find('\n') + 1, "# a comment the reader skips\n");
  capz::write_file(f, std::vector<uint8_t>(text.begin(), text.end()), true);
  r = run("verify '" + z + "' --against '" + frames + "'");
  EXPECT_EQ(r.status, 5) << r.out;
  EXPECT_NE(r.out.find("the recorded hash is not the input's"), std::string::npos) << r.out;
}

// compress repeats the reader's warnings that info lists, one line each, unless -q: a C3D's
// found reading its frames (4th words beyond 16 bits) and a TRC header's.
TEST(CliArchive, CompressPrintsTheReadersWarningsUnlessQuiet) {
  capz_test::TempDir d("capz_cli_warnings");
  const std::string c3d = std::string(CAPZ_REPO_DATA) + "/admarche2.c3d";
  Result r = run("compress '" + c3d + "' -o '" + d.file("a.capz") + "'");
  ASSERT_EQ(r.status, 0) << r.out;
  EXPECT_NE(r.out.find("capz compress: warning: " + c3d +
                       ": 2649 samples have a 4th word beyond 16 bits"),
            std::string::npos)
      << r.out;
  const std::string trc = d.file("t.trc");
  std::ofstream(trc, std::ios::binary)
      << "PathFileType\t4\t(X/Y/Z)\tt.trc\nDataRate\tNumFrames\tNumMarkers\tUnits\n100\t1\t2\tmm\n"
         "Frame#\tTime\tA\t\t\nX1\tY1\tZ1\n1\t0\t1\t2\t3\n";
  r = run("compress '" + trc + "' -o '" + d.file("t.capz") + "'");
  ASSERT_EQ(r.status, 0) << r.out;
  EXPECT_NE(r.out.find("capz compress: warning: " + trc + ": header says 2 markers, file holds 1"),
            std::string::npos)
      << r.out;
  r = run("compress -q -f '" + trc + "' -o '" + d.file("t.capz") + "'");
  ASSERT_EQ(r.status, 0) << r.out;
  EXPECT_EQ(r.out, "");
}
