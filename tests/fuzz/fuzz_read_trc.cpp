// Fuzz target: the TRC reader (read_trc_bytes) on arbitrary bytes. It must return a well-formed
// Take or throw capz::Error; every valid sample must hold finite coordinates.
#include <cmath>
#include <cstddef>
#include <cstdint>

#include "capz/error.h"
#include "capz/io.h"
#include "fuzz_common.h"

extern "C" int LLVMFuzzerTestOneInput(const uint8_t* data, size_t size) {
  try {
    capz::Take t = capz::read_trc_bytes(data, size, "fuzz.trc");
    capz_fuzz::check_take_shape(t);
    CAPZ_FUZZ_CHECK(t.trc != nullptr);
    CAPZ_FUZZ_CHECK(t.trc->times.size() == t.frames);
    CAPZ_FUZZ_CHECK(t.trc->frame_numbers.size() == t.frames);
    for (size_t i = 0; i < t.frames * t.points; ++i)
      if (t.valid[i])
        for (int a = 0; a < 3; ++a) CAPZ_FUZZ_CHECK(std::isfinite(t.xyz[i * 3 + a]));
  } catch (const capz::Error&) {
  }
  return 0;
}
