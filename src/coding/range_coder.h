// Adaptive range coder: the entropy stage every capz stream ends in (docs/FORMAT.md section 1).
//
// RangeEncoder/RangeDecoder code intervals of a fixed total 2^15 (kTotalBits) and raw bit fields.
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
  // n raw bits of v (0 <= n <= 32).
  void raw_bits(uint32_t v, int n) {
    while (n > 16) {
      raw16(v & 0xFFFF, 16);
      v >>= 16;
      n -= 16;
    }
    if (n > 0) raw16(v, n);
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
  void raw16(uint32_t v, int n) {
    range_ >>= n;
    low_ += static_cast<uint64_t>(range_) * v;
    normalize();
  }
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

  // Scaled target for an interval decode: returns r and leaves the caller to find the symbol s
  // with r * cum(s) <= code < r * cum(s + 1); then call consume(r, start, freq).
  uint32_t begin(uint32_t* code) {
    uint32_t r = range_ >> kTotalBits;
    if (code_ >= r * kTotal) corrupt("entropy-coded value out of range");
    *code = code_;
    return r;
  }
  void consume(uint32_t r, uint32_t start, uint32_t freq) {
    code_ -= r * start;
    range_ = r * freq;
    normalize();
  }
  uint32_t raw_bits(int n) {
    uint32_t v = 0;
    int shift = 0;
    while (n > 16) {
      v |= raw16(16) << shift;
      shift += 16;
      n -= 16;
    }
    if (n > 0) v |= raw16(n) << shift;
    return v;
  }
  // True when every byte of the block has been consumed (a valid block ends exactly there).
  bool at_end() const { return p_ == end_; }
  [[noreturn]] void corrupt(const char* msg) const {
    throw Error(ErrorCode::kCorrupt, what_ + ": " + msg);
  }

 private:
  uint32_t raw16(int n) {
    range_ >>= n;
    uint32_t v = code_ / range_;
    if (v >> n) corrupt("entropy-coded raw bits out of range");
    code_ -= v * range_;
    normalize();
    return v;
  }
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
  std::string what_;
};

// Adaptive model over n <= 64 symbols (docs/FORMAT.md 1.2). cum(i) = c[i] + i over kTotal.
class SymbolModel {
 public:
  static constexpr int kMaxSymbols = 64;
  explicit SymbolModel(int n = kMaxSymbols) : n_(n) {
    if (n < 2 || n > kMaxSymbols) throw Error(ErrorCode::kInternal, "SymbolModel: bad alphabet size");
    const int t = static_cast<int>(kTotal) - n;
    for (int i = 0; i <= kMaxSymbols; ++i)
      c_[i] = static_cast<int16_t>(i <= n ? static_cast<int>(static_cast<int64_t>(i) * t / n) : t);
  }
  int size() const { return n_; }

  void encode(RangeEncoder* enc, int s) {
    uint32_t lo = static_cast<uint32_t>(c_[s] + s);
    uint32_t hi = static_cast<uint32_t>(c_[s + 1] + s + 1);
    enc->encode(lo, hi - lo);
    update(s);
  }
  int decode(RangeDecoder* dec) {
    uint32_t code;
    uint32_t r = dec->begin(&code);
    // Largest s with r * cum(s) <= code; cum(0) = 0 and code < r * kTotal = r * cum(n).
    int s = 0;
    while (s + 1 < n_ && r * static_cast<uint32_t>(c_[s + 1] + s + 1) <= code) ++s;
    uint32_t lo = static_cast<uint32_t>(c_[s] + s);
    uint32_t hi = static_cast<uint32_t>(c_[s + 1] + s + 1);
    dec->consume(r, lo, hi - lo);
    update(s);
    return s;
  }

 private:
  void update(int s) {
    const int rate = count_ < 16 ? 4 : count_ < 64 ? 5 : count_ < 256 ? 6 : 7;
    if (count_ < 256) ++count_;
    const int16_t t = static_cast<int16_t>(static_cast<int>(kTotal) - n_);
    // Branch-free so the compiler vectorises it; entries past n_ stay at t (target t, no change).
    for (int i = 1; i < kMaxSymbols; ++i) {
      int16_t target = i > s ? t : 0;
      c_[i] = static_cast<int16_t>(c_[i] + ((target - c_[i]) >> rate));
    }
  }

  int n_;
  int count_ = 0;
  alignas(16) int16_t c_[kMaxSymbols + 1];
};

}  // namespace capz
