// A golden stream given another version (unit tests): to check that a decoder of an earlier
// version refuses, as corrupt and naming the chunk, what only a later version may write.
#pragma once

#include <gtest/gtest.h>

#include <cstdint>
#include <string>
#include <vector>

#include "capz/codec.h"
#include "capz/error.h"
#include "coding/crc32c.h"
#include "test_util.h"

namespace capz_test {

// tests/golden/streams/NAME's bytes (empty, with a failure, when it cannot be read).
inline std::vector<uint8_t> golden_bytes(const std::string& name) {
  const std::string text = file_text(std::string(CAPZ_TEST_DIR) + "/golden/streams/" + name);
  EXPECT_GT(text.size(), 15u) << name;
  return std::vector<uint8_t>(text.begin(), text.end());
}

// b with version major.minor and the header CRC made right for it (FORMAT.md 3).
inline std::vector<uint8_t> relabelled(std::vector<uint8_t> b, uint8_t major, uint8_t minor) {
  if (b.size() < 15) return b;
  b[9] = major;
  b[10] = minor;
  const uint32_t crc = capz::crc32c(b.data(), 11);
  for (int k = 0; k < 4; ++k) b[11 + k] = static_cast<uint8_t>(crc >> (8 * k));
  return b;
}

// Decoding b throws kCorrupt, its message naming each of `parts`.
inline void expect_corrupt_naming(const std::vector<uint8_t>& b,
                                  const std::vector<std::string>& parts) {
  std::string msg;
  EXPECT_EQ(error_of([&] { capz::decompress(b.data(), b.size()); }, &msg),
            capz::ErrorCode::kCorrupt);
  for (const std::string& p : parts) EXPECT_NE(msg.find(p), std::string::npos) << msg;
}

}  // namespace capz_test
