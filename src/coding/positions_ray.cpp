// The POSW decoder's walks of streams that may hold predictor 10 (position_coders.h); the
// encoder's are positions_ray_encode.cpp.
#include "coding/position_coders.h"

namespace capz {

void decode_walk_ray(size_t frames, size_t points, const uint8_t* valid, const uint8_t* modes,
                     const uint32_t* ref, const int32_t* t, int32_t* q, ResidualContexts& contexts,
                     IntDecoder& dec, size_t period, RayKind ray) {
  DecCoder dc{dec.cursor(), contexts.cursor(), nullptr, ray};
  walk_window_ray(frames, points, valid, modes, ref, t, q, contexts, dc, period);
  dec.commit(dc.dec);
}

}  // namespace capz
