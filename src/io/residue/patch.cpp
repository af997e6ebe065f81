// capz — byte patches (see patch.h).
#include "io/residue/patch.h"

#include <algorithm>
#include <utility>

#include "capz/error.h"

namespace capz {
namespace residue {

namespace {
constexpr size_t kJoin = 3;
}

std::vector<uint8_t> diff_bytes(const uint8_t* regen, const uint8_t* orig, size_t n) {
  std::vector<std::pair<size_t, size_t>> found;
  for (size_t i = 0; i < n;) {
    if (regen[i] == orig[i]) {
      ++i;
      continue;
    }
    size_t j = i + 1;
    // Extend while the next difference is fewer than kJoin equal bytes away.
    for (size_t k = j; k < n && k < j + kJoin; ++k)
      if (regen[k] != orig[k]) j = k + 1, k = j - 1;
    found.emplace_back(i, j);
    i = j;
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
