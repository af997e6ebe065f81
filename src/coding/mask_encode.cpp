// MASK's encoder (docs/FORMAT.md 9): per point, runs of valid and gap frames; the decoder is
// mask.cpp.
#include "coding/entropy.h"
#include "coding/mask.h"

namespace capz {

std::vector<uint8_t> encode_mask(const uint8_t* valid, size_t frames, size_t points) {
  IntEncoder enc(3);
  for (size_t p = 0; p < points; ++p) {
    size_t f = 0;
    bool first = true;
    bool want = true;  // runs start with a valid run
    while (f < frames) {
      size_t run = 0;
      while (f + run < frames && (valid[(f + run) * points + p] != 0) == want) ++run;
      enc.put(static_cast<uint32_t>(run), first ? 0 : want ? 2 : 1);
      first = false;
      want = !want;
      f += run;
    }
  }
  return enc.finish();
}

}  // namespace capz
