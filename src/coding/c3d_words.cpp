// Decoder library (capz_decode): builds without PCL and without the transform encoders.
#include "coding/c3d_words.h"

#include <algorithm>
#include <cmath>
#include <cstring>

#include "capz/error.h"
#include "coding/bytes.h"
#include "coding/entropy.h"
#include "coding/predict.h"
#include "coding/quantiser.h"

namespace capz {
namespace {
inline float residual_from_grid(int32_t k, double scale) {
  return static_cast<float>(static_cast<double>(k) * scale);
}
}  // namespace

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

void decode_c3d_words(const uint8_t* data, size_t size, const uint8_t* valid, size_t count,
                      size_t points, double point_scale, float* residual, uint8_t* camera,
                      const std::string& what) {
  ByteReader r(data, size, what);
  const uint8_t mode = r.u8();
  // Format 1.0 has modes 2 (residuals on the grid) and 3 (their float bits), each with a repeat
  // flag per frame.
  if (mode < 2 || mode > 3)
    fail(ErrorCode::kCorrupt, what, "unknown residual mode " + std::to_string(mode));
  const bool bits = mode == 3;
  // A frame flag codes a whole frame.
  const size_t symbols = points > 0 ? (count + points - 1) / points : count;
  if (symbols > kMaxSymbolsPerByte * r.remaining())
    fail(ErrorCode::kCorrupt, what, "sample words cannot fit in the chunk");
  IntDecoder dec(data + 1, size - 1, 4, what);
  IntDecoder::Cursor c = dec.cursor();  // in registers for the loop (entropy.h)
  std::vector<int32_t> prev(points, 0), prev_d(points, 0);
  std::vector<uint8_t> prev_cam(points, 0);
  for (size_t i0 = 0; i0 < count; i0 += points) {  // frame by frame: p = i % points
    const size_t n = std::min(points, count - i0);
    int tok;
    const uint32_t flag = c.get(3, &tok);
    if (flag > 1) fail(ErrorCode::kCorrupt, what, "frame repeat flag out of range");
    if (flag == 1) {
      for (size_t p = 0, i = i0; p < n; ++p, ++i) {
        prev_d[p] = 0;
        residual[i] = bits       ? ordered_to_float(prev[p])
                      : valid[i] ? residual_from_grid(prev[p], point_scale)
                                 : -1.0f;
        camera[i] = prev_cam[p];
      }
      continue;
    }
    for (size_t p = 0, i = i0; p < n; ++p, ++i) {
      int32_t d = c.get_signed(prev_d[p] == 0 ? 1 : 0, &tok);
      int32_t v = wrap_add(prev[p], d);
      prev[p] = v;
      prev_d[p] = d;
      residual[i] = bits       ? ordered_to_float(v)
                    : valid[i] ? residual_from_grid(v, point_scale)
                               : -1.0f;
      uint32_t cam = c.get(2, &tok);
      if (cam > 255) fail(ErrorCode::kCorrupt, what, "camera byte out of range");
      camera[i] = static_cast<uint8_t>(cam ^ prev_cam[p]);
      prev_cam[p] = camera[i];
    }
  }
  dec.commit(c);
  if (!dec.at_end()) fail(ErrorCode::kCorrupt, what, "sample-word block has bytes past its end");
}

}  // namespace capz
