// Negative zeros of lossless mode 1 windows, the decoder's side (negative_zeros.h). Part of the
// decoder library.
#include "codec/negative_zeros.h"

#include <algorithm>
#include <cmath>
#include <string>

#include "capz/error.h"

namespace capz {

std::vector<uint64_t> read_negative_zeros(ByteReader* r, uint64_t total) {
  const uint64_t z = r->varint(), n = 3 * total;
  if (z > n)
    fail(ErrorCode::kCorrupt, r->what(),
         std::to_string(z) + " negative zeros in a window of " + std::to_string(total) + " points");
  std::vector<uint64_t> zeros;
  zeros.reserve(static_cast<size_t>(std::min<uint64_t>(z, r->remaining())));
  uint64_t next = 0;  // the least index the next entry may name
  for (uint64_t k = 0; k < z; ++k) {
    const uint64_t gap = r->varint();
    if (gap >= n - next)
      fail(ErrorCode::kCorrupt, r->what(),
           "negative zero beyond the window's " + std::to_string(total) + " points");
    zeros.push_back(next + gap);
    next = zeros.back() + 1;
  }
  return zeros;
}

void apply_negative_zeros(const std::vector<uint64_t>& zeros, const std::vector<uint8_t>& valid,
                          const std::string& what, std::vector<double>* xyz) {
  for (uint64_t j : zeros) {
    double& v = (*xyz)[static_cast<size_t>(j)];
    if (!valid[static_cast<size_t>(j / 3)] || v != 0 || std::signbit(v))
      fail(ErrorCode::kCorrupt, what,
           "negative zero listed for coordinate " + std::to_string(j) +
               ", which is a gap or not a decoded +0");
    v = -0.0;
  }
}

}  // namespace capz
