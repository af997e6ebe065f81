#include "coding/analog/analog_entropy.h"

namespace capz {
namespace analog {

int64_t get_float_residual9(IntDecoder::Cursor* dec, int* prev_nb) {
  int tok;
  const int sym = dec->get_symbol(kMagContexts + std::min(*prev_nb, 32));
  int64_t nb = *prev_nb + sym - 7;
  if (sym == 0) nb = *prev_nb - 7 - static_cast<int64_t>(dec->get(kFarContext, &tok));
  if (sym == 15) nb = *prev_nb + 8 + static_cast<int64_t>(dec->get(kFarContext, &tok));
  if (nb < 0 || nb > 64) dec->corrupt("float residual bit length outside 0..64");
  *prev_nb = static_cast<int>(nb);
  if (nb < 2) return unzigzag64(nb);
  const int below = static_cast<int>(nb) - 1, k = below < 4 ? below : 4, n = below - k;
  const int s = dec->get_symbol(kTopContext + static_cast<int>(nb) - 2);
  if (s >> k) dec->corrupt("float residual's top bits out of range");
  const uint64_t u = (uint64_t{1} << below) | (static_cast<uint64_t>(s) << n);
  return unzigzag64(n > 0 ? u | get_raw64(dec, n) : u);
}

}  // namespace analog
}  // namespace capz
