// MASK's decoder (docs/FORMAT.md 9); the encoder is mask_encode.cpp.
#include "coding/mask.h"

#include "capz/error.h"
#include "coding/entropy.h"

namespace capz {

void decode_mask(const uint8_t* data, size_t size, size_t frames, size_t points, uint8_t* valid,
                 const std::string& what) {
  IntDecoder dec(data, size, 3, what);
  for (size_t p = 0; p < points; ++p) {
    size_t f = 0;
    bool first = true;
    bool want = true;
    while (f < frames) {
      uint32_t run = dec.get(first ? 0 : want ? 2 : 1);
      if (run > frames - f || (run == 0 && !first))
        fail(ErrorCode::kCorrupt, what,
             "gap-mask run of " + std::to_string(run) + " frames does not fit the window");
      for (size_t k = 0; k < run; ++k) valid[(f + k) * points + p] = want ? 1 : 0;
      f += run;
      first = false;
      want = !want;
    }
  }
  if (!dec.at_end()) fail(ErrorCode::kCorrupt, what, "gap-mask block has bytes past its end");
}

}  // namespace capz
