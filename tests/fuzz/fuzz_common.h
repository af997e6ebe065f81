// Shared by the fuzz targets: what counts as a finding.
//
// A target calls library code on arbitrary bytes. capz::Error is the expected way to refuse bad
// input; anything else is a bug: a crash or sanitizer report, a hang, a huge allocation (caught
// by libFuzzer's -rss_limit_mb / -malloc_limit_mb), an exception of another type (it escapes the
// target and aborts), or a result that breaks the Take's invariants (CAPZ_FUZZ_CHECK aborts).
#pragma once

#include <cstdio>
#include <cstdlib>

#include "capz/take.h"

#define CAPZ_FUZZ_CHECK(cond)                                                            \
  do {                                                                                   \
    if (!(cond)) {                                                                       \
      std::fprintf(stderr, "%s:%d: fuzz check failed: %s\n", __FILE__, __LINE__, #cond); \
      std::abort();                                                                      \
    }                                                                                    \
  } while (0)

namespace capz_fuzz {

// The shape invariants every Take a reader or decoder returns must satisfy (take.h): frames x
// points, or for frames of their own point counts frames + 1 non-decreasing offsets from 0.
inline void check_take_shape(const capz::Take& t) {
  if (t.ragged()) {
    CAPZ_FUZZ_CHECK(t.frame_offsets.size() == t.frames + 1 && t.frame_offsets[0] == 0);
    for (size_t f = 0; f < t.frames; ++f)
      CAPZ_FUZZ_CHECK(t.frame_offsets[f] <= t.frame_offsets[f + 1]);
    CAPZ_FUZZ_CHECK(t.points == 0 && t.labels.empty());
  }
  CAPZ_FUZZ_CHECK(t.xyz.size() == t.total_points() * 3);
  CAPZ_FUZZ_CHECK(t.valid.size() == t.total_points());
  for (uint8_t v : t.valid) CAPZ_FUZZ_CHECK(v == 0 || v == 1);
  CAPZ_FUZZ_CHECK(t.labels.empty() || t.labels.size() == t.points);
  if (t.analog.channels > 0) {
    CAPZ_FUZZ_CHECK(t.analog.samples_per_frame >= 0);
    CAPZ_FUZZ_CHECK(t.analog.values.size() == t.frames *
                                                  static_cast<size_t>(t.analog.samples_per_frame) *
                                                  static_cast<size_t>(t.analog.channels));
  }
}

}  // namespace capz_fuzz
