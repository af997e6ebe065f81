// The window encoder's choice between a channel's candidate representations (FORMAT.md 11
// leaves it to the encoder): each candidate is coded alone, and the smallest kept, the first
// (lowest index) of equals.
#pragma once

#include <algorithm>
#include <cstddef>
#include <cstdint>
#include <numeric>
#include <vector>

namespace capz {
namespace analog {

// Index of the smallest candidate, the first of equals. trial(k, bound) codes candidate k and
// returns its size, or SIZE_MAX once it knows that size is at least `bound` (it may stop
// there). The candidates are tried in increasing order of `estimate` (any guess of their
// sizes; ties in index order): when the guess is right, the first trial is the smallest and
// every later one stops as soon as it passes it. The result is the same for any estimate: a
// candidate after the current pick must be smaller to win (bound = the best size), one before
// it only as small (bound = best + 1).
//
// With a `margin` (> 0), a candidate whose estimate is above margin times the smallest is not
// tried at all, and when one candidate is left it is the pick without a trial: an estimate
// decides where it is far from close (the pick may then differ from the measured smallest).
template <typename Trial>
size_t pick_smallest(const std::vector<double>& estimate, Trial trial, double margin = 0) {
  const size_t n = estimate.size();
  std::vector<size_t> order(n);
  std::iota(order.begin(), order.end(), size_t{0});
  std::stable_sort(order.begin(), order.end(),
                   [&](size_t a, size_t b) { return estimate[a] < estimate[b]; });
  if (margin > 0 && n > 0) {
    const double cut = margin * estimate[order[0]];
    while (order.size() > 1 && estimate[order.back()] > cut) order.pop_back();
    if (order.size() == 1) return order[0];
  }
  size_t pick = n, best = SIZE_MAX;
  for (size_t k : order) {
    const size_t bound = pick == n ? SIZE_MAX : k < pick ? best + 1 : best;
    const size_t size = trial(k, bound);
    if (size == SIZE_MAX) continue;
    if (pick == n || size < best || (size == best && k < pick)) {
      best = size;
      pick = k;
    }
  }
  return pick == n ? 0 : pick;
}

}  // namespace analog
}  // namespace capz
