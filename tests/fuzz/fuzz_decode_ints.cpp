// Fuzz target: the integer entropy decoder (decode_ints / IntDecoder over the range coder) on
// arbitrary blocks. The first two bytes choose how many values to ask for (including counts far
// beyond what the block can hold, which must be refused before allocating).
#include <cstddef>
#include <cstdint>

#include "capz/error.h"
#include "coding/entropy.h"
#include "fuzz_common.h"

extern "C" int LLVMFuzzerTestOneInput(const uint8_t* data, size_t size) {
  if (size < 2) return 0;
  const size_t selector = static_cast<size_t>(data[0]) | static_cast<size_t>(data[1]) << 8;
  // Mostly small counts; the top bit asks for an absurd one.
  const size_t count = (selector & 0x8000) ? (size_t{1} << 40) + selector : (selector & 0x7fff);
  data += 2;
  size -= 2;
  try {
    std::vector<int32_t> v = capz::decode_ints(data, size, count, "fuzz block");
    CAPZ_FUZZ_CHECK(v.size() == count);
    // A block that decodes must re-encode to a block that decodes to the same values.
    std::vector<uint8_t> again = capz::encode_ints(v);
    CAPZ_FUZZ_CHECK(capz::decode_ints(again.data(), again.size(), count, "re-encoded") == v);
  } catch (const capz::Error&) {
  }
  return 0;
}
