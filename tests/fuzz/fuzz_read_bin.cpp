// Fuzz target: the KITTI .bin frame reader (io/bin_folder.h). On arbitrary bytes it must return
// or throw capz::Error (a size that is not a whole number of 16-byte points). A frame it accepts
// has size / 16 points, and the writer's bytes of it are the input but for the gaps' NaNs.
#include <cmath>
#include <cstddef>
#include <cstdint>
#include <cstring>
#include <vector>

#include "capz/error.h"
#include "fuzz_common.h"
#include "io/bin_folder.h"

extern "C" int LLVMFuzzerTestOneInput(const uint8_t* data, size_t size) {
  capz::FrameData f;
  try {
    capz::read_bin_frame(data, size, "fuzz.bin", &f);
  } catch (const capz::Error&) {
    CAPZ_FUZZ_CHECK(size % 16 != 0);
    return 0;
  }
  CAPZ_FUZZ_CHECK(size % 16 == 0 && f.points == size / 16 && f.attrs.size() == 1 &&
                  f.attrs[0].size() == 4 * f.points && f.valid.size() == f.points);
  std::vector<float> intensity(f.points);
  if (f.points) std::memcpy(intensity.data(), f.attrs[0].data(), 4 * f.points);
  const std::vector<uint8_t> again =
      capz::bin_frame_bytes(f.points, f.xyz.data(), f.valid.data(), intensity.data());
  CAPZ_FUZZ_CHECK(again.size() == size);
  for (size_t p = 0; p < f.points; ++p)
    if (f.valid[p]) CAPZ_FUZZ_CHECK(std::memcmp(again.data() + 16 * p, data + 16 * p, 16) == 0);
  return 0;
}
