// Damaged .capz input: every stream in streams/ (made by make_streams.py, names say what is
// wrong) is rejected with one clean capz::Error; flipping or cutting bytes of a valid stream
// gives a clean error or a harmless result, never a crash, hang or huge allocation.
#include <gtest/gtest.h>

#include <filesystem>
#include <random>

#include "capz/codec.h"
#include "capz/error.h"
#include "chunk_util.h"
#include "coding/crc32c.h"
#include "core/atomic_file.h"

namespace capz {
namespace {

namespace fs = std::filesystem;
const std::string kDir = std::string(CAPZ_TEST_DIR) + "/corrupt/streams";

bool clean(const Error& e) {
  const std::string m = e.what();
  return !m.empty() && m.find('\n') == std::string::npos &&
         (e.code() == ErrorCode::kCorrupt || e.code() == ErrorCode::kNotOurFormat ||
          e.code() == ErrorCode::kUnsupportedVersion);
}

// Payload bytes of the chunk at `at` from `from` on flipped in turn (one random bit, the chunk's
// CRC made right; every byte of a short payload, else capz_test::payload_positions): each decodes
// or throws a clean error (counted in *errors if given).
void expect_clean_under_flips(const std::vector<uint8_t>& good, size_t at, size_t from,
                              uint32_t seed, const char* chunk, int* errors = nullptr) {
  const size_t len = capz_test::chunk_len(good, at);
  std::mt19937 rng(seed);
  for (const size_t i : capz_test::payload_positions(len)) {
    if (i < from) continue;
    std::vector<uint8_t> b = good;
    b[at + 8 + i] ^= static_cast<uint8_t>(1u << (rng() % 8));
    capz_test::fix_crc(&b, at);
    try {
      decompress(b.data(), b.size(), "t.capz");
    } catch (const Error& e) {
      ASSERT_TRUE(clean(e)) << chunk << " byte " << i << ": " << e.what();
      if (errors) ++*errors;
    }
  }
}

TEST(Corrupt, GivenEveryCraftedStreamWhenDecodedThenCleanError) {
  size_t n = 0;
  for (const auto& entry : fs::directory_iterator(kDir)) {
    const std::string path = entry.path().string();
    std::vector<uint8_t> b = read_file(path);
    ++n;
    bool threw = false;
    try {
      decompress(b.data(), b.size(), entry.path().filename().string());
    } catch (const Error& e) {
      threw = true;
      EXPECT_TRUE(clean(e)) << path << ": " << e.what();
    }
    EXPECT_TRUE(threw) << path << " was accepted";
    // describe() reads less of the stream; it may accept some, but never crashes.
    try {
      describe(b.data(), b.size(), path);
    } catch (const Error& e) {
      EXPECT_TRUE(clean(e)) << path << ": " << e.what();
    }
  }
  EXPECT_GE(n, 20u);
}

TEST(Corrupt, GivenErrorsThenTheyNameTheProblem) {
  auto message = [](const char* name) {
    std::vector<uint8_t> b = read_file(kDir + "/" + name);
    try {
      decompress(b.data(), b.size(), name);
    } catch (const Error& e) {
      return std::string(e.what());
    }
    return std::string();
  };
  EXPECT_NE(message("posw_bad_crc.capz").find("POSW"), std::string::npos);
  EXPECT_NE(message("posw_bad_crc.capz").find("CRC"), std::string::npos);
  EXPECT_NE(message("future_major_version.capz").find("version"), std::string::npos);
  EXPECT_NE(message("text_file.capz").find("not a .capz"), std::string::npos);
  EXPECT_NE(message("crlf_converted_magic.capz").find("text-mode"), std::string::npos);
  EXPECT_NE(message("indx_missing.capz").find("INDX"), std::string::npos);
  EXPECT_NE(message("prerelease_magic.capz").find("pre-release capz stream (format 9.3)"),
            std::string::npos);
  EXPECT_NE(message("unknown_critical_chunk.capz").find("chunk SCAN of format 1.1"),
            std::string::npos);
  EXPECT_NE(message("version_bytes_bad_crc.capz").find("damaged file header"), std::string::npos);
}

// b's text of the error decompressing it gives ("" when it decodes); the error must be clean.
std::string decode_error_text(const std::vector<uint8_t>& b) {
  try {
    decompress(b.data(), b.size(), "t.capz");
  } catch (const Error& e) {
    EXPECT_TRUE(clean(e)) << e.what();
    return std::string(e.what());
  }
  return std::string();
}

// A small stream with everything in it: gaps, analog, C3D words, rotations, several windows.
std::vector<uint8_t> small_stream() {
  Take t;
  t.format = Format::kC3D;
  t.resize(60, 3);
  t.units = "mm";
  t.rate = 100;
  t.labels = {"A", "B", "C"};
  t.c3d = std::make_shared<C3DExtra>();
  t.c3d->float_storage = true;
  t.c3d->point_scale = 0.1;
  t.c3d->residual.assign(180, 0.5f);
  t.c3d->camera_mask.assign(180, 3);
  for (size_t f = 0; f < 60; ++f)
    for (size_t p = 0; p < 3; ++p) {
      t.valid[f * 3 + p] = (f + p) % 17 != 0;
      for (int a = 0; a < 3; ++a) t.at(f, p)[a] = t.valid[f * 3 + p] ? 100.0 * p + f * 0.7 + a : 0;
    }
  t.analog.channels = 2;
  t.analog.samples_per_frame = 2;
  t.analog.labels = {"X", "Y"};
  for (size_t i = 0; i < 240; ++i) t.analog.values.push_back(static_cast<double>((i * 37) % 101));
  t.rotations.segments = 1;
  t.rotations.samples_per_frame = 2;
  for (size_t i = 0; i < 120 * 16; ++i)
    t.rotations.matrices.push_back(i % 5 == 4 ? 1.0f : 0.01f * static_cast<float>(i % 97));
  t.rotations.reliability.assign(120, 1.0f);
  CompressOptions o;
  o.max_error = 0.05;
  o.window_frames = 16;
  return compress(t, o);
}

TEST(Corrupt, GivenEveryBitFlippedOnceWhenDecodedThenCleanErrorOrHarmless) {
  const std::vector<uint8_t> good = small_stream();
  std::mt19937 rng(11);
  for (size_t i = 0; i < good.size(); ++i) {
    std::vector<uint8_t> b = good;
    b[i] ^= static_cast<uint8_t>(1u << (rng() % 8));
    try {
      Take t = decompress(b.data(), b.size());
      EXPECT_EQ(t.xyz.size(), t.frames * t.points * 3);
    } catch (const Error& e) {
      ASSERT_TRUE(clean(e)) << "byte " << i << ": " << e.what();
    }
    try {
      decompress_frames(b.data(), b.size(), 20, 10);
    } catch (const Error& e) {
      ASSERT_TRUE(clean(e)) << "byte " << i << ": " << e.what();
    }
  }
}

TEST(Corrupt, GivenEveryTruncationWhenDecodedThenCleanError) {
  const std::vector<uint8_t> good = small_stream();
  for (size_t n = 0; n < good.size(); ++n) {
    try {
      decompress(good.data(), n);
      FAIL() << "truncated to " << n << " bytes was accepted";
    } catch (const Error& e) {
      ASSERT_TRUE(clean(e)) << n << ": " << e.what();
    }
  }
}

// A golden stream of the format written (tests/golden/streams).
std::vector<uint8_t> golden(const std::string& name) {
  const std::vector<uint8_t> b = read_file(std::string(CAPZ_TEST_DIR) + "/golden/streams/" + name);
  EXPECT_GT(b.size(), 15u);
  EXPECT_EQ(b.at(9), 1);
  return b;
}

// FORMAT.md 8.1: META coding 3, with dictionary 1 only; its LZMA2 data, damaged under a valid
// CRC, gives a clean error or a harmless take.
TEST(Corrupt, GivenMetaCoding3DamagedThenCleanCorruptNamingMeta) {
  const std::vector<uint8_t> good = golden("Capture0004.c3d.grid1mm.v1.0.capz");
  const size_t meta = capz_test::find_chunk(good, "META");
  ASSERT_NE(meta, std::string::npos);
  ASSERT_EQ(good[meta + 8], 3) << "the golden stream's META is coding 3";
  // A dictionary number the format does not define.
  std::vector<uint8_t> d2 = good;
  d2[meta + 9] = 2;
  capz_test::fix_crc(&d2, meta);
  const std::string ed = decode_error_text(d2);
  EXPECT_NE(ed.find("META"), std::string::npos) << ed;
  EXPECT_NE(ed.find("dictionary 2"), std::string::npos) << ed;
  // Payload bytes after the dictionary byte flipped in turn (payload_positions), the CRC made
  // right.
  expect_clean_under_flips(good, meta, 2, 5, "META");
}

// FORMAT.md 9.2 at stream level: ANLG payload bytes (payload_positions) of the golden stream whose
// force channels are interpolated, flipped under a valid CRC, gives a clean error or a take.
TEST(Corrupt, GivenInterpolatedAnalogDamagedThenCleanCorruptNamingAnlg) {
  const std::vector<uint8_t> good = golden("codamotion_gaitwands_19970212.c3d.lossless.v1.0.capz");
  decompress(good.data(), good.size(), "good.capz");
  const size_t anlg = capz_test::find_chunk(good, "ANLG");
  ASSERT_NE(anlg, std::string::npos);
  expect_clean_under_flips(good, anlg, 0, 9, "ANLG");
}

// FORMAT.md 9.1: an ANLG payload using the float coder's predictors 2-5, damaged under a valid
// CRC, gives a clean error or a harmless take.
TEST(Corrupt, GivenFloatPredictorsDamagedThenCleanCorruptNamingAnlg) {
  const std::vector<uint8_t> good = golden("repeat_analog.c3d.lossless.v1.0.capz");
  // Bytes of the first window's ANLG payload flipped in turn (payload_positions), the CRC made
  // right.
  const size_t anlg = capz_test::find_chunk(good, "ANLG");
  ASSERT_NE(anlg, std::string::npos);
  int errors = 0;
  expect_clean_under_flips(good, anlg, 0, 6, "ANLG", &errors);
  EXPECT_GT(errors, 0);
}

// FORMAT.md 9.7: an ANLG window's version byte has one value in format 1.0, 2. The golden stream
// of a take with force and EMG channels with its first window's version byte set to 0 or 1 (the
// pre-release versions) is refused with one clean error naming ANLG; bytes of that payload
// flipped under a valid CRC gives a clean error or a take.
TEST(Corrupt, GivenOtherAnalogWindowVersionsOrDamageThenCleanCorruptNamingAnlg) {
  const std::vector<uint8_t> good = golden("EB015PI.c3d.lossless.v1.0.capz");
  decompress(good.data(), good.size(), "good.capz");
  const size_t anlg = capz_test::find_chunk(good, "ANLG");
  ASSERT_NE(anlg, std::string::npos);
  ASSERT_EQ(good[anlg + 9], 2);  // after the window index 0
  for (const uint8_t v : {0, 1, 3}) {
    std::vector<uint8_t> b = good;
    b[anlg + 9] = v;
    capz_test::fix_crc(&b, anlg);
    const std::string e = decode_error_text(b);
    EXPECT_NE(e.find("ANLG"), std::string::npos) << e;
    EXPECT_NE(e.find("unknown analog window version"), std::string::npos) << e;
  }
  int errors = 0;
  expect_clean_under_flips(good, anlg, 0, 13, "ANLG", &errors);
  EXPECT_GT(errors, 0);
}

}  // namespace
}  // namespace capz
