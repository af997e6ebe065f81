// capz — the most frequent key of a count map, shared by the residue models that pick a
// window's or a frame's usual spelling (trc_residue, pcd_ascii).
#pragma once

#include <cstddef>
#include <map>

namespace capz {
namespace residue {

// The key counted most often in `counts` (the smallest such key on a tie); `fallback` when empty.
template <typename K>
K mode(const std::map<K, size_t>& counts, K fallback) {
  size_t best = 0;
  for (const auto& kv : counts)
    if (kv.second > best) best = kv.second, fallback = kv.first;
  return fallback;
}

}  // namespace residue
}  // namespace capz
