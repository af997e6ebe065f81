// The version API (capz/version.h) against what the library really writes and reads, and what a
// decoder of format 1.0 says of a stream it cannot read (docs/FORMAT.md 2).
#include <gtest/gtest.h>

#include <cstddef>
#include <string>
#include <vector>

#include "capz/codec.h"
#include "capz/error.h"
#include "capz/version.h"
#include "coding/container.h"
#include "coding/crc32c.h"
#include "support/stream_pieces.h"

using namespace capz;

namespace {

Take small_take() {
  Take t;
  t.resize(3, 2);
  t.units = "mm";
  t.rate = 100;
  for (size_t i = 0; i < t.xyz.size(); ++i) t.xyz[i] = static_cast<double>(i);
  for (auto& v : t.valid) v = 1;
  return t;
}

std::vector<uint8_t> small_stream() {
  CompressOptions o;
  o.max_error = 0.01;
  return compress(small_take(), o);
}

// The stream with version major.minor in its header (and the header's CRC made right).
std::vector<uint8_t> relabelled(std::vector<uint8_t> b, int major, int minor) {
  b[9] = static_cast<uint8_t>(major);
  b[10] = static_cast<uint8_t>(minor);
  const uint32_t c = crc32c(b.data(), 11);
  for (int i = 0; i < 4; ++i) b[11 + static_cast<size_t>(i)] = static_cast<uint8_t>(c >> (8 * i));
  return b;
}

// decompress()'s error code and message (kInternal and "" when it decodes).
std::pair<ErrorCode, std::string> refusal(const std::vector<uint8_t>& b, const char* name) {
  try {
    decompress(b.data(), b.size(), name);
  } catch (const Error& e) {
    return {e.code(), e.what()};
  }
  return {ErrorCode::kInternal, ""};
}

}  // namespace

TEST(Version, GivenTheLibraryThenItsVersionStringSpellsItsNumbers) {
  const Version v = library_version();
  EXPECT_EQ(v.major, kVersion.major);
  EXPECT_EQ(v.minor, kVersion.minor);
  EXPECT_EQ(v.patch, kVersion.patch);
  EXPECT_EQ(std::string(version_string()), std::to_string(v.major) + "." + std::to_string(v.minor) +
                                               "." + std::to_string(v.patch));
  EXPECT_GE(v.major, 1);  // 0.x wrote the pre-release formats
}

TEST(Version, GivenACompressedTakeThenItStartsWithTheMagicAndTheOneVersionWritten) {
  const std::vector<uint8_t> bytes = small_stream();
  ASSERT_GE(bytes.size(), kFileHeaderBytes);
  const uint8_t magic[9] = {0x89, 'C', 'A', 'P', 'Z', 0x0D, 0x0A, 0x1A, 0x0A};
  EXPECT_TRUE(std::equal(magic, magic + 9, bytes.begin()));
  EXPECT_EQ(bytes[9], 1);
  EXPECT_EQ(bytes[10], 0);
  EXPECT_EQ(kFormatWritten.major, 1);
  EXPECT_EQ(kFormatWritten.minor, 0);
  EXPECT_EQ(bytes[9], kFormatNewestRead.major);
  EXPECT_LE(bytes[10], kFormatNewestRead.minor);
  const StreamInfo si = describe(bytes.data(), bytes.size(), "v.capz");
  EXPECT_EQ(si.major, 1);
  EXPECT_EQ(si.minor, 0);
}

TEST(Version, GivenAMajorVersionBeyondTheNewestReadThenTheStreamIsRefused) {
  std::vector<uint8_t> future = relabelled(small_stream(), kFormatNewestRead.major + 1, 0);
  EXPECT_EQ(refusal(future, "future.capz").first, ErrorCode::kUnsupportedVersion);
  // Its version bytes damaged: caught by the header's own CRC.
  future[9] ^= 0x01;
  EXPECT_EQ(refusal(future, "flipped.capz").first, ErrorCode::kCorrupt);
  EXPECT_EQ(refusal(relabelled(small_stream(), 0, 0), "zero.capz").first, ErrorCode::kCorrupt);
}

TEST(Version, GivenALaterMinorVersionThatUsesNothingNewThenItIsRead) {
  const std::vector<uint8_t> later = relabelled(small_stream(), 1, kFormatNewestRead.minor + 1);
  EXPECT_EQ(decompress(later.data(), later.size(), "later-minor.capz").frames, 3u);
}

// FORMAT.md 2: a chunk type of a later minor version whose first letter is upper case is
// critical (refused, naming it and the stream's version), lower case ancillary (skipped).
TEST(Version, GivenAnUnknownChunkThenACriticalOneIsRefusedAndAnAncillaryOneSkipped) {
  const std::vector<uint8_t> later = relabelled(small_stream(), 1, 2);
  for (const bool in_window : {false, true}) {
    for (const char* type : {"SCAN", "scan"}) {
      SCOPED_TRACE(std::string(type) + (in_window ? " in a window" : " after META"));
      std::vector<capz_test::Piece> ps = capz_test::pieces(later);
      size_t at = 2;  // after HEAD and META
      if (in_window)
        while (ps[at - 1].type != "POSW") ++at;
      ps.insert(ps.begin() + static_cast<std::ptrdiff_t>(at), {type, {1, 2, 3}});
      const std::vector<uint8_t> b = capz_test::assemble(later, ps);
      const auto r = refusal(b, "x.capz");
      if (type[0] == 's') {
        EXPECT_EQ(r.second, "");
      } else {
        EXPECT_EQ(r.first, ErrorCode::kUnsupportedVersion) << r.second;
        EXPECT_NE(
            r.second.find("chunk SCAN of format 1.2 is not known to this decoder (reads 1.1)"),
            std::string::npos)
            << r.second;
      }
    }
  }
}

// FORMAT.md 17: a HEAD flag bit that this decoder's formats (1.0, and 1.1's bits 3 to 6) leave
// 0 names a feature of a later minor.
TEST(Version, GivenAnUnknownHeadFlagThenTheFeatureIsNamed) {
  const std::vector<uint8_t> later = relabelled(small_stream(), 1, 2);
  std::vector<capz_test::Piece> ps = capz_test::pieces(later);
  ASSERT_EQ(ps[0].type, "HEAD");
  ps[0].payload[19] |= 128;  // flags: after frames u64, points u32, window u32, 3 bytes
  const auto r = refusal(capz_test::assemble(later, ps), "flag.capz");
  EXPECT_EQ(r.first, ErrorCode::kUnsupportedVersion) << r.second;
  EXPECT_NE(r.second.find("feature bit 7 of format 1.2"), std::string::npos) << r.second;
}

// A stream of capz 0.1.0 or earlier (magic "\x89capz", formats 1.0-9.3) is refused with how to
// upgrade it (tests/golden/test_golden.cpp reads a real one).
TEST(Version, GivenThePrereleaseMagicThenTheStreamIsRefusedWithTheUpgradeMessage) {
  std::vector<uint8_t> old = small_stream();
  const char lower[4] = {'c', 'a', 'p', 'z'};
  std::copy(lower, lower + 4, old.begin() + 1);
  old[9] = 9;
  old[10] = 3;
  EXPECT_TRUE(is_capz(old.data(), old.size()));
  const auto r = refusal(old, "old.capz");
  EXPECT_EQ(r.first, ErrorCode::kUnsupportedVersion);
  EXPECT_NE(r.second.find("old.capz: a pre-release capz stream (format 9.3); this capz reads "
                          "format 1.x: decompress it with capz 0.1.0 (git tag v0.1.0)"),
            std::string::npos)
      << r.second;
}
