// LZF (coding/lzf.h).
#include "coding/lzf.h"

#include <cstring>

#include "capz/error.h"

namespace capz {

namespace {
constexpr size_t kMaxLiteral = 32;
constexpr size_t kMaxDistance = 8192;
constexpr size_t kMaxMatch = 2 + 7 + 255;
constexpr int kHashBits = 16;

uint32_t hash3(const uint8_t* p) {
  const uint32_t v = static_cast<uint32_t>(p[0]) << 16 | static_cast<uint32_t>(p[1]) << 8 | p[2];
  return (v * 2654435761u) >> (32 - kHashBits);
}

void flush_literals(const uint8_t* data, size_t from, size_t to, std::vector<uint8_t>* out) {
  while (from < to) {
    const size_t n = std::min(kMaxLiteral, to - from);
    out->push_back(static_cast<uint8_t>(n - 1));
    out->insert(out->end(), data + from, data + from + n);
    from += n;
  }
}
}  // namespace

std::vector<uint8_t> lzf_compress(const uint8_t* data, size_t size) {
  std::vector<uint8_t> out;
  out.reserve(size / 2 + 16);
  std::vector<size_t> table(size_t{1} << kHashBits, ~size_t{0});
  size_t i = 0, lit = 0;
  while (i + 3 <= size) {
    const uint32_t h = hash3(data + i);
    const size_t cand = table[h];
    table[h] = i;
    if (cand != ~size_t{0} && i - cand <= kMaxDistance &&
        std::memcmp(data + cand, data + i, 3) == 0) {
      size_t len = 3;
      const size_t limit = std::min(kMaxMatch, size - i);
      while (len < limit && data[cand + len] == data[i + len]) ++len;
      flush_literals(data, lit, i, &out);
      const size_t off = i - cand - 1;
      const size_t l = len - 2;
      if (l < 7) {
        out.push_back(static_cast<uint8_t>((l << 5) | (off >> 8)));
      } else {
        out.push_back(static_cast<uint8_t>((7 << 5) | (off >> 8)));
        out.push_back(static_cast<uint8_t>(l - 7));
      }
      out.push_back(static_cast<uint8_t>(off & 255));
      // Index the positions the match covers (their prefixes), so later matches find them.
      for (size_t k = i + 1; k < i + len && k + 3 <= size; ++k) table[hash3(data + k)] = k;
      i += len;
      lit = i;
    } else {
      ++i;
    }
  }
  flush_literals(data, lit, size, &out);
  return out;
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
