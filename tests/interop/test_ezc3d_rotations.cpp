// Rotations through a .capz, read by ezc3d (issue #14): a C3D with a ROTATION section, built
// here, is compressed (lossless and at 0.1 mm), decompressed and written back; ezc3d must read
// from capz's file the rotations it reads from the original, bit for bit, and nothing else may
// differ beyond the coordinates' bound.
#include <gtest/gtest.h>

#include <cmath>
#include <string>
#include <vector>

#include "capz/codec.h"
#include "capz/file.h"
#include "capz/io.h"
#include "interop/ezc3d_compare.h"
#include "interop/ezc3d_snapshot.h"
#include "support/rotation_c3d.h"
#include "test_util.h"

namespace {

using namespace capz_interop;

// A float C3D of 30 frames, `points` points and 2 segments at 2 rotation samples per frame.
capz::Take take_with_rotations(size_t points) {
  capz::Take t;
  t.format = capz::Format::kC3D;
  t.resize(30, points);
  t.rate = 60;
  t.units = "mm";
  for (size_t p = 0; p < points; ++p) t.labels.push_back("M" + std::to_string(p));
  for (size_t i = 0; i < t.xyz.size(); ++i)
    t.xyz[i] = static_cast<float>(200 + 30 * std::sin(0.01 * static_cast<double>(i)));
  t.valid.assign(t.frames * points, 1);
  capz::Rotations& r = t.rotations;
  r.segments = 2;
  r.samples_per_frame = 2;
  r.rate = 120;
  r.labels = {"pelvis", "femur"};
  for (size_t s = 0; s < 60; ++s)
    for (size_t g = 0; g < 2; ++g) {
      const float a = 0.03f * static_cast<float>(s) + static_cast<float>(g);
      const float m[16] = {std::cos(a), std::sin(a), 0, 0, -std::sin(a), std::cos(a), 0, 0,
                           0,           0,           1, 0, 10.0f * a,    -0.0f,       5, 1};
      r.matrices.insert(r.matrices.end(), m, m + 16);
      r.reliability.push_back(s == 7 ? std::nanf("") : 1.0f);
    }
  return t;
}

TEST(Ezc3dInterop, RotationsComeBackFromCapzAsEzc3dReadsTheOriginal) {
  capz_test::TempDir tmp("capz_ezc3d_rot");
  for (size_t points : {size_t{0}, size_t{3}}) {
    capz::WriteOptions wo;
    wo.c3d_float = true;
    wo.overwrite = true;
    const std::string orig = tmp.file("orig.c3d"), back = tmp.file("back.c3d");
    capz::write_c3d(take_with_rotations(points), orig, wo);
    const EzTake want = read_with_ezc3d(orig);
    ASSERT_GT(want.rotations_per_frame, 0u) << "ezc3d reads no rotations from the original";
    const capz::Take t = capz::read_c3d(orig);
    for (bool lossless : {true, false}) {
      SCOPED_TRACE(std::to_string(points) + " points, " + (lossless ? "lossless" : "0.1 mm"));
      capz::CompressOptions o;
      o.lossless = lossless;
      o.max_error = lossless ? 0 : 0.1;
      o.window_frames = 8;  // several windows
      const std::vector<uint8_t> z = capz::compress(t, o);
      capz::write_take(capz::decompress(z.data(), z.size()), back, wo);
      const EzTake got = read_with_ezc3d(back);
      EXPECT_EQ(got.rotations_per_frame, want.rotations_per_frame);
      const Diffs d = compare(want, got, lossless ? 0 : 0.1);
      EXPECT_EQ(d.found, 0u) << d.describe();
    }
  }
}

// The rotation takes of tests/support/rotation_c3d.h (issue #38) are C3D files as ezc3d reads
// them: the same frames, and every rotation value (NaN where capz reads a NaN).
TEST(Ezc3dInterop, BuiltRotationTakesReadTheSameInEzc3d) {
  capz_test::TempDir tmp("capz_ezc3d_takes");
  for (const capz_test::NamedRotationTake& take : capz_test::rotation_takes()) {
    SCOPED_TRACE(take.name);
    const std::string path = tmp.file(take.name + ".c3d");
    capz::write_file(path, capz_test::make_rotation_c3d(take.spec), true);
    const capz::Take t = capz::read_c3d(path);
    const EzTake ez = read_with_ezc3d(path);
    ASSERT_EQ(ez.frames, t.frames);
    ASSERT_EQ(ez.points, t.points);
    const size_t per_frame = t.rotations.per_frame();
    ASSERT_EQ(ez.rotations_per_frame, per_frame * 17);
    size_t differ = 0;
    for (size_t r = 0; r < t.frames * per_frame; ++r)
      for (size_t k = 0; k < 17; ++k) {
        const double want = k < 16 ? t.rotations.matrices[r * 16 + (k % 4) * 4 + k / 4]
                                   : t.rotations.reliability[r];
        const double got = ez.rotations[r * 17 + k];
        if (!(got == want || (std::isnan(got) && std::isnan(want)))) ++differ;
      }
    EXPECT_EQ(differ, 0u);
  }
}

}  // namespace
