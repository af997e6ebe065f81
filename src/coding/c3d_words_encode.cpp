// C3DW's encoder (docs/FORMAT.md 10): whether the residual words lie on the point scale's grid,
// and the words of a window as the decoder (c3d_words.cpp) reads them.
#include <algorithm>
#include <cmath>
#include <cstring>

#include "coding/bytes.h"
#include "coding/c3d_words.h"
#include "coding/entropy.h"
#include "coding/predict.h"
#include "coding/quantiser.h"

namespace capz {

bool residuals_on_grid(const std::vector<float>& residual, const std::vector<uint8_t>& valid,
                       double point_scale) {
  if (!(point_scale > 0) || valid.size() != residual.size()) return false;
  for (size_t i = 0; i < residual.size(); ++i) {
    const float r = residual[i];
    if (!valid[i]) {
      if (r != -1.0f) return false;
      continue;
    }
    double k = round_half_away(static_cast<double>(r) / point_scale);
    if (!(std::fabs(k) < 2e9)) return false;
    float back = residual_from_grid(static_cast<int32_t>(k), point_scale);
    if (std::memcmp(&back, &r, 4) != 0) return false;
  }
  return true;
}

std::vector<uint8_t> encode_c3d_words(const float* residual, const uint8_t* camera,
                                      const uint8_t* valid, size_t count, size_t points,
                                      double point_scale, bool on_grid) {
  IntEncoder enc(4);
  IntEncoder::Cursor c = enc.cursor();  // in registers for the loop (entropy.h)
  std::vector<int32_t> prev(points, 0), prev_d(points, 0), v(points);
  std::vector<uint8_t> prev_cam(points, 0);
  for (size_t i0 = 0; i0 < count; i0 += points) {  // frame by frame: p = i % points
    const size_t n = std::min(points, count - i0);
    bool repeat = true;
    for (size_t p = 0, i = i0; p < n; ++p, ++i) {
      // Mode 0 gaps decode to -1 whatever is coded: repeat the previous value (difference 0).
      v[p] = !on_grid   ? float_to_ordered(residual[i])
             : valid[i] ? static_cast<int32_t>(round_half_away(residual[i] / point_scale))
                        : prev[p];
      repeat = repeat && v[p] == prev[p] && camera[i] == prev_cam[p];
    }
    c.put(repeat ? 1 : 0, 3);
    if (repeat) {
      std::fill(prev_d.begin(), prev_d.begin() + static_cast<std::ptrdiff_t>(n), 0);
      continue;
    }
    for (size_t p = 0, i = i0; p < n; ++p, ++i) {
      const int32_t d = wrap_sub(v[p], prev[p]);
      c.put_signed(d, prev_d[p] == 0 ? 1 : 0);
      prev[p] = v[p];
      prev_d[p] = d;
      c.put(static_cast<uint32_t>(camera[i] ^ prev_cam[p]), 2);
      prev_cam[p] = camera[i];
    }
  }
  enc.commit(c);
  ByteWriter w;
  w.u8(static_cast<uint8_t>(on_grid ? 2 : 3));
  w.bytes(enc.finish());
  return std::move(w.buffer());
}

}  // namespace capz
