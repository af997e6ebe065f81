// Golden streams (tests/golden/streams, made by capz 1.0, 2.0, 3.0 and 3.1 from data/ samples;
// names say input, method and format version) must keep decoding: to the same bytes as when they
// were made (CRC-32C of the decoded take, MANIFEST.txt) and to the source file within the stored
// bound.
#include <gtest/gtest.h>

#include <cstring>
#include <fstream>
#include <sstream>

#include "capz/codec.h"
#include "capz/io.h"
#include "capz/metrics.h"
#include "coding/bytes.h"
#include "coding/crc32c.h"
#include "core/atomic_file.h"

namespace capz {
namespace {

const std::string kStreams = std::string(CAPZ_TEST_DIR) + "/golden/streams/";

// CRC-32C of the decoded positions, mask and analog values in a fixed byte layout.
uint32_t content_crc(const Take& t) {
  ByteWriter w;
  w.u64(t.frames);
  w.u64(t.points);
  for (double x : t.xyz) w.f64(x);
  w.bytes(t.valid);
  for (double x : t.analog.values) w.f64(x);
  return crc32c(w.buffer().data(), w.size());
}

struct Entry {
  std::string stream, source;
  uint32_t crc = 0;
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
    if (si.lossless)
      EXPECT_EQ(s.max_abs, 0.0);
    else
      EXPECT_LE(s.max_abs, si.max_error);
    ASSERT_EQ(a.analog.values.size(), b.analog.values.size());
    EXPECT_EQ(
        std::memcmp(a.analog.values.data(), b.analog.values.data(), a.analog.values.size() * 8), 0);
    EXPECT_EQ(a.labels, b.labels);
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
  for (const Entry& e : manifest()) {
    if (e.stream.find("lossless") == std::string::npos) continue;
    std::vector<uint8_t> bytes = read_file(kStreams + e.stream);
    Take a = read_take(std::string(CAPZ_REPO_DATA) + "/" + e.source);
    CompressOptions o;
    o.lossless = true;
    std::vector<uint8_t> now = compress(a, o);
    Take b = decompress(now.data(), now.size());
    EXPECT_EQ(content_crc(b), e.crc) << e.stream;
  }
}

}  // namespace
}  // namespace capz
