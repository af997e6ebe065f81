// Adaptive range coder: the entropy stage every capz stream ends in (docs/FORMAT.md section 2).
//
// RangeEncoder/RangeDecoder code intervals of a fixed total 2^15 (kTotalBits).
// SymbolModel is an adaptive cumulative-frequency table over up to 64 symbols; every symbol keeps
// a frequency >= 1, so any symbol can always be coded. Header-only: the hot loops inline.
//
// Decoder contract: it never reads past its buffer; a block that ends early or decodes to an
// impossible interval throws Error(kCorrupt) naming `what`.
#pragma once

#include <algorithm>
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

// Throws Error(kCorrupt, what + ": " + msg). Out of line: the decoders' hot paths only branch
// to it.
[[noreturn]] void throw_corrupt(const std::string& what, const char* msg);

namespace detail {
// Stores the 4 (or 8) bytes of v, most (or least) significant first, at p.
inline void store_be32(uint8_t* p, uint32_t v) {
#if defined(__BYTE_ORDER__) && __BYTE_ORDER__ == __ORDER_LITTLE_ENDIAN__
  v = __builtin_bswap32(v);
  std::memcpy(p, &v, 4);
#else
  for (int i = 0; i < 4; ++i) p[i] = static_cast<uint8_t>(v >> (24 - 8 * i));
#endif
}
inline void store_le64(uint8_t* p, uint64_t v) {
#if defined(__BYTE_ORDER__) && __BYTE_ORDER__ == __ORDER_LITTLE_ENDIAN__
  std::memcpy(p, &v, 8);
#else
  for (int i = 0; i < 8; ++i) p[i] = static_cast<uint8_t>(v >> (8 * i));
#endif
}
// Makes out->size() at least n + room (zero bytes added; at least doubling), for the coders'
// stores of a whole word past their n final bytes. Out of line: the hot paths only branch to it.
__attribute__((noinline)) inline void grow_output(std::vector<uint8_t>* out, size_t n,
                                                  size_t room) {
  out->resize(std::max(n + room, std::max<size_t>(2 * out->size(), 256)));
}
}  // namespace detail

class RangeEncoder {
 public:
  // The coder's moving state, trivially copyable and apart from the output bytes (passed in), so
  // a hot loop can work on a copy the compiler keeps in registers (IntEncoder::Cursor): when it
  // lives in memory, every byte or int stored in the loop may alias it and forces reloads.
  //
  // The block's bytes are the digits of a base-256 number whose low 4 digits are `low`: the
  // first n bytes of *out are the digits above them (the first always 0). A carry out of low
  // is added to those bytes at once (rare), and normalisation writes low's 4 digits past them
  // and counts k = clz(range) / 8 of them as final: no branch on the data (the decoder's
  // consume computes its k the same way). The bytes are those of the classic cache-and-pending
  // coder (LZMA's), which held a carry back instead.
  struct Core {
    uint64_t low = 0;  // < 2^32 between calls
    uint32_t range = 0xFFFFFFFFu;
    size_t n = 1;  // bytes of *out that are final; out->size() may be larger (n + 4 or more)

    // Codes [start, start + freq) of kTotal. Precondition: freq >= 1, start + freq <= kTotal.
    void encode(uint32_t start, uint32_t freq, std::vector<uint8_t>* out) {
      const uint32_t r = range >> kTotalBits;
      low += static_cast<uint64_t>(r) * start;
      range = r * freq;
      if (__builtin_expect(out->size() < n + 4, 0)) detail::grow_output(out, n, 4);
      if (__builtin_expect(static_cast<int>(low >> 32), 0)) carry(out);
      // range >= r >= 2^9 here: k is 0, 1 or 2.
      const int k = __builtin_clz(range) >> 3;
      detail::store_be32(out->data() + n, static_cast<uint32_t>(low));
      n += static_cast<size_t>(k);
      low = static_cast<uint32_t>(low << (8 * k));
      range <<= 8 * k;
    }
    // Adds the carry out of low to the final bytes (the first, 0, never overflows: the coded
    // interval stays below 2^32 at the block's scale).
    void carry(std::vector<uint8_t>* out) {
      uint8_t* p = out->data() + n - 1;
      while (*p == 0xFF) *p-- = 0;
      ++*p;
      low = static_cast<uint32_t>(low);
    }
    // The block's last 4 bytes: *out is then exactly the block.
    void flush(std::vector<uint8_t>* out) {
      if (out->size() < n + 4) detail::grow_output(out, n, 4);
      detail::store_be32(out->data() + n, static_cast<uint32_t>(low));
      n += 4;
      out->resize(n);
    }
  };

  // Codes [start, start + freq) of kTotal. Precondition: freq >= 1, start + freq <= kTotal.
  void encode(uint32_t start, uint32_t freq) { core_.encode(start, freq, &out_); }
  // Flushes and returns the block; the encoder is reset afterwards.
  std::vector<uint8_t> finish() {
    core_.flush(&out_);
    std::vector<uint8_t> out;
    out.swap(out_);
    core_ = Core();
    return out;
  }
  // The block's size if it were finished now.
  size_t bytes_so_far() const { return core_.n + 4; }

  const Core& core() const { return core_; }
  void set_core(const Core& c) { core_ = c; }
  std::vector<uint8_t>* out() { return &out_; }

 private:
  Core core_;
  std::vector<uint8_t> out_;
};

class RangeDecoder {
 public:
  // The moving state, trivially copyable (see RangeEncoder::Core); `what` names the block in
  // errors.
  struct Core {
    const uint8_t* p = nullptr;
    const uint8_t* end = nullptr;
    uint32_t code = 0;
    uint32_t range = 0xFFFFFFFFu;
    uint32_t r = 0;

    // First half of an interval decode: returns the cumulative target v in [0, kTotal); the
    // caller finds the symbol s with cum(s) <= v < cum(s + 1), then calls consume(start, freq).
    uint32_t target(const std::string& what) {
      r = range >> kTotalBits;
      uint32_t v = code / r;
      if (v >= kTotal) throw_corrupt(what, "entropy-coded value out of range");
      return v;
    }
    // A binary model's bit (FORMAT.md 2.8): 1 when the target is at least p0, without the
    // division; consume(start, freq) follows.
    __attribute__((always_inline)) bool decide(uint32_t p0, const std::string& what) {
      r = range >> kTotalBits;
      if (__builtin_expect(code >= (r << kTotalBits), 0))
        throw_corrupt(what, "entropy-coded value out of range");
      return code >= r * p0;
    }
    void consume(uint32_t start, uint32_t freq, const std::string& what) {
      code -= r * start;
      range = r * freq;
      // Normalisation: shift in k bytes until range >= 2^24. Here range >= r >= 2^9, so k =
      // clz(range) / 8 is 0, 1 or 2: computed, not looped, because its branch is as
      // unpredictable as the data. The byte-loop (which throws at the block's end) only within
      // 4 bytes of the end.
      if (end - p >= 4) {
        const int k = __builtin_clz(range) >> 3;
        const uint32_t w = static_cast<uint32_t>(p[0]) << 24 | static_cast<uint32_t>(p[1]) << 16 |
                           static_cast<uint32_t>(p[2]) << 8 | p[3];
        code = static_cast<uint32_t>((static_cast<uint64_t>(code) << 32 | w) >> (32 - 8 * k));
        range <<= 8 * k;
        p += k;
      } else {
        while (range < kTopValue) {
          range <<= 8;
          code = (code << 8) | next_byte(what);
        }
      }
    }
    // consume(start, freq) for a binary model's bit: the same state, but normalising only when
    // the range fell below 2^24, which a likely bit (the common case) seldom makes it do.
    __attribute__((always_inline)) void consume_bit(uint32_t start, uint32_t freq,
                                                    const std::string& what) {
      const uint32_t nr = r * freq;
      if (__builtin_expect(nr >= kTopValue, 1)) {
        code -= r * start;
        range = nr;
      } else {
        consume(start, freq, what);
      }
    }
    uint8_t next_byte(const std::string& what) {
      if (p == end) throw_corrupt(what, "entropy-coded block is truncated");
      return *p++;
    }
  };

  RangeDecoder(const uint8_t* data, size_t size, std::string what) : what_(std::move(what)) {
    core_ = start(data, size, what_);
  }
  // The state after the block's first 5 bytes (which must start with 0).
  static Core start(const uint8_t* data, size_t size, const std::string& what) {
    Core c;
    c.p = data;
    c.end = data + size;
    if (c.next_byte(what) != 0) throw_corrupt(what, "entropy-coded block does not start with 0");
    for (int i = 0; i < 4; ++i) c.code = (c.code << 8) | c.next_byte(what);
    return c;
  }

  uint32_t target() { return core_.target(what_); }
  void consume(uint32_t start, uint32_t freq) { core_.consume(start, freq, what_); }
  // True when every byte of the block has been consumed (a valid block ends exactly there).
  bool at_end() const { return core_.p == core_.end; }
  [[noreturn]] void corrupt(const char* msg) const { throw_corrupt(what_, msg); }

 private:
  Core core_;
  std::string what_;
};

// Raw bit fields travel beside the range-coded bytes (docs/FORMAT.md 2.4): packed LSB first.
class BitWriter {
 public:
  // n low bits of v, 0 <= n <= 32.
  void put(uint32_t v, int n) { core_.put(v, n, &out_); }
  // Pads the last byte with zero bits and returns the bytes; the writer is reset.
  std::vector<uint8_t> finish() {
    core_.flush(&out_);
    core_ = Core();
    std::vector<uint8_t> out;
    out.swap(out_);
    return out;
  }

  // The moving state (see RangeEncoder::Core). The first n bytes of *out are final, acc holds
  // the `bits` (< 8) after them; put stores acc's 8 bytes past them and counts its whole bytes
  // as final (no loop, no branch on the data).
  struct Core {
    uint64_t acc = 0;
    int bits = 0;
    size_t n = 0;
    void put(uint32_t v, int nv, std::vector<uint8_t>* out) {
      acc |= static_cast<uint64_t>(v) << bits;  // below 2^40
      bits += nv;
      if (__builtin_expect(out->size() < n + 8, 0)) detail::grow_output(out, n, 8);
      detail::store_le64(out->data() + n, acc);
      const int k = bits >> 3;
      n += static_cast<size_t>(k);
      acc >>= 8 * k;
      bits &= 7;
    }
    // The last byte padded with zero bits: *out is then exactly the bytes.
    void flush(std::vector<uint8_t>* out) {
      out->resize(n);
      if (bits > 0) out->push_back(static_cast<uint8_t>(acc));
      n = out->size();
      acc = 0;
      bits = 0;
    }
  };
  const Core& core() const { return core_; }
  void set_core(const Core& c) { core_ = c; }
  std::vector<uint8_t>* out() { return &out_; }

 private:
  Core core_;
  std::vector<uint8_t> out_;
};

// Trivially copyable: hot loops work on a copy (IntDecoder::Cursor).
class BitReader {
 public:
  BitReader() = default;
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
  const uint8_t* p_ = nullptr;
  const uint8_t* end_ = nullptr;
  uint64_t acc_ = 0;
  int bits_ = 0;
};

namespace detail {
// SymbolModel's adaptation shift by the number of updates so far: 4 for the first 16, 5 up to
// 64, 6 up to 256, then 7 (a table: the comparisons' branches cost more than the lookup).
struct RateTable {
  uint8_t r[257];
  constexpr RateTable() : r() {
    for (int n = 0; n <= 256; ++n)
      r[n] = static_cast<uint8_t>(n < 16 ? 4 : n < 64 ? 5 : n < 256 ? 6 : 7);
  }
};
inline constexpr RateTable kRates{};
// SymbolModel's update target for symbol s, plus i: lane i holds (i > s ? T : 0) + i, T = 2^15
// - 16.
struct TargetTable {
  alignas(16) uint16_t t[16][16];
  constexpr TargetTable() : t() {
    for (int s = 0; s < 16; ++s)
      for (int i = 0; i < 16; ++i) t[s][i] = static_cast<uint16_t>((i > s ? kTotal - 16 : 0) + i);
  }
};
inline constexpr TargetTable kTargets{};
}  // namespace detail

// Adaptive model over 16 symbols (docs/FORMAT.md 2.3): cum(i) = c[i] + i over kTotal, so every
// symbol keeps a frequency >= 1. Alphabets of n < 16 symbols simply never code the top ones.
// Stored as cum itself (cum_[i] = c[i] + i; cum_[16] = kTotal): the update
// c += (target - c) >> rate is the same as cum += ((target + i) - cum) >> rate.
class SymbolModel {
 public:
  static constexpr int kSymbols = 16;
  static constexpr int16_t kT = static_cast<int16_t>(kTotal - kSymbols);
  SymbolModel() {
    for (int i = 0; i <= kSymbols; ++i) cum_[i] = static_cast<uint16_t>(i * kT / kSymbols + i);
  }
  // Start on the first m symbols (FORMAT.md 2.3): c[i] = floor(i * T / m) for i <= m, T above,
  // so symbols m..15 keep their least frequency, 1.
  void restrict(int m) {
    for (int i = 0; i <= kSymbols; ++i)
      cum_[i] = static_cast<uint16_t>((i <= m ? i * kT / m : kT) + i);
  }
  // Skewed start (FORMAT.md 2.3): c[i] = T - floor(T / 2^i), symbol i has about 2^-(i+1).
  void skew() {
    for (int i = 1; i < kSymbols; ++i) cum_[i] = static_cast<uint16_t>(kT - (kT >> i) + i);
  }

  // Enc: RangeEncoder or anything with encode(start, freq); Dec: RangeDecoder or anything with
  // target() and consume(start, freq) (the cursors of entropy.h).
  template <typename Enc>
  __attribute__((always_inline)) void encode(Enc* enc, int s) {
    const uint32_t lo = cum_[s], hi = cum_[s + 1];
    enc->encode(lo, hi - lo);
    update(s);
  }
  template <typename Dec>
  __attribute__((always_inline)) int decode(Dec* dec) {
    const int s = find(static_cast<int>(dec->target()));
    const uint32_t lo = cum_[s], hi = cum_[s + 1];
    dec->consume(lo, hi - lo);
    update(s);
    return s;
  }

 private:
  int rate() {
    const int r = detail::kRates.r[count_];
    count_ += count_ < 256;
    return r;
  }
#if defined(__SSE2__)
  // s = (number of i in [0, 16) with cum(i) <= v) - 1; cum(0) = 0 <= v always. cum(i) for
  // i < 16 is below 2^15, so the signed 16-bit comparison is exact.
  int find(int v) const {
    const __m128i vv = _mm_set1_epi16(static_cast<int16_t>(v));
    const __m128i a = _mm_load_si128(reinterpret_cast<const __m128i*>(cum_));
    const __m128i b = _mm_load_si128(reinterpret_cast<const __m128i*>(cum_ + 8));
    // cum is non-decreasing, so the lanes with cum > v form a suffix: s = its start - 1.
    // No lane above v (gt = 0) means s = 15: bit 16 stands in for that (no branch).
    int gt = _mm_movemask_epi8(_mm_packs_epi16(_mm_cmpgt_epi16(a, vv), _mm_cmpgt_epi16(b, vv)));
    return __builtin_ctz(static_cast<unsigned>(gt) | 0x10000u) - 1;
  }
  void update(int s) {
    const __m128i r = _mm_cvtsi32_si128(rate());
    const __m128i* t = reinterpret_cast<const __m128i*>(detail::kTargets.t[s]);
    __m128i* p = reinterpret_cast<__m128i*>(cum_);
    __m128i a = _mm_load_si128(p), b = _mm_load_si128(p + 1);
    a = _mm_add_epi16(a, _mm_sra_epi16(_mm_sub_epi16(_mm_load_si128(t), a), r));
    b = _mm_add_epi16(b, _mm_sra_epi16(_mm_sub_epi16(_mm_load_si128(t + 1), b), r));
    _mm_store_si128(p, a);  // cum[0] stays 0: its target is 0
    _mm_store_si128(p + 1, b);
  }
#else
  int find(int v) const {
    int n = 0;
    for (int i = 1; i < kSymbols; ++i) n += (cum_[i] <= v);
    return n;
  }
  void update(int s) {
    const int r = rate();
    for (int i = 1; i < kSymbols; ++i) {
      const int c = cum_[i];
      cum_[i] = static_cast<uint16_t>(c + ((detail::kTargets.t[s][i] - c) >> r));
    }
  }
#endif

  int count_ = 0;
  alignas(16) uint16_t cum_[kSymbols + 8];  // cum_[16] = kTotal; the rest is padding
};

// Adaptive binary model (docs/FORMAT.md 2.8): q, the chance of a 0 in 2^-22, adapting at the
// symbol models' rates; coded as p = q >> 7 within [kBitFloor, kTotal - kBitFloor].
class BitModel {
 public:
  static constexpr uint32_t kBitFloor = 64, kOne = 1u << 22;
  template <typename Enc>
  __attribute__((always_inline)) void encode(Enc* enc, bool bit) {
    const uint32_t p = coded();
    enc->encode(bit ? p : 0u, bit ? kTotal - p : p);
    update(bit);
  }
  // dec: a RangeDecoder::Core; what names the block in errors.
  __attribute__((always_inline)) bool decode(RangeDecoder::Core* dec, const std::string& what) {
    const uint32_t p = coded();
    const bool bit = dec->decide(p, what);
    dec->consume_bit(bit ? p : 0u, bit ? kTotal - p : p, what);
    update(bit);
    return bit;
  }

 private:
  uint32_t coded() const {
    return std::min(std::max(q_ >> (22 - kTotalBits), kBitFloor), kTotal - kBitFloor);
  }
  __attribute__((always_inline)) void update(bool bit) {
    const int r = detail::kRates.r[count_];
    count_ += count_ < 256;
    q_ = bit ? q_ - (q_ >> r) : q_ + ((kOne - q_) >> r);
  }
  uint32_t q_ = kOne / 2;
  uint32_t count_ = 0;
};

}  // namespace capz
