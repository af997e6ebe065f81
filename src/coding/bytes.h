// Explicit little-endian byte I/O. Every stored number goes through these; never write(&x, sizeof
// x). ByteReader checks every read against the end of its buffer and throws Error(kCorrupt) naming
// `what` (e.g. "chunk POS0") instead of reading past it.
#pragma once

#include <cstdint>
#include <cstring>
#include <string>
#include <vector>

#include "capz/error.h"

namespace capz {

// The little-endian uint32 at p[0..3].
inline uint32_t load_le32(const uint8_t* p) {
  return static_cast<uint32_t>(p[0]) | static_cast<uint32_t>(p[1]) << 8 |
         static_cast<uint32_t>(p[2]) << 16 | static_cast<uint32_t>(p[3]) << 24;
}

class ByteWriter {
 public:
  void u8(uint8_t v) { buf_.push_back(v); }
  void u16(uint16_t v) {
    for (int i = 0; i < 2; ++i) buf_.push_back(static_cast<uint8_t>(v >> (8 * i)));
  }
  void u32(uint32_t v) {
    for (int i = 0; i < 4; ++i) buf_.push_back(static_cast<uint8_t>(v >> (8 * i)));
  }
  void u64(uint64_t v) {
    for (int i = 0; i < 8; ++i) buf_.push_back(static_cast<uint8_t>(v >> (8 * i)));
  }
  void i32(int32_t v) { u32(static_cast<uint32_t>(v)); }
  void f32(float v) {
    uint32_t u;
    std::memcpy(&u, &v, 4);
    u32(u);
  }
  void f64(double v) {
    uint64_t u;
    std::memcpy(&u, &v, 8);
    u64(u);
  }
  // Unsigned LEB128: 7 bits a byte, low first, high bit = more.
  void varint(uint64_t v) {
    while (v >= 0x80) {
      buf_.push_back(static_cast<uint8_t>(v | 0x80));
      v >>= 7;
    }
    buf_.push_back(static_cast<uint8_t>(v));
  }
  // Zig-zag then LEB128.
  void svarint(int64_t v) {
    varint((static_cast<uint64_t>(v) << 1) ^ static_cast<uint64_t>(v >> 63));
  }
  void bytes(const uint8_t* p, size_t n) { buf_.insert(buf_.end(), p, p + n); }
  void bytes(const std::vector<uint8_t>& v) { bytes(v.data(), v.size()); }
  // varint length, then the bytes
  void str(const std::string& s) {
    varint(s.size());
    bytes(reinterpret_cast<const uint8_t*>(s.data()), s.size());
  }

  std::vector<uint8_t>& buffer() { return buf_; }
  const std::vector<uint8_t>& buffer() const { return buf_; }
  size_t size() const { return buf_.size(); }

 private:
  std::vector<uint8_t> buf_;
};

class ByteReader {
 public:
  ByteReader(const uint8_t* data, size_t size, std::string what)
      : p_(data), end_(data + size), begin_(data), what_(std::move(what)) {}

  size_t remaining() const { return static_cast<size_t>(end_ - p_); }
  size_t offset() const { return static_cast<size_t>(p_ - begin_); }
  bool at_end() const { return p_ == end_; }
  const std::string& what() const { return what_; }

  uint8_t u8() {
    need(1);
    return *p_++;
  }
  uint16_t u16() {
    need(2);
    uint16_t v = static_cast<uint16_t>(p_[0] | (p_[1] << 8));
    p_ += 2;
    return v;
  }
  uint32_t u32() {
    need(4);
    const uint32_t v = load_le32(p_);
    p_ += 4;
    return v;
  }
  uint64_t u64() {
    need(8);
    uint64_t v = 0;
    for (int i = 0; i < 8; ++i) v |= static_cast<uint64_t>(p_[i]) << (8 * i);
    p_ += 8;
    return v;
  }
  int32_t i32() { return static_cast<int32_t>(u32()); }
  float f32() {
    uint32_t u = u32();
    float f;
    std::memcpy(&f, &u, 4);
    return f;
  }
  double f64() {
    uint64_t u = u64();
    double d;
    std::memcpy(&d, &u, 8);
    return d;
  }
  uint64_t varint() {
    uint64_t v = 0;
    for (int shift = 0; shift < 64; shift += 7) {
      uint8_t b = u8();
      v |= static_cast<uint64_t>(b & 0x7f) << shift;
      if (!(b & 0x80)) return v;
    }
    throw Error(ErrorCode::kCorrupt,
                what_ + ": varint longer than 10 bytes at offset " + std::to_string(offset()));
  }
  int64_t svarint() {
    uint64_t u = varint();
    return static_cast<int64_t>(u >> 1) ^ -static_cast<int64_t>(u & 1);
  }
  // A count that must fit in what is left, at `min_bytes_each` bytes per element.
  uint64_t count(size_t min_bytes_each, const char* name) {
    uint64_t n = varint();
    if (min_bytes_each > 0 && n > remaining() / min_bytes_each)
      throw Error(ErrorCode::kCorrupt, what_ + ": " + name + " = " + std::to_string(n) +
                                           " cannot fit in the " + std::to_string(remaining()) +
                                           " bytes left");
    return n;
  }
  const uint8_t* bytes(size_t n) {
    need(n);
    const uint8_t* q = p_;
    p_ += n;
    return q;
  }
  std::string str() {
    uint64_t n = count(1, "string length");
    const uint8_t* q = bytes(static_cast<size_t>(n));
    return std::string(reinterpret_cast<const char*>(q), static_cast<size_t>(n));
  }

 private:
  void need(size_t n) const {
    if (static_cast<size_t>(end_ - p_) < n)
      throw Error(ErrorCode::kCorrupt, what_ + ": truncated (needs " + std::to_string(n) +
                                           " bytes at offset " + std::to_string(offset()) + ", " +
                                           std::to_string(remaining()) + " left)");
  }
  const uint8_t* p_;
  const uint8_t* end_;
  const uint8_t* begin_;
  std::string what_;
};

// A length-prefixed block: varint(size), then the bytes. put_block writes one;
// get_block reads one, throwing Error(kCorrupt) naming `name` when its size exceeds what is
// left, and returns its first byte with *n = its size.
inline void put_block(ByteWriter* w, const std::vector<uint8_t>& b) {
  w->varint(b.size());
  w->bytes(b);
}
inline const uint8_t* get_block(ByteReader* r, size_t* n, const char* name) {
  *n = static_cast<size_t>(r->count(1, name));
  return r->bytes(*n);
}

}  // namespace capz
