// capz — byte patches (see patch.h).
#include "io/residue/patch.h"

#include <algorithm>
#include <cstring>
#include <utility>

#include "capz/error.h"

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

void apply_patch(const std::vector<uint8_t>& patch, uint8_t* buf, size_t n, const char* what) {
  if (patch.empty()) return;
  ByteReader in(patch.data(), patch.size(), what);
  const uint64_t runs = in.count(3, "patch runs");  // 2 header bytes + 1 byte each at least
  std::vector<std::pair<uint64_t, uint64_t>> at(static_cast<size_t>(runs));
  uint64_t end = 0;
  for (auto& r : at) {
    const uint64_t skip = in.varint(), len = in.varint() + 1;
    if (skip > n - end || len > n - end - skip)
      fail(ErrorCode::kCorrupt, what,
           "patch run past the " + std::to_string(n) + " bytes it patches");
    r = {end + skip, len};
    end += skip + len;
  }
  for (auto& r : at) {
    const uint8_t* src = in.bytes(static_cast<size_t>(r.second));
    std::copy(src, src + r.second, buf + r.first);
  }
  if (!in.at_end()) fail(ErrorCode::kCorrupt, what, "bytes left after the patch runs");
}

}  // namespace residue
}  // namespace capz
