// The version API (capz/version.h) against what the library really writes and reads.
#include <gtest/gtest.h>

#include <algorithm>
#include <cstddef>
#include <string>
#include <vector>

#include "capz/codec.h"
#include "capz/error.h"
#include "capz/version.h"
#include "coding/container.h"
#include "coding/crc32c.h"

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

}  // namespace

TEST(Version, GivenTheLibraryThenItsVersionStringSpellsItsNumbers) {
  const Version v = library_version();
  EXPECT_EQ(v.major, kVersion.major);
  EXPECT_EQ(v.minor, kVersion.minor);
  EXPECT_EQ(v.patch, kVersion.patch);
  EXPECT_EQ(std::string(version_string()), std::to_string(v.major) + "." + std::to_string(v.minor) +
                                               "." + std::to_string(v.patch));
}

TEST(Version, GivenACompressedTakeThenItsVersionIsTheOneWrittenAndItIsRead) {
  CompressOptions o;
  o.max_error = 0.01;
  const std::vector<uint8_t> bytes = compress(small_take(), o);
  ASSERT_GE(bytes.size(), 11u);
  EXPECT_EQ(bytes[9], kFormatWritten.major);
  EXPECT_EQ(bytes[10], kFormatWritten.minor);
  const StreamInfo si = describe(bytes.data(), bytes.size(), "v.capz");
  EXPECT_EQ(si.major, kFormatWritten.major);
  EXPECT_EQ(si.minor, kFormatWritten.minor);
  // What is written is within what is read.
  EXPECT_TRUE(kFormatOldestRead.major < kFormatWritten.major ||
              (kFormatOldestRead.major == kFormatWritten.major &&
               kFormatOldestRead.minor <= kFormatWritten.minor));
  // The newest version written (streams with a normal triple, FORMAT.md 13.4) is the newest
  // read, and later than the one every other stream is written in.
  EXPECT_EQ(kFormatNewestRead.major, kFormatNewestWritten.major);
  EXPECT_GE(kFormatNewestRead.minor, kFormatNewestWritten.minor);
  EXPECT_GT(kFormatNewestWritten.major, kFormatWritten.major);
}

TEST(Version, GivenAMajorVersionBeyondTheNewestReadThenTheStreamIsRefused) {
  CompressOptions o;
  o.max_error = 0.01;
  std::vector<uint8_t> bytes = compress(small_take(), o);
  // A later major keeps the 4.x file header: magic, version, and the version's CRC-32C.
  std::vector<uint8_t> future(bytes.begin(), bytes.begin() + 9);
  future.push_back(static_cast<uint8_t>(std::max(4, kFormatNewestRead.major + 1)));
  future.push_back(0);
  const uint32_t crc = crc32c(future.data(), 11);
  for (int i = 0; i < 4; ++i) future.push_back(static_cast<uint8_t>(crc >> (8 * i)));
  future.insert(future.end(),
                bytes.begin() + static_cast<std::ptrdiff_t>(file_header_bytes(bytes[9])),
                bytes.end());
  try {
    decompress(future.data(), future.size(), "future.capz");
    FAIL() << "a stream of a later major version was read";
  } catch (const Error& e) {
    EXPECT_EQ(e.code(), ErrorCode::kUnsupportedVersion) << e.what();
  }
  // Its version bytes damaged: caught by the header's own CRC.
  future[9] ^= 0x01;
  try {
    decompress(future.data(), future.size(), "flipped.capz");
    FAIL() << "a damaged version byte was read";
  } catch (const Error& e) {
    EXPECT_EQ(e.code(), ErrorCode::kCorrupt) << e.what();
  }
  // A later minor version of the newest major is read (it only adds what a decoder skips).
  bytes[9] = static_cast<uint8_t>(kFormatNewestRead.major);
  bytes[10] = static_cast<uint8_t>(kFormatNewestRead.minor + 1);
  if (bytes[9] >= 4) {  // the header's CRC, for the new minor
    const uint32_t c = crc32c(bytes.data(), 11);
    for (int i = 0; i < 4; ++i)
      bytes[11 + static_cast<size_t>(i)] = static_cast<uint8_t>(c >> (8 * i));
  }
  EXPECT_EQ(decompress(bytes.data(), bytes.size(), "later-minor.capz").frames, 3u);
}
