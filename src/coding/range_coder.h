// Adaptive range coder: the entropy stage every capz stream ends in (docs/FORMAT.md section 1).
//
// RangeEncoder/RangeDecoder code intervals of a fixed total 2^15 (kTotalBits).
// SymbolModel is an adaptive cumulative-frequency table over up to 64 symbols; every symbol keeps
// a frequency >= 1, so any symbol can always be coded. Header-only: the hot loops inline.
//
// Decoder contract: it never reads past its buffer; a block that ends early or decodes to an
// impossible interval throws Error(kCorrupt) naming `what`.
#pragma once

#include <cstdint>
#include <cstring>
#include <string>
#include <vector>

#if defined(__SSE2__)
#include <emmintrin.h>
#endif

#include "capz/error.h"

namespace capz {

constexpr int kTotalBits = 15;
constexpr uint32_t kTotal = 1u << kTotalBits;
constexpr uint32_t kTopValue = 1u << 24;

class RangeEncoder {
 public:
  // Codes [start, start + freq) of kTotal. Precondition: freq >= 1, start + freq <= kTotal.
  void encode(uint32_t start, uint32_t freq) {
    uint32_t r = range_ >> kTotalBits;
    low_ += static_cast<uint64_t>(r) * start;
    range_ = r * freq;
    normalize();
  }
  // Flushes and returns the block; the encoder is reset afterwards.
  std::vector<uint8_t> finish() {
    for (int i = 0; i < 5; ++i) shift_low();
    std::vector<uint8_t> out;
    out.swap(out_);
    low_ = 0;
    range_ = 0xFFFFFFFFu;
    cache_ = 0;
    pending_ = 1;
    return out;
  }
  size_t bytes_so_far() const { return out_.size() + pending_ + 4; }

 private:
  void normalize() {
    while (range_ < kTopValue) {
      range_ <<= 8;
      shift_low();
    }
  }
  void shift_low() {
    if (static_cast<uint32_t>(low_) < 0xFF000000u || (low_ >> 32) != 0) {
      uint8_t carry = static_cast<uint8_t>(low_ >> 32);
      uint8_t temp = cache_;
      do {
        out_.push_back(static_cast<uint8_t>(temp + carry));
        temp = 0xFF;
      } while (--pending_ != 0);
      cache_ = static_cast<uint8_t>(static_cast<uint32_t>(low_) >> 24);
    }
    ++pending_;
    low_ = static_cast<uint32_t>(static_cast<uint32_t>(low_) << 8);
  }

  uint64_t low_ = 0;
  uint32_t range_ = 0xFFFFFFFFu;
  uint8_t cache_ = 0;
  uint64_t pending_ = 1;
  std::vector<uint8_t> out_;
};

class RangeDecoder {
 public:
  RangeDecoder(const uint8_t* data, size_t size, std::string what)
      : p_(data), end_(data + size), what_(std::move(what)) {
    if (next_byte() != 0) corrupt("entropy-coded block does not start with 0");
    for (int i = 0; i < 4; ++i) code_ = (code_ << 8) | next_byte();
  }

  // First half of an interval decode: returns the cumulative target v in [0, kTotal); the caller
  // finds the symbol s with cum(s) <= v < cum(s + 1), then calls consume(start, freq).
  uint32_t target() {
    r_ = range_ >> kTotalBits;
    uint32_t v = code_ / r_;
    if (v >= kTotal) corrupt("entropy-coded value out of range");
    return v;
  }
  void consume(uint32_t start, uint32_t freq) {
    code_ -= r_ * start;
    range_ = r_ * freq;
    normalize();
  }
  // True when every byte of the block has been consumed (a valid block ends exactly there).
  bool at_end() const { return p_ == end_; }
  [[noreturn]] void corrupt(const char* msg) const {
    throw Error(ErrorCode::kCorrupt, what_ + ": " + msg);
  }

 private:
  uint8_t next_byte() {
    if (p_ == end_) corrupt("entropy-coded block is truncated");
    return *p_++;
  }
  void normalize() {
    while (range_ < kTopValue) {
      range_ <<= 8;
      code_ = (code_ << 8) | next_byte();
    }
  }

  const uint8_t* p_;
  const uint8_t* end_;
  uint32_t code_ = 0;
  uint32_t range_ = 0xFFFFFFFFu;
  uint32_t r_ = 0;
  std::string what_;
};

// Raw bit fields travel beside the range-coded bytes (docs/FORMAT.md 1.3): packed LSB first.
class BitWriter {
 public:
  // n low bits of v, 0 <= n <= 32.
  void put(uint32_t v, int n) {
    acc_ |= static_cast<uint64_t>(v) << bits_;
    bits_ += n;
    while (bits_ >= 8) {
      out_.push_back(static_cast<uint8_t>(acc_));
      acc_ >>= 8;
      bits_ -= 8;
    }
  }
  // Pads the last byte with zero bits and returns the bytes; the writer is reset.
  std::vector<uint8_t> finish() {
    if (bits_ > 0) out_.push_back(static_cast<uint8_t>(acc_));
    acc_ = 0;
    bits_ = 0;
    std::vector<uint8_t> out;
    out.swap(out_);
    return out;
  }

 private:
  uint64_t acc_ = 0;
  int bits_ = 0;
  std::vector<uint8_t> out_;
};

class BitReader {
 public:
  BitReader(const uint8_t* data, size_t size) : p_(data), end_(data + size) {}
  // n bits, 0 <= n <= 32; returns false (value unspecified) when the bytes run out.
  bool get(int n, uint32_t* v) {
    if (bits_ < n) {
      while (bits_ <= 56 && p_ != end_) {
        acc_ |= static_cast<uint64_t>(*p_++) << bits_;
        bits_ += 8;
      }
      if (bits_ < n) return false;
    }
    *v = static_cast<uint32_t>(acc_ & ((uint64_t{1} << n) - 1));
    acc_ >>= n;
    bits_ -= n;
    return true;
  }
  // A valid stream ends with fewer than 8 padding bits, all zero.
  bool at_valid_end() const { return p_ == end_ && bits_ < 8 && acc_ == 0; }

 private:
  const uint8_t* p_;
  const uint8_t* end_;
  uint64_t acc_ = 0;
  int bits_ = 0;
};

// Adaptive model over 16 symbols (docs/FORMAT.md 1.2): cum(i) = c[i] + i over kTotal, so every
// symbol keeps a frequency >= 1. Alphabets of n < 16 symbols simply never code the top ones.
class SymbolModel {
 public:
  static constexpr int kSymbols = 16;
  static constexpr int16_t kT = static_cast<int16_t>(kTotal - kSymbols);
  SymbolModel() {
    for (int i = 0; i < kSymbols; ++i) c_[i] = static_cast<int16_t>(i * kT / kSymbols);
    c_[kSymbols] = kT;
  }
  // Skewed start (FORMAT.md 1.2): c[i] = T - floor(T / 2^i), symbol i has about 2^-(i+1).
  void skew() {
    for (int i = 1; i < kSymbols; ++i) c_[i] = static_cast<int16_t>(kT - (kT >> i));
  }

  void encode(RangeEncoder* enc, int s) {
    uint32_t lo = static_cast<uint32_t>(c_[s] + s);
    uint32_t hi = static_cast<uint32_t>(c_[s + 1] + s + 1);
    enc->encode(lo, hi - lo);
    update(s);
  }
  int decode(RangeDecoder* dec) {
    const int v = static_cast<int>(dec->target());
    const int s = find(v);
    uint32_t lo = static_cast<uint32_t>(c_[s] + s);
    uint32_t hi = static_cast<uint32_t>(c_[s + 1] + s + 1);
    dec->consume(lo, hi - lo);
    update(s);
    return s;
  }

 private:
  int rate() {
    const int r = count_ < 16 ? 4 : count_ < 64 ? 5 : count_ < 256 ? 6 : 7;
    if (count_ < 256) ++count_;
    return r;
  }
#if defined(__SSE2__)
  // s = (number of i in [0, 16) with cum(i) <= v) - 1; cum(0) = 0 <= v always.
  int find(int v) const {
    const __m128i idx0 = _mm_setr_epi16(0, 1, 2, 3, 4, 5, 6, 7);
    const __m128i idx1 = _mm_setr_epi16(8, 9, 10, 11, 12, 13, 14, 15);
    const __m128i vv = _mm_set1_epi16(static_cast<int16_t>(v));
    __m128i a = _mm_add_epi16(_mm_load_si128(reinterpret_cast<const __m128i*>(c_)), idx0);
    __m128i b = _mm_add_epi16(_mm_load_si128(reinterpret_cast<const __m128i*>(c_ + 8)), idx1);
    // cum is non-decreasing, so the lanes with cum > v form a suffix: s = its start - 1.
    int gt = _mm_movemask_epi8(_mm_packs_epi16(_mm_cmpgt_epi16(a, vv), _mm_cmpgt_epi16(b, vv)));
    return gt ? __builtin_ctz(static_cast<unsigned>(gt)) - 1 : 15;
  }
  void update(int s) {
    const __m128i r = _mm_cvtsi32_si128(rate());
    const __m128i idx0 = _mm_setr_epi16(0, 1, 2, 3, 4, 5, 6, 7);
    const __m128i idx1 = _mm_setr_epi16(8, 9, 10, 11, 12, 13, 14, 15);
    const __m128i ss = _mm_set1_epi16(static_cast<int16_t>(s));
    const __m128i t = _mm_set1_epi16(kT);
    __m128i* p = reinterpret_cast<__m128i*>(c_);
    __m128i a = _mm_load_si128(p), b = _mm_load_si128(p + 1);
    __m128i ta = _mm_and_si128(_mm_cmpgt_epi16(idx0, ss), t);  // i > s ? T : 0
    __m128i tb = _mm_and_si128(_mm_cmpgt_epi16(idx1, ss), t);
    a = _mm_add_epi16(a, _mm_sra_epi16(_mm_sub_epi16(ta, a), r));
    b = _mm_add_epi16(b, _mm_sra_epi16(_mm_sub_epi16(tb, b), r));
    _mm_store_si128(p, a);  // c[0] stays 0: its target is 0
    _mm_store_si128(p + 1, b);
  }
#else
  int find(int v) const {
    int n = 0;
    for (int i = 1; i < kSymbols; ++i) n += (c_[i] + i <= v);
    return n;
  }
  void update(int s) {
    const int r = rate();
    for (int i = 1; i < kSymbols; ++i) {
      int target = i > s ? kT : 0;
      c_[i] = static_cast<int16_t>(c_[i] + ((target - c_[i]) >> r));
    }
  }
#endif

  int count_ = 0;
  alignas(16) int16_t c_[kSymbols + 8];  // c_[16] = T; the rest is padding
};

}  // namespace capz
