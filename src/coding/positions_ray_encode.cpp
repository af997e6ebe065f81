// The POSW encoder's walks of streams that may hold predictor 10 (position_coders.h), in a
// translation unit of their own as the decoder's are (positions_ray.cpp).
#include "coding/position_coders.h"

namespace capz {

void encode_walk_ray(size_t frames, size_t points, const uint8_t* valid, const uint8_t* modes,
                     const uint32_t* ref, const int32_t* t, int32_t* q, ResidualContexts& contexts,
                     IntEncoder& enc, size_t period, RayKind ray) {
  EncCoder ec{enc.cursor(), contexts.cursor(), q, nullptr, ray};
  walk_window_ray(frames, points, valid, modes, ref, t, q, contexts, ec, period);
  enc.commit(ec.enc);
}

}  // namespace capz
