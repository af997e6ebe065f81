// Fuzz target: the .bin frame reader (io/bin_folder.h), in KITTI's record (x y z intensity) and
// nuScenes' (x y z intensity ring), chosen by the input's first byte. On arbitrary bytes it must
// return or throw capz::Error (a size that is not a whole number of points). A frame it accepts
// has size / point points, and the writer's bytes of it are the input but for the gaps' NaNs.
#include <cmath>
#include <cstddef>
#include <cstdint>
#include <cstring>
#include <vector>

#include "capz/error.h"
#include "fuzz_common.h"
#include "io/bin_folder.h"

extern "C" int LLVMFuzzerTestOneInput(const uint8_t* data, size_t size) {
  if (size == 0) return 0;
  const size_t fields = 1 + (data[0] & 1), point = 4 * (3 + fields);
  ++data;
  --size;
  capz::FrameData f;
  try {
    capz::read_bin_frame(data, size, "fuzz.bin", &f, fields);
  } catch (const capz::Error&) {
    CAPZ_FUZZ_CHECK(size % point != 0);
    return 0;
  }
  CAPZ_FUZZ_CHECK(size % point == 0 && f.points == size / point && f.attrs.size() == fields &&
                  f.valid.size() == f.points);
  std::vector<std::vector<float>> values(fields, std::vector<float>(f.points));
  std::vector<const float*> in;
  for (size_t k = 0; k < fields; ++k) {
    CAPZ_FUZZ_CHECK(f.attrs[k].size() == 4 * f.points);
    if (f.points) std::memcpy(values[k].data(), f.attrs[k].data(), 4 * f.points);
    in.push_back(values[k].data());
  }
  const std::vector<uint8_t> again =
      capz::bin_frame_bytes(f.points, f.xyz.data(), f.valid.data(), in);
  CAPZ_FUZZ_CHECK(again.size() == size);
  for (size_t p = 0; p < f.points; ++p)
    if (f.valid[p])
      CAPZ_FUZZ_CHECK(std::memcmp(again.data() + point * p, data + point * p, point) == 0);
  return 0;
}
