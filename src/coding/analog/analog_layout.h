// Which samples of a channel of an analog window are coded (its *kept* rows): all of them, those
// of the point frames not repeated (docs/FORMAT.md 11.3), an interpolation's anchors, tail and
// exceptions (11.4), or a hold's anchors and exceptions (11.5). A channel has at most one of the
// three; the others are rebuilt from the kept ones. Inter-channel references need the same kept
// rows on both sides (4.2.3.2, 7.2, 9.2, 9.4).
#pragma once

#include <cstddef>
#include <cstdint>
#include <string>
#include <vector>

#include "coding/analog/analog_hold.h"
#include "coding/analog/analog_interp.h"
#include "coding/analog/analog_repeat.h"

namespace capz {
namespace analog {

struct KeptRows {
  std::vector<uint32_t> repeats;  // the repeated point frames (7.2); empty: none
  Interp interp;                  // the interpolation (9.2); period 0: none
  Hold hold;                      // the hold (9.4); period 0: none

  bool all() const { return repeats.empty() && interp.period == 0 && hold.period == 0; }
  bool operator==(const KeptRows& o) const {
    return repeats == o.repeats && interp == o.interp && hold == o.hold;
  }
  bool operator!=(const KeptRows& o) const { return !(*this == o); }

  // The kept samples of a channel of n rows, S analog samples a point frame.
  size_t count(size_t n, size_t S) const {
    if (interp.period) return interp_kept_count(n, interp);
    return hold.period ? hold_kept_count(n, hold) : n - S * repeats.size();
  }
  // Those samples of col[0], col[stride], ... (n rows).
  std::vector<double> samples(const double* col, size_t stride, size_t n, size_t S) const {
    if (interp.period) return interp_kept(col, stride, n, interp);
    if (hold.period) return hold_kept(col, stride, n, hold);
    if (!repeats.empty()) return kept_samples(col, stride, n / S, S, repeats);
    std::vector<double> v(n);
    for (size_t i = 0; i < n; ++i) v[i] = col[i * stride];
    return v;
  }
  // The channel's n rows to col[0], col[stride], ... from its kept samples (not all()).
  // Throws Error(kCorrupt) naming `what` when an interpolation is NaN.
  void expand(const double* kept, size_t n, size_t S, double* col, size_t stride,
              const std::string& what) const {
    if (interp.period)
      expand_interp(kept, n, interp, col, stride, what);
    else if (hold.period)
      expand_hold(kept, n, hold, col, stride);
    else
      expand_repeats(kept, n / S, S, repeats, col, stride);
  }
};

}  // namespace analog
}  // namespace capz
