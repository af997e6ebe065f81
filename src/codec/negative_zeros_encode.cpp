// Negative zeros of lossless mode 1 windows, the encoder's side (negative_zeros.h).
#include <cmath>

#include "codec/negative_zeros.h"

namespace capz {

void write_negative_zeros(const std::vector<double>& xyz, const std::vector<uint8_t>& valid,
                          ByteWriter* w) {
  std::vector<uint64_t> zeros;
  for (size_t j = 0; j < xyz.size(); ++j)
    if (valid[j / 3] && xyz[j] == 0 && std::signbit(xyz[j])) zeros.push_back(j);
  w->varint(zeros.size());
  uint64_t next = 0;
  for (uint64_t j : zeros) {
    w->varint(j - next);
    next = j + 1;
  }
}

}  // namespace capz
