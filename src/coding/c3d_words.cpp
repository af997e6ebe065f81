// C3DW's decoder (docs/FORMAT.md 10); the encoder is c3d_words_encode.cpp.
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
