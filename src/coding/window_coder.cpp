#include "coding/window_coder.h"

#include <cmath>
#include <cstring>

#include "capz/error.h"
#include "coding/bytes.h"
#include "coding/entropy.h"
#include "coding/predict.h"

namespace capz {
namespace {

inline uint32_t bit_cost(int32_t r) {
  uint32_t u = zigzag(r);
  return u ? 33u - static_cast<uint32_t>(__builtin_clz(u)) : 0u;
}

struct CostCoder {
  const int32_t* q;
  size_t points;
  uint64_t* cost;  // per point
  int32_t operator()(size_t i, int32_t pred, int, int* tok) {
    cost[(i / 3) % points] += bit_cost(wrap_sub(q[i], pred));
    *tok = 0;
    return q[i];
  }
};

struct EncCoder {
  IntEncoder* enc;
  const int32_t* q;
  const uint32_t* lo;
  int32_t operator()(size_t i, int32_t pred, int ctx, int* tok) {
    *tok = enc->put_signed(wrap_sub(q[i], pred), ctx);
    if (lo) enc->raw_bits(lo[i], 32);
    return q[i];
  }
};

struct DecCoder {
  IntDecoder* dec;
  uint32_t* lo;
  int32_t operator()(size_t i, int32_t pred, int ctx, int* tok) {
    int32_t r = dec->get_signed(ctx, tok);
    if (lo) lo[i] = dec->raw_bits(32);
    return wrap_add(pred, r);
  }
};

void put_block(ByteWriter* w, const std::vector<uint8_t>& b) {
  w->varint(b.size());
  w->bytes(b);
}
const uint8_t* get_block(ByteReader* r, size_t* n, const char* name) {
  *n = static_cast<size_t>(r->count(1, name));
  return r->bytes(*n);
}

}  // namespace

std::vector<uint8_t> encode_positions(const WindowInts& w, const std::vector<uint8_t>& codec_payload,
                                      const std::vector<int32_t>& tpred, bool float64) {
  const size_t F = w.frames, N = w.points;
  std::vector<int32_t> q = w.q;  // gap entries get filled by the walks
  std::vector<uint8_t> tok(N * 3);
  std::vector<uint8_t> modes(N);
  const int32_t* t = tpred.empty() ? nullptr : tpred.data();
  // Predictor per point: the cheapest by an estimate of coded bits over the window.
  if (F > 1) {
    std::vector<uint64_t> best(N, UINT64_MAX), cost(N);
    const int nmodes = t ? kPredCount : kPredTransform;
    for (int m = 0; m < nmodes; ++m) {
      std::vector<uint8_t> mm(N, static_cast<uint8_t>(m));
      std::fill(cost.begin(), cost.end(), 0);
      CostCoder cc{q.data(), N, cost.data()};
      walk_window(F, N, w.valid.data(), mm.data(), t, q.data(), tok.data(), cc);
      for (size_t p = 0; p < N; ++p)
        if (cost[p] < best[p]) best[p] = cost[p], modes[p] = static_cast<uint8_t>(m);
    }
  } else if (t) {
    std::fill(modes.begin(), modes.end(), static_cast<uint8_t>(kPredTransform));
  }
  std::fill(tok.begin(), tok.end(), 0);
  IntEncoder enc(kPosContexts);
  EncCoder ec{&enc, q.data(), float64 ? w.lo.data() : nullptr};
  walk_window(F, N, w.valid.data(), modes.data(), t, q.data(), tok.data(), ec);

  ByteWriter out;
  put_block(&out, codec_payload);
  put_block(&out, encode_ints(std::vector<int32_t>(modes.begin(), modes.end())));
  out.bytes(enc.finish());
  return std::move(out.buffer());
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
                                  const std::string& what) {
  std::vector<int32_t> m = decode_ints(pp.modes, pp.modes_size, points, what + " predictors");
  std::vector<uint8_t> modes(points);
  for (size_t p = 0; p < points; ++p) {
    if (m[p] < 0 || m[p] >= kPredCount)
      fail(ErrorCode::kCorrupt, what, "unknown predictor " + std::to_string(m[p]));
    modes[p] = static_cast<uint8_t>(m[p]);
  }
  return modes;
}

void decode_positions(const PositionsPayload& pp, const std::vector<int32_t>& tpred, bool float64,
                      WindowInts* w, const std::string& what) {
  const size_t F = w->frames, N = w->points;
  std::vector<uint8_t> modes = decode_modes(pp, N, what);
  for (uint8_t m : modes)
    if ((m == kPredTransform || m == kPredTransformLinear) && tpred.size() != F * N * 3)
      fail(ErrorCode::kCorrupt, what, "a point uses the transform predictor but no codec ran");
  w->q.assign(F * N * 3, 0);
  if (float64) w->lo.assign(F * N * 3, 0);
  std::vector<uint8_t> tok(N * 3);
  IntDecoder dec(pp.residuals, pp.residuals_size, kPosContexts, what + " residuals");
  DecCoder dc{&dec, float64 ? w->lo.data() : nullptr};
  walk_window(F, N, w->valid.data(), modes.data(), tpred.empty() ? nullptr : tpred.data(),
              w->q.data(), tok.data(), dc);
  if (!dec.at_end()) fail(ErrorCode::kCorrupt, what, "residual block has bytes past its end");
}

// ---------------------------------------------------------------------------------------------
std::vector<uint8_t> encode_mask(const uint8_t* valid, size_t frames, size_t points) {
  IntEncoder enc(3);
  for (size_t p = 0; p < points; ++p) {
    size_t f = 0;
    bool first = true;
    bool want = true;  // runs start with a valid run
    while (f < frames) {
      size_t run = 0;
      while (f + run < frames && (valid[(f + run) * points + p] != 0) == want) ++run;
      enc.put(static_cast<uint32_t>(run), first ? 0 : want ? 2 : 1);
      first = false;
      want = !want;
      f += run;
    }
  }
  return enc.finish();
}

void decode_mask(const uint8_t* data, size_t size, size_t frames, size_t points, uint8_t* valid,
                 const std::string& what) {
  IntDecoder dec(data, size, 3, what);
  for (size_t p = 0; p < points; ++p) {
    size_t f = 0;
    bool first = true;
    bool want = true;
    while (f < frames) {
      uint32_t run = dec.get(first ? 0 : want ? 2 : 1);
      if (run > frames - f || (run == 0 && !first))
        fail(ErrorCode::kCorrupt, what, "gap-mask run of " + std::to_string(run) +
                                            " frames does not fit the window");
      for (size_t k = 0; k < run; ++k) valid[(f + k) * points + p] = want ? 1 : 0;
      f += run;
      first = false;
      want = !want;
    }
  }
  if (!dec.at_end()) fail(ErrorCode::kCorrupt, what, "gap-mask block has bytes past its end");
}

// ---------------------------------------------------------------------------------------------
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
    double k = std::round(static_cast<double>(r) / point_scale);
    if (!(std::fabs(k) < 2e9)) return false;
    float back = residual_from_grid(static_cast<int32_t>(k), point_scale);
    if (std::memcmp(&back, &r, 4) != 0) return false;
  }
  return true;
}

std::vector<uint8_t> encode_c3d_words(const float* residual, const uint8_t* camera,
                                      const uint8_t* valid, size_t count, size_t points,
                                      double point_scale, bool on_grid) {
  IntEncoder enc(3);
  std::vector<int32_t> prev(points, 0), prev_d(points, 0);
  std::vector<uint8_t> prev_cam(points, 0);
  for (size_t i = 0; i < count; ++i) {
    const size_t p = i % points;
    // Mode 0 gaps decode to -1 whatever is coded: repeat the previous value (difference 0).
    int32_t v = !on_grid  ? float_to_ordered(residual[i])
                : valid[i] ? static_cast<int32_t>(std::round(residual[i] / point_scale))
                           : prev[p];
    int32_t d = wrap_sub(v, prev[p]);
    enc.put_signed(d, prev_d[p] == 0 ? 1 : 0);
    prev[p] = v;
    prev_d[p] = d;
    enc.put(static_cast<uint32_t>(camera[i] ^ prev_cam[p]), 2);
    prev_cam[p] = camera[i];
  }
  ByteWriter w;
  w.u8(on_grid ? 0 : 1);
  w.bytes(enc.finish());
  return std::move(w.buffer());
}

void decode_c3d_words(const uint8_t* data, size_t size, const uint8_t* valid, size_t count,
                      size_t points, double point_scale, float* residual, uint8_t* camera,
                      const std::string& what) {
  ByteReader r(data, size, what);
  uint8_t mode = r.u8();
  if (mode > 1) fail(ErrorCode::kCorrupt, what, "unknown residual mode " + std::to_string(mode));
  if (count > kMaxSymbolsPerByte * r.remaining())
    fail(ErrorCode::kCorrupt, what, "sample words cannot fit in the chunk");
  IntDecoder dec(data + 1, size - 1, 3, what);
  std::vector<int32_t> prev(points, 0), prev_d(points, 0);
  std::vector<uint8_t> prev_cam(points, 0);
  for (size_t i = 0; i < count; ++i) {
    const size_t p = i % points;
    int32_t d = dec.get_signed(prev_d[p] == 0 ? 1 : 0);
    int32_t v = wrap_add(prev[p], d);
    prev[p] = v;
    prev_d[p] = d;
    residual[i] = mode == 1 ? ordered_to_float(v) : valid[i] ? residual_from_grid(v, point_scale) : -1.0f;
    uint32_t c = dec.get(2);
    if (c > 255) fail(ErrorCode::kCorrupt, what, "camera byte out of range");
    camera[i] = static_cast<uint8_t>(c ^ prev_cam[p]);
    prev_cam[p] = camera[i];
  }
  if (!dec.at_end()) fail(ErrorCode::kCorrupt, what, "sample-word block has bytes past its end");
}

// ---------------------------------------------------------------------------------------------
namespace {
enum AnalogKind : uint8_t { kAnalogInt = 0, kAnalogFloat32 = 1, kAnalogFloat64 = 2 };

inline int32_t analog_predict(int pred, const int32_t* v, size_t k) {
  const int32_t a = k >= 1 ? v[k - 1] : 0, b = k >= 2 ? v[k - 2] : 0, c = k >= 3 ? v[k - 3] : 0;
  switch (pred) {
    case 0: return 0;
    case 1: return a;
    case 2: return wrap_sub(wrap_mul(a, 2), b);
    default: return wrap_add(wrap_mul(wrap_sub(a, b), 3), c);
  }
}
}  // namespace

std::vector<uint8_t> analog_kinds(const std::vector<double>& values, int channels) {
  std::vector<uint8_t> kinds(static_cast<size_t>(channels), kAnalogInt);
  update_analog_kinds(values.data(), values.size(), channels, &kinds);
  return kinds;
}

void update_analog_kinds(const double* values, size_t count, int channels,
                         std::vector<uint8_t>* kinds) {
  const size_t C = static_cast<size_t>(channels);
  for (size_t i = 0; i < count; ++i) {
    const double v = values[i];
    uint8_t& k = (*kinds)[i % C];
    if (k == kAnalogInt && !(v == std::floor(v) && std::fabs(v) < 2147483647.0 &&
                             !(v == 0 && std::signbit(v))))
      k = kAnalogFloat32;
    if (k == kAnalogFloat32 && !is_float32(v)) k = kAnalogFloat64;
  }
}

std::vector<uint8_t> encode_analog(const double* rows, size_t nrows, int channels,
                                   const std::vector<uint8_t>& kinds) {
  ByteWriter w;
  const size_t C = static_cast<size_t>(channels);
  std::vector<int32_t> v(nrows), res(nrows);
  for (size_t c = 0; c < C; ++c) {
    w.u8(kinds[c]);
    if (kinds[c] == kAnalogFloat64) {
      w.u8(0);
      for (size_t k = 0; k < nrows; ++k) w.f64(rows[k * C + c]);
      continue;
    }
    for (size_t k = 0; k < nrows; ++k) {
      const double x = rows[k * C + c];
      v[k] = kinds[c] == kAnalogInt ? static_cast<int32_t>(x) : float_to_ordered(static_cast<float>(x));
    }
    int best = 0;
    uint64_t best_cost = UINT64_MAX;
    for (int pred = 0; pred < 4; ++pred) {
      uint64_t cost = 0;
      for (size_t k = 0; k < nrows; ++k) cost += bit_cost(wrap_sub(v[k], analog_predict(pred, v.data(), k)));
      if (cost < best_cost) best_cost = cost, best = pred;
    }
    for (size_t k = 0; k < nrows; ++k) res[k] = wrap_sub(v[k], analog_predict(best, v.data(), k));
    w.u8(static_cast<uint8_t>(best));
    put_block(&w, encode_ints(res));
  }
  return std::move(w.buffer());
}

void decode_analog(const uint8_t* data, size_t size, size_t nrows, int channels, double* rows,
                   const std::string& what) {
  ByteReader r(data, size, what);
  const size_t C = static_cast<size_t>(channels);
  std::vector<int32_t> v;
  for (size_t c = 0; c < C; ++c) {
    const uint8_t kind = r.u8();
    const uint8_t pred = r.u8();
    if (kind > kAnalogFloat64 || pred > 3)
      fail(ErrorCode::kCorrupt, what, "channel " + std::to_string(c) + ": unknown kind or predictor");
    if (kind == kAnalogFloat64) {
      if (nrows > r.remaining() / 8) fail(ErrorCode::kCorrupt, what, "truncated float64 channel");
      for (size_t k = 0; k < nrows; ++k) rows[k * C + c] = r.f64();
      continue;
    }
    size_t n;
    const uint8_t* b = get_block(&r, &n, "analog block length");
    v = decode_ints(b, n, nrows, what + " channel " + std::to_string(c));
    for (size_t k = 0; k < nrows; ++k) {
      v[k] = wrap_add(v[k], analog_predict(pred, v.data(), k));
      rows[k * C + c] = kind == kAnalogInt ? static_cast<double>(v[k])
                                           : static_cast<double>(ordered_to_float(v[k]));
    }
  }
  if (!r.at_end()) fail(ErrorCode::kCorrupt, what, "bytes after the last analog channel");
}

}  // namespace capz
