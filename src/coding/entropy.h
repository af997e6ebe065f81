// Integer entropy coding on top of the range coder (docs/FORMAT.md 1.3).
//
// A value is split into a "hybrid token" (an adaptive 64-symbol model picks it, under a context
// chosen by the caller) and raw low bits, so small values cost one model step and large ones
// cost one model step plus a raw field: never one binary decision per bit.
//
//   IntEncoder enc(16);            // 16 contexts
//   enc.put_signed(v, ctx);        // ctx in [0, 16)
//   std::vector<uint8_t> block = enc.finish();
//   IntDecoder dec(block.data(), block.size(), 16, "chunk POSW");
//   int32_t v = dec.get_signed(ctx);
#pragma once

#include <cstdint>
#include <string>
#include <vector>

#include "coding/range_coder.h"

namespace capz {

// Token of an unsigned value: u < 4 -> u; else 4 + 2 * (e - 2) + (bit e-1 of u), e = floor(log2 u).
inline int token_of(uint32_t u, int* extra_bits) {
  if (u < 4) {
    *extra_bits = 0;
    return static_cast<int>(u);
  }
  int e = 31 - __builtin_clz(u);
  *extra_bits = e - 1;
  return 4 + 2 * (e - 2) + static_cast<int>((u >> (e - 1)) & 1);
}
inline uint32_t zigzag(int32_t v) {
  return (static_cast<uint32_t>(v) << 1) ^ static_cast<uint32_t>(v >> 31);
}
inline int32_t unzigzag(uint32_t u) {
  return static_cast<int32_t>((u >> 1) ^ (0u - (u & 1)));
}

class IntEncoder {
 public:
  explicit IntEncoder(int contexts = 1) : models_(static_cast<size_t>(contexts)) {}
  void put(uint32_t u, int ctx) {
    int nbits;
    int tok = token_of(u, &nbits);
    models_[static_cast<size_t>(ctx)].encode(&rc_, tok);
    if (nbits) rc_.raw_bits(u & ((1u << nbits) - 1), nbits);
  }
  void put_signed(int32_t v, int ctx) { put(zigzag(v), ctx); }
  // Returns the token the value used (callers derive the next context from it).
  int put_signed_tok(int32_t v, int ctx) {
    uint32_t u = zigzag(v);
    int nbits;
    int tok = token_of(u, &nbits);
    models_[static_cast<size_t>(ctx)].encode(&rc_, tok);
    if (nbits) rc_.raw_bits(u & ((1u << nbits) - 1), nbits);
    return tok;
  }
  std::vector<uint8_t> finish() { return rc_.finish(); }
  RangeEncoder* coder() { return &rc_; }

 private:
  RangeEncoder rc_;
  std::vector<SymbolModel> models_;
};

class IntDecoder {
 public:
  IntDecoder(const uint8_t* data, size_t size, int contexts, std::string what)
      : rc_(data, size, std::move(what)), models_(static_cast<size_t>(contexts)) {}
  uint32_t get(int ctx) {
    int tok;
    return get_tok(ctx, &tok);
  }
  int32_t get_signed(int ctx) { return unzigzag(get(ctx)); }
  uint32_t get_tok(int ctx, int* tok_out) {
    int tok = models_[static_cast<size_t>(ctx)].decode(&rc_);
    *tok_out = tok;
    if (tok < 4) return static_cast<uint32_t>(tok);
    int e = (tok - 4) / 2 + 2;
    uint32_t top = (2u | static_cast<uint32_t>(tok & 1)) << (e - 1);
    return top | rc_.raw_bits(e - 1);
  }
  int32_t get_signed_tok(int ctx, int* tok) { return unzigzag(get_tok(ctx, tok)); }
  bool at_end() const { return rc_.at_end(); }
  RangeDecoder* coder() { return &rc_; }

 private:
  RangeDecoder rc_;
  std::vector<SymbolModel> models_;
};

// Generic integer streams (16 contexts from the previous token; FORMAT.md 1.3).
constexpr int kIntStreamContexts = 16;
constexpr size_t kMaxSymbolsPerByte = 2900;
std::vector<uint8_t> encode_ints(const std::vector<int32_t>& values);
std::vector<uint8_t> encode_uints(const std::vector<uint32_t>& values);
// Decodes exactly `count` values; throws Error(kCorrupt) naming `what` if the block is truncated,
// inconsistent, or has bytes left over. A symbol costs at least -log2(1 - 63/2^15) > 1/360 bit,
// so count <= kMaxSymbolsPerByte * size is enforced before allocating.
std::vector<int32_t> decode_ints(const uint8_t* data, size_t size, size_t count,
                                 const std::string& what = "integer stream");
std::vector<uint32_t> decode_uints(const uint8_t* data, size_t size, size_t count,
                                   const std::string& what = "integer stream");

}  // namespace capz
