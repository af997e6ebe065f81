// ATTR's entropy coding (docs/FORMAT.md 13.6): the context map of an attribute's block and how a
// lane's residuals are coded under it. ATTR's own numbering: the analog coder (ANLG, FORMAT.md
// 11.10) shares the primitives of residuals.h, not its contexts.
#pragma once

#include <cstdint>

#include "coding/entropy.h"
#include "coding/residuals.h"

namespace capz {
namespace attr {

// An attribute's block of kContexts contexts, all with the uniform start (FORMAT.md 13.6):
//   0 .. 47   integer residuals, by the lane state's running magnitude (Magnitude::context)
//   48 .. 80  float residuals' bit lengths, by the lane state's previous bit length / 2
//   81, 82    predictor 9's sign, by the sign of the lane's previous completable value
//   83, 84    predictor 13's run counts and misses (a ragged window's)
inline constexpr int kIntContext = 0;
inline constexpr int kIntContexts = kMagnitudeContexts;
inline constexpr int kFloatContext = kIntContext + kIntContexts;
inline constexpr int kFloatContexts = 33;  // previous bit length 0 .. 64, halved
inline constexpr int kSignContext = kFloatContext + kFloatContexts;
inline constexpr int kSignContexts = 2;
inline constexpr int kRunContext = kSignContext + kSignContexts;
inline constexpr int kMissContext = kRunContext + 1;
inline constexpr int kContexts = kMissContext + 1;
static_assert(kFloatContext == 48 && kSignContext == 81 && kRunContext == 83 && kContexts == 85,
              "ATTR's context numbers are part of the format (FORMAT.md 13.6)");

// An integer residual (int32; the zig-zag of |v| < 2^31 fits 32 bits) under the state's
// magnitude context, which it then updates.
inline void put_int_residual(IntEncoder::Cursor* enc, Magnitude* m, int32_t v) {
  const uint32_t u = zigzag(v);
  enc->put(u, kIntContext + m->context());
  m->update(u);
}
inline int32_t get_int_residual(IntDecoder::Cursor* dec, Magnitude* m) {
  int tok;
  const uint32_t u = dec->get(kIntContext + m->context(), &tok);
  m->update(u);
  return unzigzag(u);
}

// A float residual d (the wrapping difference of two ordered bit patterns, as int64): its bit
// length nb = 0..64 of zigzag64(d) under context kFloatContext + prev_nb / 2, then the nb - 1
// bits below the leading one, raw (low 32 first when 32 or more). *prev_nb is updated.
inline void put_float_residual(IntEncoder::Cursor* enc, int* prev_nb, int64_t d) {
  const uint64_t u = zigzag64(d);
  const int nb = u == 0 ? 0 : 64 - __builtin_clzll(u);
  enc->put(static_cast<uint32_t>(nb), kFloatContext + *prev_nb / 2);
  *prev_nb = nb;
  if (nb < 2) return;
  put_raw64(enc, u, nb - 1);
}
inline int64_t get_float_residual(IntDecoder::Cursor* dec, int* prev_nb) {
  int tok;
  const uint32_t nb = dec->get(kFloatContext + *prev_nb / 2, &tok);
  if (nb > 64) dec->corrupt("float residual longer than 64 bits");
  *prev_nb = static_cast<int>(nb);
  if (nb < 2) return unzigzag64(nb);
  const int n = static_cast<int>(nb) - 1;
  return unzigzag64((uint64_t{1} << n) | get_raw64(dec, n));
}

}  // namespace attr
}  // namespace capz
