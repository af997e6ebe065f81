// Fuzz target: the full decoder (decompress, and decompress_frames of a frame range chosen by
// the last byte) on arbitrary bytes, as given and with every chunk CRC made valid. It must return
// a well-formed Take or throw capz::Error.
#include <cstddef>
#include <cstdint>

#include "capz/codec.h"
#include "capz/error.h"
#include "fuzz_common.h"
#include "fuzz_util_capz.h"

namespace {

void decode(const uint8_t* data, size_t size) {
  try {
    capz::Take t = capz::decompress(data, size, "fuzz.capz", capz_fuzz::decode_options());
    capz_fuzz::check_take_shape(t);
    if (size > 0 && t.frames > 0) {
      const size_t first = data[size - 1] % t.frames;
      capz::Take part =
          capz::decompress_frames(data, size, first, 3, "fuzz.capz", capz_fuzz::decode_options());
      capz_fuzz::check_take_shape(part);
      CAPZ_FUZZ_CHECK(part.points == t.points);
      CAPZ_FUZZ_CHECK(part.frames == std::min<size_t>(3, t.frames - first));
    }
  } catch (const capz::Error&) {
  }
}

}  // namespace

extern "C" int LLVMFuzzerTestOneInput(const uint8_t* data, size_t size) {
  decode(data, size);
  std::vector<uint8_t> fixed = capz_fuzz::with_fixed_crcs(data, size);
  if (fixed != std::vector<uint8_t>(data, data + size)) decode(fixed.data(), fixed.size());
  return 0;
}
