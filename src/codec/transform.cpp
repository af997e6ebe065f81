#include "codec/transform.h"

#include <algorithm>

namespace capz {

std::vector<double> fill_gaps(size_t frames, size_t points, const double* xyz,
                              const uint8_t* valid) {
  const size_t N = points;
  std::vector<double> x(xyz, xyz + frames * N * 3);
  for (size_t p = 0; p < N; ++p) {
    long last = -1;
    for (size_t f = 0; f < frames; ++f) {
      if (valid[f * N + p]) {
        if (last < 0)  // back-fill the leading gap
          for (size_t g = 0; g < f; ++g)
            std::copy(&x[(f * N + p) * 3], &x[(f * N + p) * 3] + 3, &x[(g * N + p) * 3]);
        last = static_cast<long>(f);
      } else if (last >= 0) {
        std::copy(&x[(static_cast<size_t>(last) * N + p) * 3],
                  &x[(static_cast<size_t>(last) * N + p) * 3] + 3, &x[(f * N + p) * 3]);
      }
    }
    if (last < 0)
      for (size_t f = 0; f < frames; ++f) std::fill_n(&x[(f * N + p) * 3], 3, 0.0);
  }
  return x;
}

}  // namespace capz
