// POSW's decoder (docs/FORMAT.md 8): the payload parsed and the walks run with the decoder's
// coder; the encoder is positions_encode.cpp, the walks and predictors predict.h.
#include "coding/positions.h"

#include <algorithm>
#include <cstring>

#include "capz/error.h"
#include "coding/bytes.h"
#include "coding/entropy.h"
#include "coding/position_coders.h"
#include "coding/predict.h"

namespace capz {
PositionsPayload split_positions(const uint8_t* data, size_t size, const std::string& what) {
  ByteReader r(data, size, what);
  PositionsPayload pp;
  pp.codec_bytes = get_block(&r, &pp.codec_size, "codec payload length");
  pp.modes = get_block(&r, &pp.modes_size, "predictor block length");
  pp.residuals_size = r.remaining();
  pp.residuals = r.bytes(pp.residuals_size);
  return pp;
}

std::vector<uint8_t> decode_modes(const PositionsPayload& pp, size_t points,
                                  const std::string& what, RayKind ray) {
  std::vector<int32_t> m = decode_ints(pp.modes, pp.modes_size, points, what + " predictors");
  std::vector<uint8_t> modes(points);
  for (size_t p = 0; p < points; ++p) {
    if (m[p] < 0 || m[p] >= predictor_count(ray))
      fail(ErrorCode::kCorrupt, what, "unknown predictor " + std::to_string(m[p]));
    if (p == 0 && uses_ref(m[p]))
      fail(ErrorCode::kCorrupt, what, "point 0 uses a reference predictor");
    modes[p] = static_cast<uint8_t>(m[p]);
  }
  return modes;
}

void decode_positions(const PositionsPayload& pp, const std::vector<int32_t>& tpred, bool float64,
                      WindowInts* w, const std::string& what, RayKind ray) {
  const size_t F = w->frames, N = w->points;
  if (float64) ray = RayKind::kNone;  // 7.1: not in mode 3
  std::vector<uint8_t> modes = decode_modes(pp, N, what, ray);
  size_t nref = 0;
  bool any_period = false;
  for (uint8_t m : modes) {
    if ((m == kPredTransform || m == kPredTransformLinear) && tpred.size() != F * N * 3)
      fail(ErrorCode::kCorrupt, what, "a point uses the transform predictor but no codec ran");
    nref += uses_ref(m) ? 1 : 0;
    any_period = any_period || uses_period(m);
  }
  // The reference block, then the period, come first in the rest of the payload (3.3).
  ByteReader r(pp.residuals, pp.residuals_size, what);
  std::vector<uint32_t> ref(N, 0);
  if (nref > 0) {
    size_t n;
    const uint8_t* b = get_block(&r, &n, "reference block length");
    std::vector<uint32_t> dist = decode_uints(b, n, nref, what + " references");
    for (size_t p = 0, k = 0; p < N; ++p) {
      if (!uses_ref(modes[p])) continue;
      if (dist[k] > p - 1)
        fail(ErrorCode::kCorrupt, what,
             "point " + std::to_string(p) + " refers to point -" +
                 std::to_string(dist[k] - (p - 1)));
      ref[p] = static_cast<uint32_t>(p - 1 - dist[k++]);
    }
  }
  size_t period = 0;
  if (any_period) {
    const uint64_t T = r.varint();
    if (T < 1 || T >= F)
      fail(ErrorCode::kCorrupt, what,
           "period of " + std::to_string(T) + " frames in a window of " + std::to_string(F));
    period = static_cast<size_t>(T);
  }
  const size_t res_size = r.remaining();
  const uint8_t* res = r.bytes(res_size);
  w->q.assign(F * N * 3, 0);
  if (float64) w->lo.assign(F * N * 3, 0);
  ResidualContexts ctx(N);
  IntDecoder dec(res, res_size, ResidualContexts::kCount, what + " residuals");
  dec.skew_contexts();
  const int32_t* t = tpred.empty() ? nullptr : tpred.data();
  if (ray != RayKind::kNone) {
    decode_walk_ray(F, N, w->valid.data(), modes.data(), ref.data(), t, w->q.data(), ctx, dec,
                    period, ray);
  } else {
    DecCoder dc{dec.cursor(), ctx.cursor(), float64 ? w->lo.data() : nullptr};
    walk_window(F, N, w->valid.data(), modes.data(), ref.data(), t, w->q.data(), ctx, dc, period);
    dec.commit(dc.dec);
  }
  if (!dec.at_end()) fail(ErrorCode::kCorrupt, what, "residual block has bytes past its end");
}

}  // namespace capz
