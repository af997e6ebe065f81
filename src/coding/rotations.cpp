// Lossless rotation-window coder (docs/FORMAT.md 12): per element series, a
// temporal prediction made in float arithmetic, the value and the prediction mapped to ordered
// integers, their difference coded with the hybrid-token integer coder.
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

namespace capz {

namespace {

constexpr int kElements = 17;          // 16 matrix elements + reliability
constexpr int kContextsPerClass = 16;  // by the series' previous token
constexpr int kRotationContexts = kRotationClasses * kContextsPerClass;
constexpr int kPredictors = 3;

// float_to_ordered / ordered_to_float (quantiser.h) on the bits themselves, so no value is
// passed as a float on its way (a signalling NaN keeps its bits).
uint32_t ordered(uint32_t bits) {
  return bits & 0x80000000u ? bits ^ 0x7FFFFFFFu : bits;
}
uint32_t unordered(uint32_t q) {
  return ordered(q);
}  // the map is its own inverse

// The prediction's float32 bits from the series' previous values' bits a = v[s-1], b = v[s-2]
// (`have` of them exist). No arithmetic touches a non-finite value, so NaN payloads never
// depend on the machine.
uint32_t predict(RotationPredictor p, size_t have, uint32_t a, uint32_t b) {
  if (p == RotationPredictor::kNone || have == 0) return 0;
  const float fa = bits_float(a), fb = bits_float(b);
  if (p == RotationPredictor::kPrevious || have == 1 || !std::isfinite(fa) || !std::isfinite(fb))
    return a;
  const double d = 2.0 * static_cast<double>(fa) - static_cast<double>(fb);
  if (d > FLT_MAX) return float_bits(std::numeric_limits<float>::infinity());
  if (d < -FLT_MAX) return float_bits(-std::numeric_limits<float>::infinity());
  return float_bits(static_cast<float>(d));
}

// The context of a residual of class c after the series' previous token prev_tok.
int context(RotationClass c, int prev_tok) {
  return static_cast<int>(c) * kContextsPerClass + std::min(prev_tok, kContextsPerClass - 1);
}

int escape_set(RotationClass c) {
  return c == RotationClass::kRotation ? 0 : c == RotationClass::kTranslation ? 1 : 2;
}

// Where element k of segment g at sample s lives, as float32 bits.
struct WindowBits {
  const float* matrices;
  const float* reliability;
  size_t segments;
  uint32_t get(size_t s, size_t g, int k) const {
    const size_t i = s * segments + g;
    uint32_t u;
    std::memcpy(&u, k < 16 ? &matrices[i * 16 + static_cast<size_t>(k)] : &reliability[i], 4);
    return u;
  }
};

// The residual of value (s, g, k): ordered value minus ordered prediction, wrapping.
uint32_t residual(const WindowBits& w, RotationPredictor p, size_t s, size_t g, int k) {
  const uint32_t a = s >= 1 ? w.get(s - 1, g, k) : 0, b = s >= 2 ? w.get(s - 2, g, k) : 0;
  return ordered(w.get(s, g, k)) - ordered(predict(p, s, a, b));
}

// Calls f(s, g, k, class of k, &token of the series' previous residual) for every value in coding
// order: sample by sample, segment by segment, element by element (the token starts at 0).
template <typename F>
void in_coding_order(size_t samples, size_t segments, F f) {
  std::vector<int> prev_tok(segments * kElements, 0);
  for (size_t s = 0; s < samples; ++s)
    for (size_t g = 0; g < segments; ++g)
      for (int k = 0; k < kElements; ++k)
        f(s, g, k, rotation_class(k), &prev_tok[g * kElements + static_cast<size_t>(k)]);
}

// Per class, the predictor whose residuals have the fewest significant bits in total.
void choose_predictors(const WindowBits& w, size_t samples, RotationPredictor* out) {
  uint64_t cost[kRotationClasses][kPredictors] = {};
  for (size_t s = 0; s < samples; ++s)
    for (size_t g = 0; g < w.segments; ++g)
      for (int k = 0; k < kElements; ++k)
        for (int p = 0; p < kPredictors; ++p) {
          const uint32_t u =
              zigzag(static_cast<int32_t>(residual(w, static_cast<RotationPredictor>(p), s, g, k)));
          cost[static_cast<int>(rotation_class(k))][p] +=
              static_cast<uint64_t>(32 - __builtin_clz(u | 1));
        }
  for (int c = 0; c < kRotationClasses; ++c) {
    int best = 0;
    for (int p = 1; p < kPredictors; ++p)
      if (cost[c][p] < cost[c][best]) best = p;
    out[c] = static_cast<RotationPredictor>(best);
  }
}

}  // namespace

RotationClass rotation_class(int k) {
  if (k >= 16) return RotationClass::kReliability;
  const int row = k % 4, col = k / 4;
  if (row == 3) return RotationClass::kBottomRow;
  return col == 3 ? RotationClass::kTranslation : RotationClass::kRotation;
}

std::vector<uint8_t> encode_rotations(const float* matrices, const float* reliability,
                                      size_t samples, size_t segments) {
  const WindowBits w{matrices, reliability, segments};
  RotationPredictor pred[kRotationClasses];
  choose_predictors(w, samples, pred);
  IntEncoder enc(kRotationContexts);
  in_coding_order(samples, segments, [&](size_t s, size_t g, int k, RotationClass c, int* tok) {
    const uint32_t r = residual(w, pred[static_cast<int>(c)], s, g, k);
    *tok = enc.put(zigzag(static_cast<int32_t>(r)), context(c, *tok), escape_set(c));
  });
  const std::vector<uint8_t> block = enc.finish();
  std::vector<uint8_t> out(kRotationClasses + block.size());
  for (int c = 0; c < kRotationClasses; ++c)
    out[static_cast<size_t>(c)] = static_cast<uint8_t>(pred[c]);
  std::copy(block.begin(), block.end(), out.begin() + kRotationClasses);
  return out;
}

RotationWindow decode_rotations(const uint8_t* data, size_t size, size_t samples, size_t segments,
                                const std::string& what) {
  ByteReader r(data, size, what);
  RotationPredictor pred[kRotationClasses];
  for (RotationPredictor& p : pred) {
    const uint8_t v = r.u8();
    if (v >= kPredictors)
      throw Error(ErrorCode::kCorrupt, what + ": unknown predictor " + std::to_string(v));
    p = static_cast<RotationPredictor>(v);
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
  IntDecoder dec(data + r.offset(), block, kRotationContexts, what);
  const WindowBits w{out.matrices.data(), out.reliability.data(), segments};
  in_coding_order(samples, segments, [&](size_t s, size_t g, int k, RotationClass c, int* tok) {
    const uint32_t res =
        static_cast<uint32_t>(dec.get_signed(context(c, *tok), tok, escape_set(c)));
    const uint32_t a = s >= 1 ? w.get(s - 1, g, k) : 0, b = s >= 2 ? w.get(s - 2, g, k) : 0;
    const uint32_t v = unordered(ordered(predict(pred[static_cast<int>(c)], s, a, b)) + res);
    const size_t i = s * segments + g;
    std::memcpy(k < 16 ? &out.matrices[i * 16 + static_cast<size_t>(k)] : &out.reliability[i], &v,
                4);
  });
  if (!dec.at_end()) dec.corrupt("rotation block has bytes past its last value");
  return out;
}

}  // namespace capz
