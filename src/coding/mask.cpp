// Decoder library (capz_decode): builds without PCL and without the transform encoders.
#include "coding/mask.h"

#include "capz/error.h"
#include "coding/entropy.h"

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
