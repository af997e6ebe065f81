// The coders of the POSW walks, for positions.cpp and positions_ray.cpp (the walks of streams
// that may hold predictor 10, in a translation unit of their own: see walk_window_ray in
// predict.h). Internal to the position coder.
#pragma once

#include <cstddef>
#include <cstdint>

#include "coding/entropy.h"
#include "coding/predict.h"

namespace capz {

// The coders of the final walks hold the entropy coder's cursor by value (entropy.h): walk_window
// works on a local copy of its Coder, so the coder state stays in registers; commit it after.
// In an unnamed namespace on purpose: each including file has its own, with internal linkage,
// which the compiler inlines into its walks' hot loop (as one with external linkage, called
// from two files, it is not).
namespace {

struct EncCoder {
  IntEncoder::Cursor enc;
  ResidualContexts::Cursor contexts;
  const int32_t* q;
  const uint32_t* lo;
  RayKind ray = RayKind::kNone;  // how predictor 10 reads the integers (walk_window_ray only)
  int32_t operator()(size_t i, int32_t pred, int ctx, int* tok) {
    *tok = enc.put_signed(wrap_sub(q[i], pred), ctx, contexts.escape_set(ctx));
    if (lo) enc.raw_bits(lo[i], 32);
    return q[i];
  }
};

struct DecCoder {
  IntDecoder::Cursor dec;
  ResidualContexts::Cursor contexts;
  uint32_t* lo;
  RayKind ray = RayKind::kNone;  // as EncCoder's
  int32_t operator()(size_t i, int32_t pred, int ctx, int* tok) {
    int32_t r = dec.get_signed(ctx, tok, contexts.escape_set(ctx));
    if (lo) lo[i] = dec.raw_bits(32);
    return wrap_add(pred, r);
  }
};

}  // namespace

// The walks of a scheme-3 stream that may hold predictor 10 (positions_ray.cpp): code q (every
// valid sample's residual, gaps filled) into enc, or decode it from dec, predictor 10 reading
// the integers as `ray` says (FORMAT.md 8.3); mode 3 never has it, so there are no low words.
void encode_walk_ray(size_t frames, size_t points, const uint8_t* valid, const uint8_t* modes,
                     const uint32_t* ref, const int32_t* t, int32_t* q, ResidualContexts& contexts,
                     IntEncoder& enc, size_t period, RayKind ray);
void decode_walk_ray(size_t frames, size_t points, const uint8_t* valid, const uint8_t* modes,
                     const uint32_t* ref, const int32_t* t, int32_t* q, ResidualContexts& contexts,
                     IntDecoder& dec, size_t period, RayKind ray);

}  // namespace capz
