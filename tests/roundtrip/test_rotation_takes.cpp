// Rotation takes of the kind Theia and Visual3D write (issue #38, item 2), built by
// tests/support/rotation_c3d.h's own C3D writer: through `capz compress` (compress_file) at the
// default bound and with --lossless, every rotation comes back bit for bit, --lossless rebuilds
// the file byte for byte, and the residue (HASH, C3DR, C3DP: the rotation section regenerated,
// docs/format/rotw.md) stays under 1% of the archive.
#include <gtest/gtest.h>

#include <cstring>
#include <string>
#include <vector>

#include "capz/codec.h"
#include "capz/compress_file.h"
#include "capz/file.h"
#include "capz/io.h"
#include "capz/original.h"
#include "coding/container.h"
#include "support/rotation_c3d.h"
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

}  // namespace
