// Lossless rotation-window coder (docs/FORMAT.md 12): per segment and sample, the bottom row and
// the reliability predicted by the previous sample, the translation by a temporal predictor, and
// the rotation part by what a rotation is: two elements of column 0 in time and the third from its
// unit norm, one element of column 1 in time and the other two from orthogonality and unit norm,
// column 2 as the cross product of the first two. Values and predictions are float32 bit patterns,
// mapped to ordered integers; their difference is coded with the hybrid-token integer coder. One
// traversal (code_sample, rotations_shared.h) drives estimate, encode and decode. This is the
// decoder; the encoder is rotations_encode.cpp.
#include "coding/rotations.h"

#include <algorithm>
#include <cfloat>
#include <cmath>
#include <cstring>
#include <limits>

#include "capz/error.h"
#include "coding/bytes.h"
#include "coding/entropy.h"
#include "coding/quantiser.h"
#include "coding/rotations_shared.h"

namespace capz {

using namespace rotw;

RotationClass rotation_class(int k) {
  if (k >= 16) return RotationClass::kReliability;
  const int row = k % 4, col = k / 4;
  if (row == 3) return RotationClass::kBottomRow;
  return col == 3 ? RotationClass::kTranslation : RotationClass::kRotation;
}

RotationWindow decode_rotations(const uint8_t* data, size_t size, size_t samples, size_t segments,
                                const std::string& what) {
  ByteReader r(data, size, what);
  uint8_t pred[2];
  for (uint8_t& p : pred) {
    p = r.u8();
    if (p >= kPredictors)
      throw Error(ErrorCode::kCorrupt, what + ": unknown predictor " + std::to_string(p));
  }
  const size_t block = r.remaining();
  const size_t per_sample = segments * kElements;
  if ((segments != 0 && per_sample / kElements != segments) ||
      (per_sample != 0 && samples > kMaxSymbolsPerByte * block / per_sample))
    throw Error(ErrorCode::kCorrupt, what + ": " + std::to_string(samples) + " samples x " +
                                         std::to_string(segments) + " segments cannot fit in " +
                                         std::to_string(block) + " bytes");
  RotationWindow out;
  out.matrices.resize(samples * segments * 16);
  out.reliability.resize(samples * segments);
  IntDecoder dec(data + r.offset(), block, kContexts, what);
  std::vector<int> tok(per_sample, 0);
  const WindowBits w{out.matrices.data(), out.reliability.data(), segments};
  code_window(w, samples, pred[0], pred[1], [&](uint32_t p, int role, size_t s, size_t g, int k) {
    int& t = tok[g * kElements + static_cast<size_t>(k)];
    const uint32_t res =
        static_cast<uint32_t>(dec.get_signed(context(role, t), &t, escape_set(role)));
    const uint32_t v = ordered(ordered(p) + res);
    const size_t i = s * segments + g;
    std::memcpy(k < 16 ? &out.matrices[i * 16 + static_cast<size_t>(k)] : &out.reliability[i], &v,
                4);
    return v;
  });
  if (!dec.at_end()) dec.corrupt("rotation block has bytes past its last value");
  return out;
}

}  // namespace capz
