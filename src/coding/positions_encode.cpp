// POSW's encoder (docs/FORMAT.md 8): the predictors chosen (position_modes.cpp), the walks run
// with the encoder's coder, the payload written; its decoder is positions.cpp.
#include <algorithm>

#include "coding/bytes.h"
#include "coding/entropy.h"
#include "coding/position_coders.h"
#include "coding/position_modes.h"
#include "coding/positions.h"
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

// The walks' raw bits alone (entropy.h: the bits below each residual's token, and a mode 3
// sample's low word), tokens as EncCoder gives them (they steer the contexts), nothing coded.
struct RawBitsCoder {
  const int32_t* q;
  bool lo;
  uint64_t bits = 0;
  int32_t operator()(size_t i, int32_t pred, int, int* tok) {
    int extra;
    *tok = token_of(zigzag(wrap_sub(q[i], pred)), &extra);
    bits += static_cast<uint64_t>(extra) + (lo ? 32u : 0u);
    return q[i];
  }
};

}  // namespace

std::vector<uint8_t> encode_positions_bound(const WindowInts& w,
                                            const std::vector<uint8_t>& codec_payload,
                                            const std::vector<int32_t>& tpred, bool float64,
                                            RayKind ray) {
  if (float64) ray = RayKind::kNone;  // 7.1: not in mode 3
  if (ray != RayKind::kNone) return encode_positions(w, codec_payload, tpred, float64, ray);
  const size_t F = w.frames, N = w.points;
  std::vector<int32_t> q = w.q;  // as encode_positions' walks
  ResidualContexts ctx(N);
  const int32_t* t = tpred.empty() ? nullptr : tpred.data();
  const ModeChoice c = choose_modes(w, t, ctx, &q, ray);
  ctx.reset();
  RawBitsCoder rc{q.data(), float64};
  walk_window(F, N, w.valid.data(), c.modes.data(), c.ref.data(), t, q.data(), ctx, rc, c.period);
  // The finished block holds the raw bits' bytes after the range coder's (IntEncoder::finish).
  return write_positions(codec_payload, c, std::vector<uint8_t>((rc.bits + 7) / 8));
}

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

}  // namespace capz
