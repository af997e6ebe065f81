// ROTW's encoder (docs/FORMAT.md 12): the predictors of a window chosen by the residuals' bit
// lengths, then every value coded by the traversal the decoder (rotations.cpp) runs.
#include <algorithm>
#include <vector>

#include "coding/entropy.h"
#include "coding/rotations.h"
#include "coding/rotations_shared.h"

namespace capz {

namespace {

using namespace rotw;

// Per predictor, the residuals' bit lengths of the rotation elements and of the translation; the
// cheapest of each (the lowest on a tie).
void choose_predictors(const WindowBits& w, size_t samples, uint8_t* pr, uint8_t* pt) {
  uint64_t cost[kPredictors][2] = {};
  for (int p = 0; p < kPredictors; ++p)
    code_window(w, samples, p, p, [&](uint32_t pred, int role, size_t s, size_t g, int k) {
      const uint32_t v = w.get(s, g, k);
      if (role <= kTranslation)
        cost[p][role == kTranslation] += bit_cost(static_cast<int32_t>(residual(v, pred)));
      return v;
    });
  *pr = *pt = 0;
  for (uint8_t p = 1; p < kPredictors; ++p) {
    if (cost[p][0] < cost[*pr][0]) *pr = p;
    if (cost[p][1] < cost[*pt][1]) *pt = p;
  }
}

}  // namespace

std::vector<uint8_t> encode_rotations(const float* matrices, const float* reliability,
                                      size_t samples, size_t segments) {
  const WindowBits w{matrices, reliability, segments};
  uint8_t pr, pt;
  choose_predictors(w, samples, &pr, &pt);
  IntEncoder enc(kContexts);
  std::vector<int> tok(segments * kElements, 0);
  code_window(w, samples, pr, pt, [&](uint32_t pred, int role, size_t s, size_t g, int k) {
    const uint32_t v = w.get(s, g, k);
    int& t = tok[g * kElements + static_cast<size_t>(k)];
    t = enc.put(zigzag(static_cast<int32_t>(residual(v, pred))), context(role, t),
                escape_set(role));
    return v;
  });
  const std::vector<uint8_t> block = enc.finish();
  std::vector<uint8_t> out(2 + block.size());
  out[0] = pr;
  out[1] = pt;
  std::copy(block.begin(), block.end(), out.begin() + 2);
  return out;
}

}  // namespace capz
