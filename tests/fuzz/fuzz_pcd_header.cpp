// Fuzz target: the PCD frame header parser (io/pcd_header.h), which capz runs before PCL sees a
// frame's bytes, and the ASCII body check. On arbitrary bytes each must return or throw
// capz::Error. A header it accepts is consistent: FIELDS, SIZE, TYPE and COUNT of one length,
// POINTS = WIDTH x HEIGHT, the point step their sum, a known DATA type, and a binary body large
// enough for the points it announces.
#include <cstddef>
#include <cstdint>
#include <vector>

#include "capz/error.h"
#include "fuzz_common.h"
#include "io/pcd_header.h"

extern "C" int LLVMFuzzerTestOneInput(const uint8_t* data, size_t size) {
  const std::vector<uint8_t> bytes(data, data + size);
  capz::PcdHeader h;
  try {
    h = capz::parse_header(bytes, "fuzz.pcd");
  } catch (const capz::Error&) {
    return 0;
  }
  const size_t n = h.fields.size();
  CAPZ_FUZZ_CHECK(n > 0 && h.sizes.size() == n && h.types.size() == n && h.counts.size() == n);
  CAPZ_FUZZ_CHECK(h.points == h.width * h.height);
  uint64_t step = 0, values = 0;
  for (size_t i = 0; i < n; ++i) {
    CAPZ_FUZZ_CHECK(h.sizes[i] == 1 || h.sizes[i] == 2 || h.sizes[i] == 4 || h.sizes[i] == 8);
    CAPZ_FUZZ_CHECK(h.types[i] == 'F' || h.types[i] == 'I' || h.types[i] == 'U');
    step += static_cast<uint64_t>(h.sizes[i]) * h.counts[i];
    values += h.counts[i];
  }
  CAPZ_FUZZ_CHECK(step == h.point_step && values == h.values_per_point);
  CAPZ_FUZZ_CHECK(h.data_idx <= size);
  CAPZ_FUZZ_CHECK(h.viewpoint.empty() || h.viewpoint.size() == 7);
  CAPZ_FUZZ_CHECK(h.data == "binary" || h.data == "binary_compressed" || h.data == "ascii");
  if (h.data == "binary" && h.point_step > 0)
    CAPZ_FUZZ_CHECK(h.points <= (size - h.data_idx) / h.point_step);
  if (h.data == "ascii") {
    try {
      capz::check_ascii_body(bytes, h, "fuzz.pcd");
    } catch (const capz::Error&) {
    }
  }
  return 0;
}
