// Byte patches found (patch.h): the runs where a regenerated file differs from the original;
// patch.cpp applies them.
#include <cstring>
#include <utility>

#include "io/residue/patch.h"

namespace capz {
namespace residue {

namespace {
constexpr size_t kJoin = 3;

// The first i' >= i below n where a and b differ, or n: eight bytes at a time.
inline size_t next_diff(const uint8_t* a, const uint8_t* b, size_t i, size_t n) {
  for (; i + 8 <= n; i += 8) {
    uint64_t x, y;
    std::memcpy(&x, a + i, 8);
    std::memcpy(&y, b + i, 8);
    if (const uint64_t d = x ^ y) {
#if defined(__BYTE_ORDER__) && __BYTE_ORDER__ == __ORDER_BIG_ENDIAN__
      return i + static_cast<size_t>(__builtin_clzll(d) >> 3);
#else
      return i + static_cast<size_t>(__builtin_ctzll(d) >> 3);
#endif
    }
  }
  while (i < n && a[i] == b[i]) ++i;
  return i;
}
}  // namespace

std::vector<uint8_t> diff_bytes(const uint8_t* regen, const uint8_t* orig, size_t n) {
  std::vector<std::pair<size_t, size_t>> found;
  for (size_t i = next_diff(regen, orig, 0, n); i < n;) {
    // Extend the run while the next difference is fewer than kJoin equal bytes away.
    size_t j = i + 1, d;
    while ((d = next_diff(regen, orig, j, n)) < n && d - j < kJoin) j = d + 1;
    found.emplace_back(i, j);
    i = d;
  }
  if (found.empty()) return {};
  ByteWriter out;
  size_t end = 0;  // one past the previous run
  out.varint(found.size());
  for (auto& r : found) {
    out.varint(r.first - end);
    out.varint(r.second - r.first - 1);
    end = r.second;
  }
  for (auto& r : found) out.bytes(orig + r.first, r.second - r.first);
  return std::move(out.buffer());
}

}  // namespace residue
}  // namespace capz
