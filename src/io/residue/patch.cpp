// Byte patches applied (patch.h); patch_encode.cpp finds them.
#include "io/residue/patch.h"

#include "capz/error.h"

namespace capz {
namespace residue {

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
