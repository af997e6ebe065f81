// Fuzz target: a TRC the reader accepts is written back (write_trc) and read again. The writer
// must succeed or throw capz::Error, and what it wrote must read back as the same take: frames,
// points, first frame, gaps, labels, rate, units, the Time and Frame# columns, and every valid
// coordinate within half a unit of the last decimal the source wrote (relative 1e-6 when the
// reader found no decimals).
#include <cmath>
#include <cstddef>
#include <cstdint>
#include <cstdio>

#include "capz/error.h"
#include "capz/io.h"
#include "fuzz_common.h"
#include "fuzz_rewrite.h"

namespace {

// Half a unit of the d-th decimal, or a relative 1e-6 of x when d is unknown (< 0).
double half_unit(int d, double x) {
  const double rel = std::fabs(x) * 1e-6 + 1e-12;
  return d < 0 ? rel : std::max(rel, 0.5 * std::pow(10.0, -d) * (1 + 1e-9));
}

}  // namespace

extern "C" int LLVMFuzzerTestOneInput(const uint8_t* data, size_t size) {
  static const capz_fuzz::TempFile out("trc_rewrite");
  capz::Take t, b;
  if (!capz_fuzz::rewrite(
          out, [&] { return capz::read_trc_bytes(data, size, "fuzz.trc"); }, capz::write_trc,
          capz::read_trc, &t, &b))
    return 0;
  CAPZ_FUZZ_CHECK(b.frames == t.frames && b.points == t.points);
  CAPZ_FUZZ_CHECK(b.valid == t.valid);
  CAPZ_FUZZ_CHECK(b.labels.size() == t.labels.size());
  CAPZ_FUZZ_CHECK(t.trc && b.trc);
  CAPZ_FUZZ_CHECK(b.trc->frame_numbers == t.trc->frame_numbers);
  for (size_t f = 0; f < t.frames; ++f) {
    const double x = t.trc->times[f], y = b.trc->times[f];
    const bool same = x == y || (std::isnan(x) && std::isnan(y));  // a NaN time stays NaN
    if (!same && !(std::fabs(x - y) <= half_unit(t.trc->time_decimals, x))) {
      std::fprintf(stderr, "time of frame %zu: %.17g written back as %.17g\n", f, x, y);
      std::abort();
    }
  }
  for (size_t i = 0; i < t.frames * t.points; ++i) {
    if (!t.valid[i]) continue;
    for (int a = 0; a < 3; ++a) {
      const double x = t.xyz[i * 3 + a], y = b.xyz[i * 3 + a];
      if (!(std::fabs(x - y) <= half_unit(t.trc->decimals, x))) {
        std::fprintf(stderr, "sample %zu axis %d: %.17g written back as %.17g\n", i, a, x, y);
        std::abort();
      }
    }
  }
  return 0;
}
