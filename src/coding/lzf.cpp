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

// Whether the 3 bytes at a and b are equal, reading 4 bytes at each (both have a 4th).
bool same3_wide(const uint8_t* a, const uint8_t* b) {
  uint32_t x, y;
  std::memcpy(&x, a, 4);
  std::memcpy(&y, b, 4);
#if defined(__BYTE_ORDER__) && __BYTE_ORDER__ == __ORDER_LITTLE_ENDIAN__
  return ((x ^ y) & 0xFFFFFFu) == 0;
#else
  return ((x ^ y) & 0xFFFFFF00u) == 0;
#endif
}

// The length of the match of a and b, 3 equal bytes known, at most limit: the first byte that
// differs, 8 bytes at a time while 8 fit, then byte by byte.
size_t match_length(const uint8_t* a, const uint8_t* b, size_t limit) {
  size_t len = 3;
  for (; len + 8 <= limit; len += 8) {
    uint64_t x, y;
    std::memcpy(&x, a + len, 8);
    std::memcpy(&y, b + len, 8);
#if defined(__BYTE_ORDER__) && __BYTE_ORDER__ == __ORDER_LITTLE_ENDIAN__
    if (x != y) return len + static_cast<size_t>(__builtin_ctzll(x ^ y) >> 3);
#else
    if (x != y) break;
#endif
  }
  while (len < limit && a[len] == b[len]) ++len;
  return len;
}

size_t lzf_compress_capz(const uint8_t* data, size_t size, uint8_t* out) {
  // A slot holds a position, or kNone (above any position: size is below 2^32, checked by the
  // callers), whose distance i - kNone wraps beyond kMaxDistance.
  constexpr uint32_t kNone = ~uint32_t{0};
  std::vector<uint32_t> table(size_t{1} << kHashBits, kNone);
  uint32_t* const slots = table.data();
  uint8_t* o = out;
  size_t i = 0, lit = 0;
  uint32_t v = size >= 3 ? bytes3(data) : 0;  // the 3 bytes at i, rolled on byte by byte
  while (i + 3 <= size) {
    const uint32_t h = hash_of(v);
    const size_t cand = slots[h];
    slots[h] = static_cast<uint32_t>(i);
    const bool hit = i - cand <= kMaxDistance &&
                     (i + 4 <= size ? same3_wide(data + cand, data + i) : bytes3(data + cand) == v);
    if (!hit) {
      ++i;
      if (i + 3 <= size) v = (v << 8 | data[i + 2]) & 0xFFFFFFu;
      continue;
    }
    const size_t len = match_length(data + cand, data + i, std::min(kMaxMatch, size - i));
    o = flush_literals(data, lit, i, o);
    o = put_copy(len, i - cand - 1, o);
    // Index the positions the match covers (their prefixes), so later matches find them; the
    // 3 bytes rolled on from i's.
    const size_t stop = std::min(i + len, size - 2);  // k + 3 <= size
    for (size_t k = i + 1; k < stop; ++k) {
      v = (v << 8 | data[k + 2]) & 0xFFFFFFu;
      slots[hash_of(v)] = static_cast<uint32_t>(k);
    }
    i += len;
    lit = i;
    if (i + 3 <= size) v = bytes3(data + i);
  }
  o = flush_literals(data, lit, size, o);
  return static_cast<size_t>(o - out);
}

}  // namespace

size_t lzf_bound(size_t size) {
  return size + size / kMaxLiteral + 1;
}

size_t lzf_compress_into(const uint8_t* data, size_t size, uint8_t* out) {
  if (size > 0xFFFFFFFFu) fail(ErrorCode::kUsage, "", "LZF of more than 4 GiB");
  return lzf_compress_capz(data, size, out);
}

std::vector<uint8_t> lzf_compress(const uint8_t* data, size_t size) {
  if (size > 0xFFFFFFFFu) fail(ErrorCode::kUsage, "", "LZF of more than 4 GiB");
  std::vector<uint8_t> out(lzf_bound(size));
  out.resize(lzf_compress_capz(data, size, out.data()));
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

namespace {

// Runs of the stream decompressed into out[0, size) until `stop` bytes are out (stop <= size) or
// the stream ends; returns the bytes out, or SIZE_MAX on a run that is malformed, references
// before the start or passes `size`. *p: the stream's bytes used. While a run's bytes and 32
// more fit both buffers (kRoom), the runs go without their bounds tests: a literal run copied 32
// bytes at once, a copy from at least 16 bytes back 16 at a time (the bytes past the run are
// written again by the runs after it, or lie beyond what was asked when the stream stops); the
// last runs are tested one by one.
size_t decompress_runs(const uint8_t* data, size_t n, uint8_t* out, size_t size, size_t stop,
                       size_t* used) {
  constexpr size_t kFail = ~size_t{0};
  constexpr size_t kRoom = 3 + kMaxMatch + 32;  // a run's bytes in either buffer, and 32
  size_t p = 0, o = 0;
  while (o < stop && n - p >= kRoom && size - o >= kRoom) {
    const size_t c = data[p++];
    if (c < 32) {
      std::memcpy(out + o, data + p, 32);
      p += c + 1, o += c + 1;
      continue;
    }
    size_t len = (c >> 5) + 2;
    if (len == 9) len += data[p++];
    const size_t dist = ((c & 31) << 8) + data[p++] + 1;
    if (dist > o) return kFail;
    const uint8_t* from = out + o - dist;
    if (dist >= 16) {  // each 16 bytes read were written before
      for (size_t k = 0; k < len; k += 16) std::memcpy(out + o + k, from + k, 16);
    } else {  // the copy overlaps what it writes: byte by byte, in order
      for (size_t k = 0; k < len; ++k) out[o + k] = from[k];
    }
    o += len;
  }
  while (p < n && o < stop) {
    const size_t c = data[p++];
    if (c < 32) {
      const size_t len = c + 1;
      if (len > n - p || len > size - o) return kFail;
      std::memcpy(out + o, data + p, len);
      p += len, o += len;
      continue;
    }
    size_t len = (c >> 5) + 2;
    if ((c >> 5) == 7) {
      if (p >= n) return kFail;
      len += data[p++];
    }
    if (p >= n) return kFail;
    const size_t dist = ((c & 31) << 8) + data[p++] + 1;
    if (dist > o || len > size - o) return kFail;
    const uint8_t* from = out + o - dist;
    if (dist >= len) {
      std::memcpy(out + o, from, len);
    } else {  // the copy overlaps what it writes: byte by byte, in order
      for (size_t k = 0; k < len; ++k) out[o + k] = from[k];
    }
    o += len;
  }
  *used = p;
  return o;
}

}  // namespace

bool lzf_decompress_into(const uint8_t* data, size_t n, uint8_t* out, size_t size) {
  size_t used = 0;
  return decompress_runs(data, n, out, size, size, &used) == size && used == n;
}

bool lzf_decompress_prefix(const uint8_t* data, size_t n, uint8_t* out, size_t size,
                           size_t prefix) {
  size_t used = 0;
  const size_t o = decompress_runs(data, n, out, size, std::min(prefix, size), &used);
  return o != ~size_t{0} && o >= std::min(prefix, size);
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
