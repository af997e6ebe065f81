// The float32 split's encoder (scan_split.h; docs/FORMAT.md "Lossless ragged streams").
#include <cmath>
#include <cstring>

#include "coding/entropy.h"
#include "coding/scan_split.h"

namespace capz {
namespace scan {

bool split_coordinates(const double* xyz, const uint8_t* valid, size_t n, int e, int64_t max_int,
                       std::vector<int32_t>* q, std::vector<uint32_t>* t) {
  q->assign(3 * n, 0);
  t->assign(3 * n, 0);
  for (size_t i = 0; i < n; ++i) {
    if (!valid[i]) continue;
    for (size_t a = 0; a < 3; ++a) {
      const double v = xyz[3 * i + a];
      const double r = std::floor(std::ldexp(v, e) + 0.5);  // v 2^E exact for |q| < 2^30
      if (!(std::fabs(r) < static_cast<double>(max_int))) return false;
      const int32_t qi = static_cast<int32_t>(r);
      uint32_t ti;
      if (qi == 0) {
        const float f = static_cast<float>(v);
        std::memcpy(&ti, &f, 4);
      } else {
        const int b = split_budget(qi, e);
        const double c = std::ldexp(v - std::ldexp(r, -e), e + b);  // exact: an integer
        ti = static_cast<uint32_t>(static_cast<int64_t>(c) + (b > 0 ? int64_t{1} << (b - 1) : 0));
      }
      (*q)[3 * i + a] = qi;
      (*t)[3 * i + a] = ti;
    }
  }
  return true;
}

std::vector<uint8_t> encode_split(int e, const std::vector<int32_t>& q,
                                  const std::vector<uint32_t>& t,
                                  const std::vector<uint8_t>& valid) {
  IntEncoder enc(kSplitContexts);
  IntEncoder::Cursor c = enc.cursor();
  for (size_t i = 0; i < valid.size(); ++i) {
    if (!valid[i]) continue;
    for (int a = 0; a < 3; ++a) {
      const size_t k = 3 * i + static_cast<size_t>(a);
      const int b = split_budget(q[k], e);
      if (b == 0) continue;
      const int h = b < 4 ? b : 4;
      c.put_symbol(static_cast<int>(t[k] >> (b - h)), 26 * a + (b > 25 ? 25 : b));
      if (b > h) c.raw_bits(t[k] & ((uint32_t{1} << (b - h)) - 1), b - h);
    }
  }
  enc.commit(c);
  return enc.finish();
}

}  // namespace scan
}  // namespace capz
