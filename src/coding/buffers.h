// Buffers refilled again and again (decoder side): sized for the values the caller writes next.
#pragma once

#include <cstddef>
#include <vector>

namespace capz {

// Sizes *v to n values that the caller writes whole: within its capacity as it is (values past
// its old size zeroed); above it, room for an eighth more, taken without copying the old values
// (a buffer refilled window after window, the windows' sizes a little apart).
template <typename T>
void size_for_overwrite(std::vector<T>* v, size_t n) {
  if (n > v->capacity()) {
    v->clear();
    v->reserve(n + n / 8);
  }
  v->resize(n);
}

}  // namespace capz
