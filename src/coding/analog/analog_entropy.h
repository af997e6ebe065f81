// Analog residual entropy stage (docs/format-drafts/analog.md section A.5).
//
// Every coded number of an analog window goes through one IntEncoder (entropy.h) whose contexts
// are laid out here:
//   - integer residuals (int32) under a context from the running mean of recent magnitudes
//     (kMagContexts contexts), as adaptive Rice coders pick their parameter;
//   - float residuals (wrapping differences of ordered float bits, up to 64 bits) as a bit
//     length under a context from the previous bit length, then the bits below the leading one
//     raw (fpzip's scheme);
//   - side information (LPC orders, coefficients, stage flags) under two parameter contexts.
#pragma once

#include <algorithm>
#include <cstdint>

#include "coding/entropy.h"
#include "coding/residuals.h"

namespace capz {
namespace analog {

// The primitives residuals.h holds for ANLG and ATTR, under their names of the analog coder.
using capz::Magnitude;
using capz::put_raw64;
using capz::unzigzag64;
using capz::zigzag64;

constexpr int kMagContexts = kMagnitudeContexts;
constexpr int kFloatContexts = 33;
constexpr int kParamContext = kMagContexts + kFloatContexts;
constexpr int kCoefContext = kParamContext + 1;
// FORMAT.md 11.10: the 4 bits below a float residual's leading bit, by its bit length 2..64.
constexpr int kTopContext = kCoefContext + 1;
constexpr int kTopContexts = 63;
// FORMAT.md 11.10: a bit length far from the previous one.
constexpr int kFarContext = kTopContext + kTopContexts;
// FORMAT.md 11.10: the two bits below an integer residual's token t (4..63), by t.
constexpr int kLowContext = kFarContext + 1;
constexpr int kLowContexts = 60;
// FORMAT.md 11.10 (a version 2 window): a token far below its magnitude context c, by c; one far
// above it, for every context.
constexpr int kBelowContext = kLowContext + kLowContexts;
constexpr int kAboveContext = kBelowContext + kMagContexts;
constexpr int kAnalogContexts = kAboveContext + 1;
// FORMAT.md 11.10: a version 2 window's token t under magnitude context c is d = t - c + kRelShift;
// its context's model codes d in 1 .. 14 itself.
constexpr int kRelShift = 14;

// FORMAT.md 9.5: an analog window's coder starts each low-bit model on the symbols it can code
// (2 after tokens 4 and 5, whose values have one bit below the token; 4 after the others).
template <typename Coder>
void start_low_bit_models(Coder* c) {
  for (int t = 4; t < 64; ++t) c->restrict_context(kLowContext + t - 4, t < 6 ? 2 : 4);
}
// FORMAT.md 9.5: the (up to) two bits below token tok of u as one
// symbol under context kLowContext + tok - 4, then only the bits below them raw.
inline void put_low_bits(IntEncoder::Cursor* enc, uint32_t u, int tok, int nbits) {
  if (nbits) {
    const int k = nbits < 2 ? nbits : 2, r = nbits - k;
    enc->put_symbol(static_cast<int>((u >> r) & ((1u << k) - 1)), kLowContext + tok - 4);
    if (r) enc->raw_bits(u & ((1u << r) - 1), r);
  }
}
inline uint32_t get_low_bits(IntDecoder::Cursor* dec, int tok) {
  int nbits;
  uint32_t u = token_floor(tok, &nbits);
  if (nbits) {
    const int k = nbits < 2 ? nbits : 2, r = nbits - k;
    const int s = dec->get_symbol(kLowContext + tok - 4);
    if (s >= (1 << k)) dec->corrupt("analog residual's low-bit symbol out of range");
    u |= static_cast<uint32_t>(s) << r;
    if (r) u |= dec->raw_bits(r);
  }
  return u;
}
// FORMAT.md 9.7 (an analog window's integer residual): its token relative to the magnitude
// context, then the bits below it as put_low_bits codes them: d = t - c + kRelShift, symbol d (1 ..
// 14) under context c itself, or symbol 0 and -d under kBelowContext + c, or symbol 15 and d - 15
// under kAboveContext.
inline void put_residual_v2(IntEncoder::Cursor* enc, Magnitude* m, int32_t v) {
  const uint32_t u = zigzag(v);
  const int c = m->context();
  int nbits;
  const int tok = token_of(u, &nbits);
  const int d = tok - c + kRelShift;
  if (d <= 0) {
    enc->put_symbol(0, c);
    enc->put(static_cast<uint32_t>(-d), kBelowContext + c);
  } else if (d < 15) {
    enc->put_symbol(d, c);
  } else {
    enc->put_symbol(15, c);
    enc->put(static_cast<uint32_t>(d - 15), kAboveContext);
  }
  put_low_bits(enc, u, tok, nbits);
  m->update(u);
}
inline int32_t get_residual_v2(IntDecoder::Cursor* dec, Magnitude* m) {
  const int c = m->context();
  const int s = dec->get_symbol(c);
  int tok_unused;
  int64_t d = s;
  if (s == 0)
    d = -static_cast<int64_t>(dec->get(kBelowContext + c, &tok_unused));
  else if (s == 15)
    d = 15 + static_cast<int64_t>(dec->get(kAboveContext, &tok_unused));
  const int64_t tok = d + c - kRelShift;
  if (tok < 0 || tok > 63) dec->corrupt("analog residual token out of range");
  const uint32_t u = get_low_bits(dec, static_cast<int>(tok));
  m->update(u);
  return unzigzag(u);
}

// FORMAT.md 11.10: a float residual d (the wrapping difference of two ordered bit patterns, as
// int64): the bit length nb of zigzag64(d) relative to the previous one, as a symbol under
// context kMagContexts + min(prev_nb, 32) (or an escape and how far beyond, under kFarContext);
// then the (up to) 4 bits below the leading one as one symbol under context
// kTopContext + nb - 2, and only the bits below them raw. *prev_nb is updated.
inline void put_float_residual9(IntEncoder::Cursor* enc, int* prev_nb, int64_t d) {
  const uint64_t u = zigzag64(d);
  const int nb = u == 0 ? 0 : 64 - __builtin_clzll(u);
  // The bit length as one symbol nb - prev + 7 when that is 1..14, else an escape (0: below,
  // 15: above) and how far beyond, as an integer.
  const int delta = nb - *prev_nb;
  if (delta < -6) {
    enc->put_symbol(0, kMagContexts + std::min(*prev_nb, 32));
    enc->put(static_cast<uint32_t>(-7 - delta), kFarContext);
  } else if (delta > 7) {
    enc->put_symbol(15, kMagContexts + std::min(*prev_nb, 32));
    enc->put(static_cast<uint32_t>(delta - 8), kFarContext);
  } else {
    enc->put_symbol(delta + 7, kMagContexts + std::min(*prev_nb, 32));
  }
  *prev_nb = nb;
  if (nb < 2) return;
  const int below = nb - 1, k = below < 4 ? below : 4, n = below - k;
  enc->put_symbol(static_cast<int>((u >> n) & ((1u << k) - 1)), kTopContext + nb - 2);
  if (n > 0) put_raw64(enc, u, n);
}
int64_t get_float_residual9(IntDecoder::Cursor* dec, int* prev_nb);

}  // namespace analog
}  // namespace capz
