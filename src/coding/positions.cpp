// Decoder library (capz_decode): builds without PCL and without the transform encoders.
#include "coding/positions.h"

#include <algorithm>
#include <cstring>

#include "capz/error.h"
#include "coding/bytes.h"
#include "coding/entropy.h"
#include "coding/position_coders.h"
#include "coding/position_modes.h"
#include "coding/predict.h"

namespace capz {
namespace {

// The POSW payload after the window index and has_mask byte (3.3): codec block, predictor
// block, reference block (when a point uses one), period (when a point uses it), residuals.
std::vector<uint8_t> write_positions(const std::vector<uint8_t>& codec_payload, const ModeChoice& c,
                                     const std::vector<uint8_t>& residuals) {
  ByteWriter out;
  put_block(&out, codec_payload);
  put_block(&out, encode_ints(std::vector<int32_t>(c.modes.begin(), c.modes.end())));
  // Written from the modes (like the period below), so a point whose reference lost to a later
  // candidate leaves no entry.
  if (std::any_of(c.modes.begin(), c.modes.end(), [](uint8_t m) { return uses_ref(m); })) {
    std::vector<uint32_t> dist;
    for (size_t p = 0; p < c.modes.size(); ++p)
      if (uses_ref(c.modes[p])) dist.push_back(static_cast<uint32_t>(p - 1 - c.ref[p]));
    put_block(&out, encode_uints(dist));
  }
  if (std::any_of(c.modes.begin(), c.modes.end(), [](uint8_t m) { return uses_period(m); }))
    out.varint(c.period);
  out.bytes(residuals);
  return std::move(out.buffer());
}

}  // namespace

std::vector<uint8_t> encode_positions(const WindowInts& w,
                                      const std::vector<uint8_t>& codec_payload,
                                      const std::vector<int32_t>& tpred, bool float64,
                                      RayKind ray) {
  const size_t F = w.frames, N = w.points;
  std::vector<int32_t> q = w.q;  // gap entries get filled by the walks
  ResidualContexts ctx(N);
  const int32_t* t = tpred.empty() ? nullptr : tpred.data();
  if (float64) ray = RayKind::kNone;  // 7.1: not in mode 3
  const ModeChoice c = choose_modes(w, t, ctx, &q, ray);
  ctx.reset();
  IntEncoder enc(ResidualContexts::kCount);
  enc.skew_contexts();
  if (ray != RayKind::kNone) {
    encode_walk_ray(F, N, w.valid.data(), c.modes.data(), c.ref.data(), t, q.data(), ctx, enc,
                    c.period, ray);
  } else {
    EncCoder ec{enc.cursor(), ctx.cursor(), q.data(), float64 ? w.lo.data() : nullptr};
    walk_window(F, N, w.valid.data(), c.modes.data(), c.ref.data(), t, q.data(), ctx, ec, c.period);
    enc.commit(ec.enc);
  }
  return write_positions(codec_payload, c, enc.finish());
}

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
