// Golden streams (tests/golden/streams, made by capz 1.0, 2.0, 3.0 and 3.1 from data/ samples;
// names say input, method and format version) must keep decoding: to the same bytes as when they
// were made (CRC-32C of the decoded take, MANIFEST.txt) and to the source file within the stored
// bound (or, for transform output, within its KG target). The streams of the newest version must
// also still be what the encoder writes: `capz compress` with the options MANIFEST.txt records
// gives the same bytes.
#include <gtest/gtest.h>
#include <sys/wait.h>

#include <algorithm>
#include <cmath>
#include <cstdio>
#include <cstdlib>
#include <cstring>
#include <fstream>
#include <map>
#include <sstream>

#include "capz/codec.h"
#include "capz/io.h"
#include "capz/metrics.h"
#include "capz/version.h"
#include "coding/bytes.h"
#include "coding/crc32c.h"
#include "core/atomic_file.h"
#include "test_util.h"

namespace capz {
namespace {

const std::string kStreams = std::string(CAPZ_TEST_DIR) + "/golden/streams/";

// CRC-32C of the decoded positions, mask, analog values and point fields in a fixed byte layout.
uint32_t content_crc(const Take& t) {
  ByteWriter w;
  w.u64(t.frames);
  w.u64(t.points);
  for (double x : t.xyz) w.f64(x);
  w.bytes(t.valid);
  for (double x : t.analog.values) w.f64(x);
  for (const capz::PointAttribute& a : t.attributes) w.bytes(a.data);  // none before 5.0
  return crc32c(w.buffer().data(), w.size());
}

struct Entry {
  std::string stream, source;
  uint32_t crc = 0;
  std::string options;  // of `capz compress SOURCE -o STREAM OPTIONS` (newest version only)
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
    ls >> e.stream >> e.source >> crc;
    e.crc = static_cast<uint32_t>(std::stoul(crc, nullptr, 16));
    std::getline(ls >> std::ws, e.options);
    v.push_back(e);
  }
  return v;
}

TEST(Golden, GivenManifestThenItListsStreams) {
  EXPECT_GE(manifest().size(), 3u);
}

TEST(Golden, GivenGoldenStreamsWhenDecodedThenKnownContentAndWithinBoundOfSource) {
  for (const Entry& e : manifest()) {
    SCOPED_TRACE(e.stream);
    std::vector<uint8_t> bytes = read_file(kStreams + e.stream);
    Take b = decompress(bytes.data(), bytes.size(), e.stream);
    char hex[16];
    std::snprintf(hex, sizeof hex, "%08x", content_crc(b));
    EXPECT_EQ(content_crc(b), e.crc) << "decoded content changed: now " << hex;
    StreamInfo si = describe(bytes.data(), bytes.size(), e.stream);
    Take a = read_take(std::string(CAPZ_REPO_DATA) + "/" + e.source);
    ASSERT_EQ(a.frames, b.frames);
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
          std::memcmp(a.analog.values.data(), b.analog.values.data(), a.analog.values.size() * 8),
          0);
    } else {  // lossy analog channels (FORMAT.md 5.7): within their bounds, the rest exact
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
    // PCD point fields (5.0 on) come back byte for byte at every target.
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
          std::memcmp(a.c3d->residual.data(), b.c3d->residual.data(), a.c3d->residual.size() * 4),
          0);
      EXPECT_EQ(a.c3d->camera_mask, b.c3d->camera_mask);
    }
  }
}

// The same source compressed today gives a stream that decodes identically (the encoder may
// change its choices; the decoded content for a lossless stream may not).
TEST(Golden, GivenLosslessSourceWhenRecompressedThenSameDecodedContent) {
  size_t checked = 0;
  for (const Entry& e : manifest()) {
    if (e.stream.find("lossless") == std::string::npos) continue;
    ++checked;
    std::vector<uint8_t> bytes = read_file(kStreams + e.stream);
    Take a = read_take(std::string(CAPZ_REPO_DATA) + "/" + e.source);
    CompressOptions o;
    o.lossless = true;
    std::vector<uint8_t> now = compress(a, o);
    Take b = decompress(now.data(), now.size());
    EXPECT_EQ(content_crc(b), e.crc) << e.stream;
  }
  EXPECT_GE(checked, 4u);
}

// The format version a stream's name ends with: "x.v3.1.capz" -> 301.
int version_of(const std::string& stream) {
  const size_t v = stream.rfind(".v");
  if (v == std::string::npos) return -1;
  int major = 0, minor = 0;
  if (std::sscanf(stream.c_str() + v, ".v%d.%d.capz", &major, &minor) != 2) return -1;
  return major * 100 + minor;
}

// The encoder still writes the golden streams of the versions it writes byte for byte (5.0; 6.0
// for takes with a normal triple or an organized layout, FORMAT.md 13; 7.0 for scans along
// sensor rays or unorganized clouds' fields, FORMAT.md 7; 8.0 for C3D parameters after the
// dictionary, FORMAT.md 5.8; 9.0 for analog channels, FORMAT.md 11),
// through the CLI with the options
// MANIFEST.txt records: for each source and options, the stream of the highest version (older
// ones of the same source and options were written by older encoders, and are only decoded).
// This guards refactors of the encoder: a change that is meant to change the bytes remakes
// these streams and says so.
TEST(Golden, GivenNewestGoldensWhenRecompressedWithTheirOptionsThenSameBytes) {
  const std::vector<Entry> all = manifest();
  int newest = 0;
  for (const Entry& e : all) newest = std::max(newest, version_of(e.stream));
  auto number = [](capz::FormatVersion v) { return v.major * 100 + v.minor; };
  const int written = number(capz::kFormatWritten),
            newest_written = number(capz::kFormatNewestWritten);
  const std::vector<int> writes = {written, number(capz::kFormat6), number(capz::kFormat7),
                                   number(capz::kFormat8), number(capz::kFormat9)};
  // A new format version brings golden streams of its own (CONTRIBUTING.md).
  ASSERT_EQ(newest, newest_written) << "no golden stream of the newest version the encoder writes";
  for (int v : writes)
    ASSERT_TRUE(std::any_of(
        all.begin(), all.end(),
        [&](const Entry& e) { return version_of(e.stream) == v && !e.options.empty(); }))
        << "no golden stream of version " << v / 100 << "." << v % 100
        << ", which the encoder writes";
  std::map<std::string, int> highest;  // source and options -> highest version
  for (const Entry& e : all) {
    if (e.options.empty()) continue;
    int& h = highest[e.source + " " + e.options];
    h = std::max(h, version_of(e.stream));
  }
  capz_test::TempDir dir("capz_golden_encode");
  size_t checked = 0;
  for (const Entry& e : all) {
    ASSERT_GT(version_of(e.stream), 0) << e.stream << ": no version in the name";
    if (e.options.empty() || version_of(e.stream) != highest[e.source + " " + e.options]) continue;
    SCOPED_TRACE(e.stream + " from " + e.source + " with " + e.options);
    ASSERT_TRUE(std::find(writes.begin(), writes.end(), version_of(e.stream)) != writes.end())
        << "the newest stream of its source and options is of a version the encoder no longer "
           "writes: remake it (make_newest.py) or record it without options";
    const std::string out = dir.file(e.stream);
    const std::string cmd = std::string("'") + CAPZ_CLI + "' compress -q '" + CAPZ_REPO_DATA + "/" +
                            e.source + "' -o '" + out + "' " + e.options;
    const int rc = std::system(cmd.c_str());
    ASSERT_TRUE(WIFEXITED(rc) && WEXITSTATUS(rc) == 0) << cmd;
    const std::vector<uint8_t> now = read_file(out), stored = read_file(kStreams + e.stream);
    const size_t common = std::min(now.size(), stored.size());
    const size_t first =
        std::mismatch(now.begin(), now.begin() + static_cast<long>(common), stored.begin()).first -
        now.begin();
    EXPECT_TRUE(now == stored) << "the encoder now writes " << now.size() << " bytes, the golden "
                               << stored.size() << "; first difference at byte " << first;
    ++checked;
  }
  EXPECT_GE(checked, 9u);
}

}  // namespace
}  // namespace capz
