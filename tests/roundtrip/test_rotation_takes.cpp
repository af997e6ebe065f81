// Rotation takes of the kind Theia and Visual3D write (issue #38, item 2), built by
// tests/support/rotation_c3d.h's own C3D writer: through `capz compress` (compress_file) at the
// default bound and with --lossless, every rotation comes back bit for bit, --lossless rebuilds
// the file byte for byte, and the residue (HASH, C3DR, C3DP: the rotation section regenerated,
// docs/FORMAT.md 7.1, 14) stays under 1% of the archive.
#include <gtest/gtest.h>

#include <algorithm>
#include <cstdio>
#include <cstring>
#include <functional>
#include <stdexcept>
#include <string>
#include <vector>

#include "capz/codec.h"
#include "capz/compress_file.h"
#include "capz/file.h"
#include "capz/io.h"
#include "capz/original.h"
#include "coding/bytes.h"
#include "coding/container.h"
#include "support/rotation_c3d.h"
#include "support/stream_pieces.h"
#include "test_util.h"

namespace {

// Bytes of the residue chunks (HASH, C3DR, C3DP with their framing) of the archive `z`.
size_t residue_bytes(const std::vector<uint8_t>& z) {
  size_t off = capz::file_header_bytes(z[9]), total = 0;
  while (off < z.size()) {
    const capz::Chunk c = capz::read_chunk(z.data(), z.size(), off, "archive");
    if (c.type == "HASH" || c.type == "C3DR" || c.type == "C3DP") total += c.end - c.offset;
    off = c.end;
  }
  return total;
}

bool same_bits(const std::vector<float>& a, const std::vector<float>& b) {
  return a.size() == b.size() && std::memcmp(a.data(), b.data(), 4 * a.size()) == 0;
}

class RotationTakes : public ::testing::TestWithParam<size_t> {};

TEST_P(RotationTakes, RotationsExactResidueUnderOnePercentLosslessByteForByte) {
  const capz_test::NamedRotationTake take = capz_test::rotation_takes()[GetParam()];
  SCOPED_TRACE(take.name);
  capz_test::TempDir tmp("capz_rot_takes");
  const std::string in = tmp.file(take.name + ".c3d"), z = tmp.file("z.capz"),
                    back = tmp.file("back.c3d");
  const std::vector<uint8_t> original = capz_test::make_rotation_c3d(take.spec);
  capz::write_file(in, original, true);
  const capz::Take read = capz::read_c3d(in);
  ASSERT_EQ(read.rotations.segments, static_cast<int>(take.spec.segments));
  ASSERT_EQ(read.frames, take.spec.frames);
  for (bool lossless : {false, true}) {
    SCOPED_TRACE(lossless ? "lossless" : "default bound");
    capz::CompressTarget target;
    target.lossless = lossless;
    capz::CompressOptions opts;
    opts.window_frames = 128;  // several windows
    capz::CompressStats stats;
    capz::compress_file(in, z, target, opts, "", true, &stats);
    const std::vector<uint8_t> bytes = capz::read_file(z);
    const size_t residue = residue_bytes(bytes);
    EXPECT_LT(100 * residue, bytes.size())
        << "residue " << residue << " B of an archive of " << bytes.size() << " B";
    std::printf("%s %s: archive %zu B, residue %zu B\n", take.name.c_str(),
                lossless ? "lossless" : "default", bytes.size(), residue);
    const capz::Take got = capz::decompress(bytes.data(), bytes.size());
    EXPECT_TRUE(same_bits(got.rotations.matrices, read.rotations.matrices));
    EXPECT_TRUE(same_bits(got.rotations.reliability, read.rotations.reliability));
    capz::rebuild_original(z, back, true);
    const std::vector<uint8_t> rebuilt = capz::read_file(back);
    if (lossless || take.spec.points == 0) {
      EXPECT_TRUE(rebuilt == original);
    } else {  // at a bound: the same size; the file's last bytes (rotations, padding) exact
      ASSERT_EQ(rebuilt.size(), original.size());
      const long rot = static_cast<long>(read.rotations.matrices.size() / 16 * 68);
      EXPECT_TRUE(std::equal(rebuilt.end() - rot, rebuilt.end(), original.end() - rot));
    }
  }
}

INSTANTIATE_TEST_SUITE_P(Built, RotationTakes,
                         ::testing::Range(size_t{0}, capz_test::rotation_takes().size()));

// NaN payloads in the rotation section come back bit for bit; then the rotation fields of C3DR
// and the C3DP patches over the rotations, damaged one at a time (CRCs and INDX made valid
// again): the rebuild fails with capz::Error (kCorrupt).
TEST(RotationTakes, NanPayloadsComeBackAndDamagedRotationResidueIsCorrupt) {
  capz_test::RotationTakeSpec spec;
  spec.frames = 60;
  spec.segments = 5;
  spec.points = 3;
  capz_test::TempDir tmp("capz_rot_residue");
  const std::string in = tmp.file("in.c3d"), z = tmp.file("z.capz"), bad = tmp.file("bad.capz"),
                    out = tmp.file("out.c3d");
  std::vector<uint8_t> original = capz_test::make_rotation_c3d(spec);
  original[original.size() - 1] = 7;  // the tail: a byte after the rotations
  // NaN payloads: a signalling NaN in a rotation element and a quiet one with a payload in the
  // reliability of sample 7, segment 2 (found by its bytes: Intel float32s).
  capz::write_file(in, original, true);
  {
    const capz::Take t = capz::read_c3d(in);
    const size_t i = 7 * spec.segments + 2;
    std::vector<uint8_t> pattern(68);
    std::memcpy(pattern.data(), &t.rotations.matrices[16 * i], 64);
    std::memcpy(pattern.data() + 64, &t.rotations.reliability[i], 4);
    const auto at = std::search(original.begin(), original.end(), pattern.begin(), pattern.end());
    ASSERT_NE(at, original.end());
    const uint8_t snan[4] = {0x01, 0x00, 0x80, 0x7f}, payload[4] = {0x23, 0x01, 0xc0, 0x7f};
    std::copy(snan, snan + 4, at);
    std::copy(payload, payload + 4, at + 64);
    capz::write_file(in, original, true);
  }
  capz::CompressTarget target;
  target.lossless = true;
  capz::CompressOptions opts;
  opts.window_frames = 16;
  capz::compress_file(in, z, target, opts, "", true);
  capz::rebuild_original(z, out, true);
  ASSERT_TRUE(capz::read_file(out) == original);
  const std::vector<uint8_t> good = capz::read_file(z);
  const capz::Take back = capz::decompress(good.data(), good.size());
  uint32_t bits[2];
  std::memcpy(&bits[0], &back.rotations.matrices[16 * (7 * spec.segments + 2)], 4);
  std::memcpy(&bits[1], &back.rotations.reliability[7 * spec.segments + 2], 4);
  EXPECT_EQ(bits[0], 0x7f800001u);
  EXPECT_EQ(bits[1], 0x7fc00123u);
  auto rebuild_error = [&](const std::function<void(std::vector<capz_test::Piece>*)>& change) {
    std::vector<capz_test::Piece> ps = capz_test::pieces(good);
    change(&ps);
    capz::write_file(bad, capz_test::assemble(good, ps), true);
    try {
      capz::rebuild_original(bad, out, true);
    } catch (const capz::Error& e) {
      EXPECT_EQ(e.code(), capz::ErrorCode::kCorrupt) << e.what();
      return std::string(e.what());
    }
    return std::string();
  };
  auto c3dr = [](std::vector<capz_test::Piece>* ps) -> std::vector<uint8_t>& {
    for (capz_test::Piece& p : *ps)
      if (p.type == "C3DR") return p.payload;
    throw std::runtime_error("no C3DR");
  };
  // C3DR: kind, processor, flags, scale, frames, points, analog values, per_frame, head_size,
  // then rot_gap and rot_per_frame (docs/FORMAT.md 7.1).
  std::vector<capz_test::Piece> ps0 = capz_test::pieces(good);
  const std::vector<uint8_t>& r0 = c3dr(&ps0);
  capz::ByteReader rd(r0.data(), r0.size(), "C3DR");
  rd.u8();
  rd.u8();
  const size_t flags = rd.offset();
  ASSERT_EQ(rd.u8(), 5) << "float storage and the rotation section";
  rd.f64();
  for (int i = 0; i < 5; ++i) rd.varint();
  const size_t gap_at = rd.offset();
  EXPECT_GT(rd.varint(), 0u);
  const size_t per_frame_at = rd.offset();
  EXPECT_EQ(rd.varint(), 5u * 68);
  EXPECT_FALSE(rebuild_error([&](std::vector<capz_test::Piece>* ps) {
                 c3dr(ps)[flags] = 1;  // the rotation section not regenerated: sizes differ
               }).empty());
  EXPECT_FALSE(rebuild_error([&](std::vector<capz_test::Piece>* ps) {
                 c3dr(ps)[flags] = 13;  // an unknown flag
               }).empty());
  EXPECT_FALSE(rebuild_error([&](std::vector<capz_test::Piece>* ps) {
                 c3dr(ps)[per_frame_at] ^= 4;  // rot_per_frame not 68 x R x G
               }).empty());
  EXPECT_FALSE(rebuild_error([&](std::vector<capz_test::Piece>* ps) {
                 c3dr(ps)[gap_at] += 1;  // rot_gap one byte more
               }).empty());
  // A C3DP added to window 1, patching a rotation byte past the window's bytes.
  EXPECT_FALSE(rebuild_error([&](std::vector<capz_test::Piece>* ps) {
                 size_t w = 0;
                 for (size_t i = 0; i < ps->size(); ++i)
                   if ((*ps)[i].type == "ROTW" && w++ == 1) {
                     // window 1, packed stored: method 0, size 4, n 4; patch: 1 run, skip
                     // 16 x (frame + rotation bytes), length 1, the byte.
                     const size_t past = 16 * (3 * 16 + 5 * 68);
                     capz_test::Piece p{"C3DP",
                                        {1, 0, 5, 5, 1, static_cast<uint8_t>(0x80 | (past & 0x7f)),
                                         static_cast<uint8_t>(past >> 7), 0, 9}};
                     ps->insert(ps->begin() + static_cast<long>(i) + 1, p);
                     break;
                   }
               }).empty());
}

}  // namespace
