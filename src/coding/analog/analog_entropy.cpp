#include "coding/analog/analog_entropy.h"

namespace capz {
namespace analog {

int64_t get_float_residual(IntDecoder::Cursor* dec, int* prev_nb) {
  int tok;
  const uint32_t nb = dec->get(kMagContexts + *prev_nb / 2, &tok);
  if (nb > 64) dec->corrupt("float residual longer than 64 bits");
  *prev_nb = static_cast<int>(nb);
  if (nb < 2) return unzigzag64(nb);
  const int n = static_cast<int>(nb) - 1;
  uint64_t u = uint64_t{1} << n;
  if (n < 32) {
    u |= dec->raw_bits(n);
  } else {
    u |= dec->raw_bits(32);
    u |= static_cast<uint64_t>(dec->raw_bits(n - 32)) << 32;
  }
  return unzigzag64(u);
}

}  // namespace analog
}  // namespace capz
