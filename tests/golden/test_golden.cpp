// Golden streams (tests/golden/streams, made by make_newest.py from data/ samples; names say
// input, method and format version) must keep decoding to the recorded content, exactly (CRC-32C
// of the decoded take, MANIFEST.txt), and to the source file within the stored bound (or, for
// transform output, within its KG target). Compressing each source again with the recorded
// options must give a stream that decodes within the same promise (lossless: to the same
// content), and, where the manifest says `bytes`, the same bytes in every chunk of integer paths
// (HEAD, POSW, MASK, C3DW, ROTW, and SCNW of format 1.1's ragged takes; Eigen, floating-point
// fits and the system's LZMA decide the others' bytes). A pre-release stream
// (tests/golden/prerelease, written by capz 0.1.0) is refused with how to upgrade it.
#include <gtest/gtest.h>
#include <sys/wait.h>

#include <algorithm>
#include <cmath>
#include <cstdio>
#include <cstdlib>
#include <cstring>
#include <filesystem>
#include <fstream>
#include <sstream>

#include "capz/codec.h"
#include "capz/error.h"
#include "capz/io.h"
#include "capz/metrics.h"
#include "capz/tool/file.h"
#include "capz/tool/original.h"
#include "capz/tool/verify.h"
#include "capz/version.h"
#include "coding/bytes.h"
#include "coding/crc32c.h"
#include "core/atomic_file.h"
#include "test_util.h"

namespace capz {
namespace {

const std::string kStreams = std::string(CAPZ_TEST_DIR) + "/golden/streams/";

// CRC-32C of the decoded positions, mask, analog values and point fields in a fixed byte layout
// (a ragged take's frame offsets after its shape; a fixed take has none, so its CRC is as before
// format 1.1).
uint32_t content_crc(const Take& t) {
  ByteWriter w;
  w.u64(t.frames);
  w.u64(t.points);
  for (size_t o : t.frame_offsets) w.u64(o);
  for (double x : t.xyz) w.f64(x);
  w.bytes(t.valid);
  for (double x : t.analog.values) w.f64(x);
  for (const capz::PointAttribute& a : t.attributes) w.bytes(a.data);
  return crc32c(w.buffer().data(), w.size());
}

struct Entry {
  std::string stream, source;
  uint32_t crc = 0;
  std::string check;    // "bytes" or "content" (MANIFEST.txt's header)
  std::string options;  // of `capz compress SOURCE -o STREAM OPTIONS` (empty: decode-only)
};

std::vector<Entry> manifest() {
  std::ifstream in(kStreams + "MANIFEST.txt");
  std::vector<Entry> v;
  std::string line;
  while (std::getline(in, line)) {
    if (line.empty() || line[0] == '#') continue;
    std::istringstream ls(line);
    Entry e;
    std::string crc;
    ls >> e.stream >> e.source >> crc >> e.check;
    e.crc = static_cast<uint32_t>(std::stoul(crc, nullptr, 16));
    std::getline(ls >> std::ws, e.options);
    v.push_back(e);
  }
  return v;
}

// The source of an entry, read as its options say (a .bin record: --bin-fields R).
Take read_source(const Entry& e) {
  ReadOptions ro;
  const size_t at = e.options.find("--bin-fields ");
  if (at != std::string::npos) {
    std::istringstream rest(e.options.substr(at + 13));
    rest >> ro.bin_fields;
  }
  return read_take(std::string(CAPZ_REPO_DATA) + "/" + e.source, ro);
}

// The format version a stream's name ends with: "x.v1.0.capz" -> {1, 0} ({0, 0} without one).
FormatVersion version_of(const std::string& stream) {
  FormatVersion v;
  const size_t at = stream.rfind(".v");
  if (at == std::string::npos ||
      std::sscanf(stream.c_str() + at, ".v%d.%d.capz", &v.major, &v.minor) != 2)
    return FormatVersion();
  return v;
}

TEST(Golden, GivenManifestThenItListsStreamsOfReleasedVersionsWithTheirChecks) {
  const std::vector<Entry> all = manifest();
  EXPECT_GE(all.size(), 20u);
  size_t bytes = 0, written = 0;
  for (const Entry& e : all) {
    SCOPED_TRACE(e.stream);
    const FormatVersion v = version_of(e.stream);
    EXPECT_EQ(v.major, kFormatNewestRead.major);
    EXPECT_LE(v.minor, kFormatNewestRead.minor);
    EXPECT_TRUE(e.check == "bytes" || e.check == "content") << e.check;
    bytes += e.check == "bytes" && !e.options.empty();
    written += v.major == kFormatWritten.major && v.minor == kFormatWritten.minor;
  }
  EXPECT_GE(written, 20u) << "the version written has golden streams of its own";
  EXPECT_GE(bytes, 10u) << "most streams' integer paths are checked byte for byte";
}

// b, decoded from a stream described by si, against its source a: every promise the stream
// makes (bound or KG target, exact mask, labels, analog values, point fields and C3D words).
void expect_within_promise(const Take& a, const Take& b, const StreamInfo& si) {
  ASSERT_EQ(a.frames, b.frames);
  // A ragged source's frames keep their counts; a fixed one reordered decodes as ragged frames of
  // its count (same_frame_counts).
  ASSERT_TRUE(si.points_reordered ? same_frame_counts(a, b) : a.frame_offsets == b.frame_offsets);
  if (si.points_reordered) {  // FORMAT.md "Points reordered": each frame's points as a set
    Take source = a;  // --drop-fields: the stream holds no fields to compare (as verify says)
    if (b.attributes.empty()) source.attributes.clear();
    const PromiseResult r = check_promise(source, b, promise_of(si));
    EXPECT_TRUE(r.holds) << r.why;
    return;
  }
  ErrorStats s = compare(a, b);
  EXPECT_EQ(s.mask_mismatches, 0u);
  if (si.lossless) {
    EXPECT_EQ(s.max_abs, 0.0);
  } else if (si.transform_output) {
    EXPECT_GT(si.kg_target, 0.0);
    EXPECT_LE(s.kg_error, si.kg_target);
  } else {
    EXPECT_LE(s.max_abs, si.max_error);
  }
  ASSERT_EQ(a.analog.values.size(), b.analog.values.size());
  if (si.analog_bounds.empty()) {
    EXPECT_EQ(
        std::memcmp(a.analog.values.data(), b.analog.values.data(), a.analog.values.size() * 8), 0);
  } else {  // lossy analog channels (FORMAT.md 5.2): within their bounds, the rest exact
    const size_t C = si.analog_bounds.size();
    size_t moved = 0;
    for (size_t k = 0; k < a.analog.values.size(); ++k) {
      const double err = std::fabs(a.analog.values[k] - b.analog.values[k]);
      EXPECT_LE(err * si.analog_factors[k % C], si.analog_bounds[k % C]) << k;
      moved += err > 0;
    }
    EXPECT_GT(moved, 0u);
  }
  EXPECT_EQ(a.labels, b.labels);
  // PCD point fields come back byte for byte at every target.
  if (!b.attributes.empty()) {
    ASSERT_EQ(a.attributes.size(), b.attributes.size());
    for (size_t k = 0; k < a.attributes.size(); ++k)
      EXPECT_EQ(a.attributes[k].data, b.attributes[k].data) << a.attributes[k].name;
  }
  // C3D 4th words (residual and camera bytes) are always kept exactly.
  ASSERT_EQ(a.c3d != nullptr, b.c3d != nullptr);
  if (a.c3d) {
    ASSERT_EQ(a.c3d->residual.size(), b.c3d->residual.size());
    EXPECT_EQ(
        std::memcmp(a.c3d->residual.data(), b.c3d->residual.data(), a.c3d->residual.size() * 4), 0);
    EXPECT_EQ(a.c3d->camera_mask, b.c3d->camera_mask);
  }
}

TEST(Golden, GivenGoldenStreamsWhenDecodedThenKnownContentAndWithinBoundOfSource) {
  for (const Entry& e : manifest()) {
    SCOPED_TRACE(e.stream);
    std::vector<uint8_t> bytes = read_file(kStreams + e.stream);
    Take b = decompress(bytes.data(), bytes.size(), e.stream);
    char hex[16];
    std::snprintf(hex, sizeof hex, "%08x", content_crc(b));
    EXPECT_EQ(content_crc(b), e.crc) << "decoded content changed: now " << hex;
    const StreamInfo si = describe(bytes.data(), bytes.size(), e.stream);
    expect_within_promise(read_source(e), b, si);
  }
}

// The chunks of integer paths of stream b (after its 15-byte file header), in order, each as its
// type and payload. SCNW (format 1.1) is one: its coder is integer, and the laser table it infers
// comes from binary64 arithmetic compiled without contraction (CMakeLists.txt) and the C
// library's atan2, hypot, sin and cos: the same bytes on every build against one C library (a
// libm rounding those differently could move a table entry and fail this check; the decoder's
// sin and cos are capz's own, FORMAT.md "Scans", so decoding is exact everywhere).
std::vector<std::string> integer_chunks(const std::vector<uint8_t>& b) {
  std::vector<std::string> out;
  for (size_t off = 15; off + 12 <= b.size();) {
    const size_t n = static_cast<size_t>(b[off + 4]) | static_cast<size_t>(b[off + 5]) << 8 |
                     static_cast<size_t>(b[off + 6]) << 16 | static_cast<size_t>(b[off + 7]) << 24;
    if (n > b.size() - off - 12) break;
    const std::string type(b.begin() + static_cast<long>(off),
                           b.begin() + static_cast<long>(off) + 4);
    if (type == "HEAD" || type == "POSW" || type == "MASK" || type == "C3DW" || type == "ROTW" ||
        type == "SCNW")
      out.push_back(type + std::string(b.begin() + static_cast<long>(off) + 8,
                                       b.begin() + static_cast<long>(off + 8 + n)));
    off += 12 + n;
  }
  return out;
}

// Each source compressed again through the CLI with the recorded options: a stream that keeps
// the same promise (lossless: the same content), and where the manifest says `bytes` the same
// chunks of integer paths. A change meant to alter those remakes the streams (make_newest.py,
// while the version is being written) and says so.
TEST(Golden, GivenGoldenSourcesWhenRecompressedWithTheirOptionsThenAsTheManifestSays) {
  capz_test::TempDir dir("capz_golden_encode");
  size_t checked = 0;
  for (const Entry& e : manifest()) {
    if (e.options.empty()) continue;
    SCOPED_TRACE(e.stream + " from " + e.source + " with " + e.options);
    const std::string out = dir.file(e.stream);
    const std::string cmd = std::string("'") + CAPZ_CLI + "' compress -q '" + CAPZ_REPO_DATA + "/" +
                            e.source + "' -o '" + out + "' " + e.options;
    const int rc = std::system(cmd.c_str());
    ASSERT_TRUE(WIFEXITED(rc) && WEXITSTATUS(rc) == 0) << cmd;
    const std::vector<uint8_t> now = read_file(out), stored = read_file(kStreams + e.stream);
    ++checked;
    if (e.check == "bytes") {
      const std::vector<std::string> a = integer_chunks(now), g = integer_chunks(stored);
      EXPECT_EQ(a.size(), g.size());
      for (size_t k = 0; k < std::min(a.size(), g.size()); ++k)
        EXPECT_TRUE(a[k] == g[k]) << "chunk " << k << " of the integer paths (" << g[k].substr(0, 4)
                                  << ") differs";
    }
    const Take b = decompress(now.data(), now.size(), out);
    const StreamInfo si = describe(now.data(), now.size(), out),
                     old = describe(stored.data(), stored.size());
    EXPECT_EQ(si.lossless, old.lossless);
    EXPECT_EQ(si.transform_output, old.transform_output);
    if (si.lossless) {
      EXPECT_EQ(content_crc(b), e.crc);
    }
    expect_within_promise(read_source(e), b, si);
  }
  EXPECT_GE(checked, 20u);
}

// The format 1.1 streams (ragged frames, FORMAT.md "Scans") are in the manifest and are what
// they say: minor version 1, HEAD feature bit 3, one SCNW chunk per window and no POSW or MASK,
// frames of their own point counts as in their source, at both bounds and in more than one window;
// a source of frames of one count (lidar_small: frames of one organized shape, FORMAT.md "Ragged
// frames: HEAD and the window chunk") decodes to the fixed take of its shape, or reordered
// (--point-order any, layout 0 x 1) to ragged frames of that count.
TEST(Golden, GivenTheScanGoldenStreamsThenFormat11RaggedFramesWithOneScnwPerWindow) {
  size_t scans = 0, multi_window = 0, organized = 0;
  for (const Entry& e : manifest()) {
    const FormatVersion v = version_of(e.stream);
    if (v.major != kFormatScans.major || v.minor != kFormatScans.minor) continue;
    SCOPED_TRACE(e.stream);
    ++scans;
    const std::vector<uint8_t> b = read_file(kStreams + e.stream);
    ASSERT_GT(b.size(), 15u + 12 + 20);
    EXPECT_EQ(b[9], kFormatScans.major);
    EXPECT_EQ(b[10], kFormatScans.minor);
    EXPECT_EQ(std::string(b.begin() + 15, b.begin() + 19), "HEAD");
    EXPECT_EQ(b[15 + 8 + 19] & 0x08, 0x08) << "HEAD flags: feature bit 3, ragged frames";
    size_t scnw = 0, other = 0;
    for (const std::string& c : integer_chunks(b)) {
      scnw += c.compare(0, 4, "SCNW") == 0;
      other += c.compare(0, 4, "POSW") == 0 || c.compare(0, 4, "MASK") == 0;
    }
    const StreamInfo si = describe(b.data(), b.size(), e.stream);
    const Take src = read_source(e);
    // A fixed source reordered (--point-order any) is coded as frames of their own counts that
    // happen to be equal, and decodes so.
    const bool reordered_fixed = si.points_reordered && !src.ragged();
    EXPECT_EQ(si.ragged, src.ragged() || reordered_fixed);
    EXPECT_EQ(scnw, si.windows);
    EXPECT_EQ(other, 0u);
    multi_window += si.windows > 1;
    const Take t = decompress(b.data(), b.size(), e.stream);
    EXPECT_TRUE(same_frame_counts(t, src));
    EXPECT_EQ(t.ragged(), src.ragged() || reordered_fixed);
    if (!src.ragged() && !reordered_fixed) {
      ++organized;
      ASSERT_TRUE(src.pcd && t.pcd);
      EXPECT_EQ(si.pcd_width, src.pcd->width);
      EXPECT_EQ(si.pcd_height, src.pcd->height);
      EXPECT_EQ(t.pcd->width, src.pcd->width);
      EXPECT_EQ(t.pcd->height, src.pcd->height);
    }
  }
  EXPECT_GE(scans, 2u);
  EXPECT_GE(multi_window, 1u);
  EXPECT_GE(organized, 1u);
}

// The lossless golden streams of format 1.1's frame files (scan_small as PCD, PLY, KITTI .bin,
// nuScenes .pcd.bin and a declared record's .bin frames: FORMAT.md "Lossless ragged streams",
// "Lossless frame-file streams") rebuild every frame file of their source byte for byte.
TEST(Golden, GivenTheLosslessScanGoldenStreamsThenTheirFrameFilesRebuildByteForByte) {
  capz_test::TempDir tmp("capz_golden_rebuild");
  size_t rebuilt = 0;
  for (const Entry& e : manifest()) {
    const FormatVersion v = version_of(e.stream);
    if (v.major != kFormatScans.major || v.minor != kFormatScans.minor ||
        e.options.find("--lossless") == std::string::npos)
      continue;
    SCOPED_TRACE(e.stream);
    const std::string src = std::string(CAPZ_REPO_DATA) + "/" + e.source, out = tmp.file("back");
    std::filesystem::remove_all(out);
    rebuild_original(kStreams + e.stream, out, true);
    size_t files = 0;
    for (const auto& f : std::filesystem::directory_iterator(src)) {
      const std::string name = f.path().filename().string();
      EXPECT_EQ(read_file(out + "/" + name), read_file(src + "/" + name)) << name;
      ++files;
    }
    size_t back = 0;
    for (const auto& f : std::filesystem::directory_iterator(out)) back += f.is_regular_file();
    EXPECT_EQ(back, files);
    ++rebuilt;
  }
  EXPECT_GE(rebuilt, 5u);  // scan_small, scan_small_ply, scan_small_bin, scan_small_nus, _rec
}

// A stream of capz 0.1.0 (format 9.3, magic "\x89capz") is refused, by the library and the CLI,
// as unsupported-version with how to upgrade it (CHANGELOG.md).
TEST(Golden, GivenAPrereleaseStreamThenRefusedWithTheUpgradeMessage) {
  const std::string path =
      std::string(CAPZ_TEST_DIR) + "/golden/prerelease/held_analog.c3d.grid0.1mm.v9.3.capz";
  const std::vector<uint8_t> old = read_file(path);
  ASSERT_GT(old.size(), 15u);
  ASSERT_EQ(old[1], 'c');
  ASSERT_EQ(old[9], 9);
  ASSERT_EQ(old[10], 3);
  EXPECT_TRUE(is_capz(old.data(), old.size()));
  const std::string want =
      "old.capz: a pre-release capz stream (format 9.3); this capz reads format 1.x: decompress "
      "it with capz 0.1.0 (git tag v0.1.0) and compress it again (see CHANGELOG.md)";
  for (int how = 0; how < 2; ++how) {
    try {
      if (how == 0) decompress(old.data(), old.size(), "old.capz");
      if (how == 1) describe(old.data(), old.size(), "old.capz");
      ADD_FAILURE() << "a pre-release stream was read";
    } catch (const Error& e) {
      EXPECT_EQ(e.code(), ErrorCode::kUnsupportedVersion);
      EXPECT_EQ(std::string(e.what()), want);
    }
  }
  capz_test::TempDir dir("capz_golden_prerelease");
  const auto r = capz_test::run_command(
      CAPZ_CLI, "decompress -q '" + path + "' -o '" + dir.file("x.c3d") + "'", dir.file("o.txt"));
  EXPECT_EQ(r.status, static_cast<int>(ErrorCode::kUnsupportedVersion)) << r.out;
  EXPECT_NE(r.out.find("a pre-release capz stream (format 9.3)"), std::string::npos) << r.out;
  EXPECT_NE(r.out.find("git tag v0.1.0"), std::string::npos) << r.out;
}

}  // namespace
}  // namespace capz
