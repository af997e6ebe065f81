// Fuzz target: a C3D the reader accepts is written back (write_c3d) and read again. The writer
// must succeed or throw capz::Error, and what it wrote must read back as the same take: frames
// (none when they hold nothing), points, first frame (of a take that has frames), gaps, labels,
// analog channels (their count, samples per frame and every stored value, bit for bit) and every
// valid coordinate within half the file's point scale (an int16 file's step; float files within
// float32 rounding).
#include <cmath>
#include <cstddef>
#include <cstdint>
#include <cstdio>
#include <cstring>

#include "capz/error.h"
#include "capz/io.h"
#include "fuzz_common.h"
#include "fuzz_rewrite.h"

extern "C" int LLVMFuzzerTestOneInput(const uint8_t* data, size_t size) {
  static const capz_fuzz::TempFile out("c3d_rewrite");
  capz::Take t, b;
  if (!capz_fuzz::rewrite(
          out, [&] { return capz::read_c3d_bytes(data, size, "fuzz.c3d"); }, capz::write_c3d,
          capz::read_c3d, &t, &b))
    return 0;
  CAPZ_FUZZ_CHECK(b.points == t.points);
  // Frames that hold nothing (no points, analog or rotations) are read as none: the reader does
  // not trust a count of frames of no bytes (c3d_read.cpp, frames_present).
  const bool empty_frames = t.points == 0 && t.analog.channels == 0 && t.rotations.segments == 0;
  CAPZ_FUZZ_CHECK(b.frames == t.frames || (empty_frames && b.frames == 0));
  if (b.frames != t.frames) return 0;
  // A take of no frames is written as frames 1 .. 0 (C3D counts from 1), whatever it said.
  CAPZ_FUZZ_CHECK(b.first_frame == t.first_frame || t.frames == 0);
  CAPZ_FUZZ_CHECK(b.valid == t.valid);
  CAPZ_FUZZ_CHECK(b.labels.size() == t.labels.size());
  const double step = t.c3d ? t.c3d->point_scale : 0;
  for (size_t i = 0; i < t.frames * t.points; ++i) {
    if (!t.valid[i]) continue;
    for (int a = 0; a < 3; ++a) {
      const double x = t.xyz[i * 3 + a], y = b.xyz[i * 3 + a];
      const double tol = std::max(0.5 * step, std::fabs(x) * 1e-6) + 1e-9;
      if (!(std::fabs(x - y) <= tol)) {
        std::fprintf(stderr, "sample %zu axis %d: %.17g written back as %.17g\n", i, a, x, y);
        std::abort();
      }
    }
  }
  CAPZ_FUZZ_CHECK(b.analog.channels == t.analog.channels);
  if (t.analog.channels > 0) {
    CAPZ_FUZZ_CHECK(b.analog.samples_per_frame == t.analog.samples_per_frame);
    CAPZ_FUZZ_CHECK(b.analog.values.size() == t.analog.values.size());
    for (size_t i = 0; i < t.analog.values.size(); ++i) {
      const double x = t.analog.values[i], y = b.analog.values[i];
      if (std::memcmp(&x, &y, sizeof x) != 0 && !(std::isnan(x) && std::isnan(y))) {
        std::fprintf(stderr, "analog value %zu: %.17g written back as %.17g\n", i, x, y);
        std::abort();
      }
    }
  }
  return 0;
}
