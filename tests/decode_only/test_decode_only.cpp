// The decoder library alone (capz::decode, no encoders, no PCL): this executable links nothing
// else, so it fails to link if a decode-side file reaches for encoder code. It decodes every
// golden stream and checks the transform decoders are registered.
#include <dirent.h>
#include <gtest/gtest.h>

#include <fstream>
#include <iterator>
#include <string>
#include <vector>

#include "capz/codec.h"
#include "capz/error.h"
#include "codec/decoder_registry.h"

namespace {

std::vector<std::string> golden_streams() {
  std::vector<std::string> out;
  const std::string dir = std::string(CAPZ_TEST_DIR) + "/../golden/streams";
  if (DIR* d = opendir(dir.c_str())) {
    while (dirent* e = readdir(d)) {
      const std::string n = e->d_name;
      if (n.size() > 5 && n.substr(n.size() - 5) == ".capz") out.push_back(dir + "/" + n);
    }
    closedir(d);
  }
  return out;
}

std::vector<uint8_t> slurp(const std::string& path) {
  std::ifstream f(path, std::ios::binary);
  return std::vector<uint8_t>(std::istreambuf_iterator<char>(f), {});
}

TEST(DecodeOnly, GivenTheDecoderLibraryAloneWhenDecodingEveryGoldenStreamThenEachDecodes) {
  const std::vector<std::string> streams = golden_streams();
  ASSERT_GE(streams.size(), 10u) << "golden streams missing";
  for (const std::string& s : streams) {
    const std::vector<uint8_t> bytes = slurp(s);
    const capz::Take t = capz::decompress(bytes.data(), bytes.size(), s);
    EXPECT_GT(t.frames, 0u) << s;
    EXPECT_EQ(t.xyz.size(), t.total_points() * 3) << s;  // frames x points, or ragged (1.1)
    const capz::Take part = capz::decompress_frames(bytes.data(), bytes.size(), 1, 2, s);
    EXPECT_EQ(part.frames, std::min<size_t>(2, t.frames - 1)) << s;
    for (size_t f = 0; f < part.frames; ++f)
      EXPECT_EQ(part.frame_points(f), t.frame_points(1 + f)) << s;
  }
}

TEST(DecodeOnly, GivenTheDecoderLibraryThenTsAndPdctDecodersAreRegistered) {
  ASSERT_NE(capz::find_decoder(1), nullptr);
  ASSERT_NE(capz::find_decoder(2), nullptr);
  EXPECT_EQ(std::string(capz::find_decoder(1)->name()), "ts");
  EXPECT_EQ(std::string(capz::find_decoder(2)->name()), "pdct");
  EXPECT_EQ(capz::find_decoder(0), nullptr);
}

TEST(DecodeOnly, GivenDamagedBytesThenTheDecoderLibraryThrowsCapzError) {
  const std::vector<std::string> streams = golden_streams();
  ASSERT_FALSE(streams.empty());
  std::vector<uint8_t> bytes = slurp(streams.front());
  bytes[bytes.size() / 2] ^= 0x10;
  EXPECT_THROW(capz::decompress(bytes.data(), bytes.size(), "damaged"), capz::Error);
}

}  // namespace
