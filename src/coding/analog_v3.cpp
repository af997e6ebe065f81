// Decoder library (capz_decode): builds without PCL and without the transform encoders.
#include "coding/analog_v3.h"

#include <cmath>

#include "capz/error.h"
#include "coding/bytes.h"
#include "coding/entropy.h"
#include "coding/predict.h"
#include "coding/quantiser.h"

namespace capz {
namespace {
enum AnalogKind : uint8_t { kAnalogInt = 0, kAnalogFloat32 = 1, kAnalogFloat64 = 2 };

inline int32_t analog_predict(int pred, const int32_t* v, size_t k) {
  const int32_t a = k >= 1 ? v[k - 1] : 0, b = k >= 2 ? v[k - 2] : 0, c = k >= 3 ? v[k - 3] : 0;
  switch (pred) {
    case 0:
      return 0;
    case 1:
      return a;
    case 2:
      return wrap_sub(wrap_mul(a, 2), b);
    default:
      return wrap_add(wrap_mul(wrap_sub(a, b), 3), c);
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
    if (k == kAnalogInt &&
        !(v == std::floor(v) && std::fabs(v) < 2147483647.0 && !(v == 0 && std::signbit(v))))
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
      v[k] = kinds[c] == kAnalogInt ? static_cast<int32_t>(x)
                                    : float_to_ordered(static_cast<float>(x));
    }
    int best = 0;
    uint64_t best_cost = UINT64_MAX;
    for (int pred = 0; pred < 4; ++pred) {
      uint64_t cost = 0;
      for (size_t k = 0; k < nrows; ++k)
        cost += bit_cost(wrap_sub(v[k], analog_predict(pred, v.data(), k)));
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
      fail(ErrorCode::kCorrupt, what,
           "channel " + std::to_string(c) + ": unknown kind or predictor");
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
