// LZF (coding/lzf.h).
#include "coding/lzf.h"

#include <algorithm>
#include <cstring>

#include "capz/error.h"

namespace capz {

namespace {
constexpr size_t kMaxLiteral = 32;
constexpr size_t kMaxDistance = 8192;
constexpr size_t kMaxMatch = 2 + 7 + 255;
constexpr int kHashBits = 16;

uint32_t bytes3(const uint8_t* p) {
  return static_cast<uint32_t>(p[0]) << 16 | static_cast<uint32_t>(p[1]) << 8 | p[2];
}
uint32_t hash_of(uint32_t v) {
  return (v * 2654435761u) >> (32 - kHashBits);
}
uint32_t hash3(const uint8_t* p) {
  return hash_of(bytes3(p));
}

// The literals [from, to) at o, in runs of up to kMaxLiteral under a control byte; returns the
// end.
uint8_t* flush_literals(const uint8_t* data, size_t from, size_t to, uint8_t* o) {
  while (from < to) {
    const size_t n = std::min(kMaxLiteral, to - from);
    *o++ = static_cast<uint8_t>(n - 1);
    std::memcpy(o, data + from, n);
    o += n;
    from += n;
  }
  return o;
}
// A copy of `len` bytes (3 to 264) from `off` + 1 bytes back, at o; returns the end.
uint8_t* put_copy(size_t len, size_t off, uint8_t* o) {
  const size_t l = len - 2;
  if (l < 7) {
    *o++ = static_cast<uint8_t>((l << 5) | (off >> 8));
  } else {
    *o++ = static_cast<uint8_t>((7 << 5) | (off >> 8));
    *o++ = static_cast<uint8_t>(l - 7);
  }
  *o++ = static_cast<uint8_t>(off & 255);
  return o;
}
void put_copy(size_t len, size_t off, std::vector<uint8_t>* out) {
  uint8_t b[3];
  out->insert(out->end(), b, put_copy(len, off, b));
}
}  // namespace

// size is below 2^32, so a position fits 32 bits and is never kNone.
std::vector<uint8_t> lzf_compress(const uint8_t* data, size_t size) {
  constexpr uint32_t kNone = ~uint32_t{0};
  if (size > 0xFFFFFFFFu) fail(ErrorCode::kUsage, "", "LZF of more than 4 GiB");
  // At most the input and a control byte per kMaxLiteral literals: a copy codes 3 or more bytes
  // in 2 or 3.
  std::vector<uint8_t> out(size + size / kMaxLiteral + 1);
  uint8_t* o = out.data();
  std::vector<uint32_t> table(size_t{1} << kHashBits, kNone);
  size_t i = 0, lit = 0;
  uint32_t v = size >= 3 ? bytes3(data) : 0;  // the 3 bytes at i, rolled on byte by byte
  while (i + 3 <= size) {
    const uint32_t h = hash_of(v);
    const uint32_t cand = table[h];
    table[h] = static_cast<uint32_t>(i);
    if (cand != kNone && i - cand <= kMaxDistance && bytes3(data + cand) == v) {
      size_t len = 3;
      const size_t limit = std::min(kMaxMatch, size - i);
      while (len + 8 <= limit) {  // 8 bytes at a time, then byte by byte: the same length
        uint64_t a, b;
        std::memcpy(&a, data + cand + len, 8);
        std::memcpy(&b, data + i + len, 8);
        if (a != b) break;
        len += 8;
      }
      while (len < limit && data[cand + len] == data[i + len]) ++len;
      o = flush_literals(data, lit, i, o);
      o = put_copy(len, i - cand - 1, o);
      // Index the positions the match covers (their prefixes), so later matches find them.
      for (size_t k = i + 1; k < i + len && k + 3 <= size; ++k)
        table[hash3(data + k)] = static_cast<uint32_t>(k);
      i += len;
      lit = i;
      if (i + 3 <= size) v = bytes3(data + i);
    } else {
      ++i;
      if (i + 3 <= size) v = (v << 8 | data[i + 2]) & 0xFFFFFFu;
    }
  }
  o = flush_literals(data, lit, size, o);
  out.resize(static_cast<size_t>(o - out.data()));
  return out;
}

namespace {

// Variant 1's output: literal runs under a control byte reserved when the run opens.
struct LiteralRuns {
  std::vector<uint8_t>* out;
  size_t at = 0;
  size_t n = 0;
  void open() {
    at = out->size();
    out->push_back(0);
    n = 0;
  }
  void close() {
    if (n)
      (*out)[at] = static_cast<uint8_t>(n - 1);
    else
      out->pop_back();
  }
  void add(uint8_t c) {
    out->push_back(c);
    if (++n == kMaxLiteral) {
      (*out)[at] = static_cast<uint8_t>(kMaxLiteral - 1);
      open();
    }
  }
};

constexpr int kLiblzfBits = 13;

uint32_t liblzf_slot(uint32_t h) {
  return ((h >> (24 - kLiblzfBits)) - h) & ((1u << kLiblzfBits) - 1);
}

// Variant 1's match length at i against r (FORMAT.md 14.3): liblzf checks its first 16 bytes
// past the 3 equal ones unrolled whenever more than 16 may follow.
size_t liblzf_length(const uint8_t* in, size_t n, size_t r, size_t i) {
  const size_t M = std::min(kMaxMatch, n - i - 2);
  size_t m = 2;
  if (M > 16)
    for (int k = 0; k < 16; ++k) {
      ++m;
      if (in[r + m] != in[i + m]) return m;
    }
  do ++m;
  while (m < M && in[r + m] == in[i + m]);
  return m;
}

std::vector<uint8_t> lzf_compress_liblzf(const uint8_t* in, size_t n) {
  std::vector<uint8_t> out;
  out.reserve(n / 2 + 16);
  LiteralRuns lit{&out};
  lit.open();
  std::vector<uint32_t> table(size_t{1} << kLiblzfBits, 0);
  size_t i = 0;
  uint32_t h = n >= 2 ? (uint32_t{in[0]} << 8 | in[1]) : 0;
  while (i + 2 < n) {
    h = h << 8 | in[i + 2];
    uint32_t& slot = table[liblzf_slot(h)];
    const size_t r = slot;
    slot = static_cast<uint32_t>(i);
    if (!(r > 0 && r < i && i - r <= kMaxDistance && std::memcmp(in + r, in + i, 3) == 0)) {
      lit.add(in[i++]);
      continue;
    }
    const size_t m = liblzf_length(in, n, r, i);
    lit.close();
    put_copy(m, i - r - 1, &out);
    lit.open();
    i += m;
    if (i + 2 >= n) break;
    h = uint32_t{in[i - 1]} << 16 | uint32_t{in[i]} << 8 | in[i + 1];
    table[liblzf_slot(h)] = static_cast<uint32_t>(i - 1);
  }
  while (i < n) lit.add(in[i++]);
  lit.close();
  return out;
}

}  // namespace

std::vector<uint8_t> lzf_compress(const uint8_t* data, size_t size, LzfVariant variant) {
  if (size > 0xFFFFFFFFu) fail(ErrorCode::kUsage, "", "LZF of more than 4 GiB");
  return variant == LzfVariant::kLiblzf13 ? lzf_compress_liblzf(data, size)
                                          : lzf_compress(data, size);
}

bool lzf_decompress_into(const uint8_t* data, size_t n, uint8_t* out, size_t size) {
  size_t p = 0, o = 0;
  while (p < n) {
    const size_t c = data[p++];
    if (c < 32) {
      const size_t len = c + 1;
      if (len > n - p || len > size - o) return false;
      std::memcpy(out + o, data + p, len);
      p += len, o += len;
      continue;
    }
    size_t len = (c >> 5) + 2;
    if ((c >> 5) == 7) {
      if (p >= n) return false;
      len += data[p++];
    }
    if (p >= n) return false;
    const size_t dist = ((c & 31) << 8) + data[p++] + 1;
    if (dist > o || len > size - o) return false;
    const uint8_t* from = out + o - dist;
    if (dist >= len) {
      std::memcpy(out + o, from, len);
    } else {  // the copy overlaps what it writes: byte by byte, in order
      for (size_t k = 0; k < len; ++k) out[o + k] = from[k];
    }
    o += len;
  }
  return o == size;
}

std::vector<uint8_t> lzf_decompress(const uint8_t* data, size_t n, size_t size,
                                    const std::string& what) {
  std::vector<uint8_t> out(size);
  if (!lzf_decompress_into(data, n, out.data(), size))
    fail(ErrorCode::kCorrupt, what,
         "malformed LZF stream (a run past either end, or too few bytes)");
  return out;
}

}  // namespace capz
