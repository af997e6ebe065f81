// Integer entropy coding on top of the range coder (docs/FORMAT.md 2.4).
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
// The least value of token tok (0..63), and in *extra_bits the bits below it: token_of's inverse.
inline uint32_t token_floor(int tok, int* extra_bits) {
  if (tok < 4) {
    *extra_bits = 0;
    return static_cast<uint32_t>(tok);
  }
  const int e = (tok - 4) / 2 + 2;
  *extra_bits = e - 1;
  return (2u | static_cast<uint32_t>(tok & 1)) << (e - 1);
}
inline uint32_t zigzag(int32_t v) {
  return (static_cast<uint32_t>(v) << 1) ^ static_cast<uint32_t>(v >> 31);
}
inline int32_t unzigzag(uint32_t u) {
  return static_cast<int32_t>((u >> 1) ^ (0u - (u & 1)));
}
// Bit length of zigzag(r) (0 for r = 0): encoders' quick estimate of a residual's cost.
inline uint32_t bit_cost(int32_t r) {
  const uint32_t u = zigzag(r);
  // Without a branch (zero and nonzero residuals alternate unpredictably): clz(u | 1) is
  // defined for every u, and the mask zeroes the result for u = 0.
  return (33u - static_cast<uint32_t>(__builtin_clz(u | 1))) & (0u - (u != 0));
}

// Tokens 0..63 go through up to five 16-symbol models: the context's own model codes
// min(token, 15); 15 escapes to shared model k (k = 0..3), which codes min(token - 15 (k + 1), 15).
constexpr int kEscapeLevels = 4;
// Sets of escape models a block may choose between per value (set 0 is the only one most
// streams use; position residuals of format 2.x choose by context, FORMAT.md 8.4).
constexpr int kEscapeSets = 3;

// Encoder and decoder keep their moving state in a Cursor: a trivially copyable object (coder
// state by value, models and output by pointer). put/get on the IntEncoder/IntDecoder code
// through the one it holds; a hot loop takes a copy (cursor()), codes through it, and stores it
// back (commit()) before the coder is used otherwise. The copy is a local whose address never
// escapes, so the compiler keeps it in registers; the coder object lives in memory, where every
// byte or int the loop stores may alias it and forces reloads (about a third of the decoding
// time of positions, measured on AlbertoREAL.c3d). Both objects point into themselves, hence
// neither copies nor moves.
class IntEncoder {
 public:
  class Cursor {
   public:
    // Codes u under context ctx (0 <= ctx < contexts); returns its token.
    // `eset` picks the set of escape models (0 <= eset < kEscapeSets).
    __attribute__((always_inline)) int put(uint32_t u, int ctx, int eset = 0) {
      int nbits;
      const int tok = put_token(u, ctx, &nbits, eset);
      if (nbits) bits_.put(u & ((1u << nbits) - 1), nbits, bits_out_);
      return tok;
    }
    // As put, but only u's token: the *nbits bits below it are the caller's to code.
    __attribute__((always_inline)) int put_token(uint32_t u, int ctx, int* nbits, int eset = 0) {
      const int tok = token_of(u, nbits);
      if (tok < 15) {
        models_[ctx].encode(this, tok);
      } else {
        models_[ctx].encode(this, 15);
        int rest = tok - 15;
        SymbolModel* escape = escape_ + kEscapeLevels * eset;
        for (int k = 0;; ++k) {
          const int sym = rest < 15 ? rest : 15;
          escape[k].encode(this, sym);
          if (sym < 15) break;
          rest -= 15;
        }
      }
      return tok;
    }
    int put_signed(int32_t v, int ctx, int eset = 0) { return put(zigzag(v), ctx, eset); }
    // FORMAT.md 2.8 (a block with binary models, IntEncoder::add_bit_models): a bit with
    // context ctx's binary model; u zero first (the bit u != 0, then u - 1 if it is 1).
    __attribute__((always_inline)) void put_bit(bool b, int ctx) {
      bit_models_[ctx].encode(this, b);
    }
    __attribute__((always_inline)) void put_zero_first(uint32_t u, int ctx) {
      put_bit(u != 0, ctx);
      if (u != 0) put(u - 1, ctx);
    }
    // One symbol 0..15 with the context's model itself: no token, no escape (FORMAT.md 2.3).
    void put_symbol(int s, int ctx) { models_[ctx].encode(this, s); }
    // n raw bits of v (0 <= n <= 32), uncompressed.
    void raw_bits(uint32_t v, int n) { bits_.put(v, n, bits_out_); }
    // For SymbolModel::encode.
    void encode(uint32_t start, uint32_t freq) { rc_.encode(start, freq, rc_out_); }
    // The block's size if it were finished now, less its varint: finish() would output this
    // many bytes after the varint, and coding more never lowers it (a lower bound of the
    // finished block's size).
    size_t bytes_out() const { return rc_.n + 4 + bits_.n + (bits_.bits > 0); }

   private:
    friend class IntEncoder;
    RangeEncoder::Core rc_;
    BitWriter::Core bits_;
    std::vector<uint8_t>* rc_out_ = nullptr;
    std::vector<uint8_t>* bits_out_ = nullptr;
    SymbolModel* models_ = nullptr;
    SymbolModel* escape_ = nullptr;
    BitModel* bit_models_ = nullptr;
  };

  explicit IntEncoder(int contexts = 1) : models_(static_cast<size_t>(contexts)) {
    cur_.rc_out_ = &rc_out_;
    cur_.bits_out_ = &bits_out_;
    cur_.models_ = models_.data();
    cur_.escape_ = escape_;
  }
  IntEncoder(const IntEncoder&) = delete;
  IntEncoder& operator=(const IntEncoder&) = delete;
  // Starts the context models skewed towards small tokens (SymbolModel::skew).
  void skew_contexts() {
    for (SymbolModel& m : models_) m.skew();
  }
  // Gives every context a binary model too (FORMAT.md 2.8), before anything is coded.
  void add_bit_models() {
    bit_models_.assign(models_.size(), BitModel());
    cur_.bit_models_ = bit_models_.data();
  }
  // Starts context ctx's model on its first m symbols (SymbolModel::restrict).
  void restrict_context(int ctx, int m) { models_[static_cast<size_t>(ctx)].restrict(m); }
  int put(uint32_t u, int ctx, int eset = 0) { return cur_.put(u, ctx, eset); }
  int put_signed(int32_t v, int ctx, int eset = 0) { return cur_.put_signed(v, ctx, eset); }
  void put_symbol(int s, int ctx) { cur_.put_symbol(s, ctx); }
  void put_bit(bool b, int ctx) { cur_.put_bit(b, ctx); }
  void put_zero_first(uint32_t u, int ctx) { cur_.put_zero_first(u, ctx); }
  void raw_bits(uint32_t v, int n) { cur_.raw_bits(v, n); }
  // The range coder's interval [start, start + freq) of kTotal, for a caller's own model.
  void encode(uint32_t start, uint32_t freq) { cur_.encode(start, freq); }
  Cursor cursor() const { return cur_; }
  void commit(const Cursor& c) { cur_ = c; }
  // The block: varint(length of the range-coded part), that part, then the raw bits.
  std::vector<uint8_t> finish();
  // finish()'s size if it were called now (the coder left as it is).
  size_t finished_size() const {
    size_t varint = 1;
    for (size_t v = cur_.rc_.n + 4; v >= 0x80; v >>= 7) ++varint;
    return varint + cur_.bytes_out();
  }

 private:
  std::vector<SymbolModel> models_;
  SymbolModel escape_[kEscapeLevels * kEscapeSets];
  std::vector<BitModel> bit_models_;
  std::vector<uint8_t> rc_out_, bits_out_;
  Cursor cur_;
};

class IntDecoder {
 public:
  class Cursor {
   public:
    // Decodes one value under ctx and stores its token in *tok.
    __attribute__((always_inline)) uint32_t get(int ctx, int* tok_out, int eset = 0) {
      const int tok = get_token(ctx, eset);
      *tok_out = tok;
      int nbits;
      const uint32_t top = token_floor(tok, &nbits);
      return nbits ? top | raw_bits(nbits) : top;
    }
    // The token put_token coded (0..63).
    __attribute__((always_inline)) int get_token(int ctx, int eset = 0) {
      int tok = models_[ctx].decode(this);
      if (tok == 15) {
        SymbolModel* escape = escape_ + kEscapeLevels * eset;
        for (int k = 0;; ++k) {
          if (k == kEscapeLevels) corrupt("entropy-coded token out of range");
          const int sym = escape[k].decode(this);
          tok += sym;
          if (sym < 15) break;
        }
        if (tok > 63) corrupt("entropy-coded token out of range");
      }
      return tok;
    }
    uint32_t raw_bits(int n) {
      uint32_t v;
      if (!bits_.get(n, &v)) corrupt("raw bits of an entropy-coded block are truncated");
      return v;
    }
    __attribute__((always_inline)) int32_t get_signed(int ctx, int* tok, int eset = 0) {
      return unzigzag(get(ctx, tok, eset));
    }
    // FORMAT.md 2.8 (a block with binary models, IntDecoder::add_bit_models): a bit; a value
    // zero first.
    __attribute__((always_inline)) bool get_bit(int ctx) {
      return bit_models_[ctx].decode(&rc_, *what_);
    }
    __attribute__((always_inline)) uint32_t get_zero_first(int ctx) {
      if (!get_bit(ctx)) return 0;
      int tok;
      const uint32_t v = get(ctx, &tok);
      if (__builtin_expect(v == 0xFFFFFFFFu, 0)) corrupt("zero-first value out of range");
      return v + 1;
    }
    // The symbol put_symbol coded.
    int get_symbol(int ctx) { return models_[ctx].decode(this); }
    // For SymbolModel::decode.
    uint32_t target() { return rc_.target(*what_); }
    void consume(uint32_t start, uint32_t freq) { rc_.consume(start, freq, *what_); }
    [[noreturn]] void corrupt(const char* msg) const { throw_corrupt(*what_, msg); }

   private:
    friend class IntDecoder;
    RangeDecoder::Core rc_;
    BitReader bits_;
    SymbolModel* models_ = nullptr;
    SymbolModel* escape_ = nullptr;
    BitModel* bit_models_ = nullptr;
    const std::string* what_ = nullptr;
  };

  IntDecoder(const uint8_t* data, size_t size, int contexts, const std::string& what);
  IntDecoder(const IntDecoder&) = delete;
  IntDecoder& operator=(const IntDecoder&) = delete;
  uint32_t get(int ctx, int* tok_out, int eset = 0) { return cur_.get(ctx, tok_out, eset); }
  uint32_t raw_bits(int n) { return cur_.raw_bits(n); }
  uint32_t get(int ctx) {
    int tok;
    return get(ctx, &tok);
  }
  int32_t get_signed(int ctx, int* tok, int eset = 0) { return cur_.get_signed(ctx, tok, eset); }
  int32_t get_signed(int ctx) { return unzigzag(get(ctx)); }
  int get_symbol(int ctx) { return cur_.get_symbol(ctx); }
  // For a caller's own model: the target in [0, kTotal), then the interval it lies in.
  uint32_t target() { return cur_.target(); }
  void consume(uint32_t start, uint32_t freq) { cur_.consume(start, freq); }
  // True when both parts of the block were consumed exactly (a valid block ends there).
  bool at_end() const { return cur_.rc_.p == cur_.rc_.end && cur_.bits_.at_valid_end(); }
  [[noreturn]] void corrupt(const char* msg) const { cur_.corrupt(msg); }
  void skew_contexts() {
    for (SymbolModel& m : models_) m.skew();
  }
  // Gives every context a binary model too (FORMAT.md 2.8), before anything is decoded.
  void add_bit_models() {
    bit_models_.assign(models_.size(), BitModel());
    cur_.bit_models_ = bit_models_.data();
  }
  void restrict_context(int ctx, int m) { models_[static_cast<size_t>(ctx)].restrict(m); }
  Cursor cursor() const { return cur_; }
  void commit(const Cursor& c) { cur_ = c; }

 private:
  std::string what_;
  std::vector<SymbolModel> models_;
  SymbolModel escape_[kEscapeLevels * kEscapeSets];
  std::vector<BitModel> bit_models_;
  Cursor cur_;
};

// Generic integer streams (16 contexts from the previous token; FORMAT.md 2.4).
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

// Byte strings (text-like metadata, FORMAT.md 2.5): each byte as two nibbles, the high one under
// the context of the previous two bytes' high nibbles, the low one under the context of its high
// nibble and the previous byte's high nibble.
std::vector<uint8_t> encode_bytes(const uint8_t* data, size_t size);
// Decodes exactly `count` bytes (count <= kMaxSymbolsPerByte / 2 * size is enforced).
std::vector<uint8_t> decode_bytes(const uint8_t* data, size_t size, size_t count,
                                  const std::string& what);

}  // namespace capz
