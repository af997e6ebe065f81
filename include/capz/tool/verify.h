// NOT PART OF THE STABLE API (include/capz/tool/): what the capz CLI and the Python module share
// so that they behave alike. Installed for programs that want the CLI's exact behaviour, but it
// may change in any release; the stable API is the headers of include/capz/ itself.
// capz — does a decoded .capz keep its promise? The one rule used by `capz verify --against`,
// the check after writing (`capz compress --rm`) and the tests.
//
// A stream promises, for the take it was made from (the "original"):
//   - the shape (frames, points) and the gap mask exactly;
//   - every valid coordinate as its header says (Promise below): bit-identical (lossless), within
//     the stored per-coordinate bound, or, for a transform-output stream (FORMAT.md 4.3, a KG
//     target and no bound), finite with the KG error over the whole take at most its target;
//   - the rotations (layout, rate, labels, and every sample bit for bit: NaN payloads count);
//   - rate, units, first frame, labels, descriptions, analog layout and values, and the format
//     extras a .capz keeps (C3D parameter section, header fields and events, residual/camera
//     words; TRC time and frame columns; PCD frame names) exactly (NaN equals NaN).
// Gap samples' coordinates are never compared (take.h: unspecified by contract).
#pragma once

#include <string>
#include <vector>

#include "capz/codec.h"
#include "capz/metrics.h"
#include "capz/stream.h"
#include "capz/take.h"

namespace capz {

// What a stream promises about its positions, read from its header.
struct Promise {
  enum class Kind { kLossless, kBound, kKgTarget };
  Kind kind = Kind::kLossless;
  double max_error = 0;  // kBound: per-coordinate bound, in the take's units
  double kg_target = 0;  // kKgTarget: KG error target in percent (metrics.h)
  // Per point field (Take::attributes): 0 when it comes back byte for byte, else the bound its
  // float values (float_size 4 or 8 bytes) come back within; NaN and infinities exactly.
  std::vector<double> attribute_bounds;
  std::vector<int> attribute_float_size;
  // Per analog channel (FORMAT.md 5.7), empty when every channel comes back exactly: the bound
  // in physical units (0: exact) and the factor from stored to physical units.
  std::vector<double> analog_bounds, analog_factors;
  // Each frame's points were reordered by the encoder (--point-order any, FORMAT.md "Points
  // reordered"): the original's points are paired with the decoded ones as sets, frame by frame,
  // before the check (metrics/point_match.h); a point without a partner is a breach.
  bool points_reordered = false;
};
Promise promise_of(const StreamInfo& info);

struct PromiseResult;

// Checks a decoded take against its original piece by piece, so a long take is checked a block
// of frames at a time: header() once, frames() for consecutive blocks covering the take, then
// finish(). Every call returns holds(); the first breach found is kept in why() (later ones are
// not), and the error measures go on accumulating over every block given.
class PromiseCheck {
 public:
  explicit PromiseCheck(const Promise& promise) : promise_(promise) {}
  // measure = false: the rule only, no error measures (error() stays empty, and finish() has no
  // KG error to hold to a KG target): for a caller that measures the same samples itself (the
  // encoder's self-check, whose decoded samples must equal its own reconstruction).
  PromiseCheck(const Promise& promise, bool measure) : promise_(promise), measure_(measure) {}
  // Everything but the per-frame arrays (FrameSource::header()).
  bool header(const Take& original, const Take& decoded);
  // One block of frames; `decoded` must cover the same frames as `original`.
  bool frames(const FrameBlock& original, const FrameBlock& decoded);
  // Checks what needs the whole take (the KG target). Call once, after the last block.
  bool finish();

  bool holds() const { return why_.empty(); }
  // "" while the promise holds, else the first breach, e.g. "coordinate 12.5 at frame 3, point
  // 7 comes back as 12.7 (bound 0.1)".
  const std::string& why() const { return why_; }
  // The measures (metrics.h) over the blocks given so far, mask_mismatches included.
  ErrorStats error() const;
  // PromiseResult::analog_bound_use over the blocks given so far.
  double analog_bound_use() const { return analog_bound_use_; }

 private:
  struct Frames;  // the per-frame arrays of a block or a whole take (promise.cpp)
  friend PromiseResult check_promise(const Take&, const Take&, const Promise&);
  bool breach(const std::string& what);
  bool check(const Frames& original, const Frames& decoded);
  bool positions(const Frames& original, const Frames& decoded);
  bool analog(const Frames& original, const Frames& decoded);

  Promise promise_;
  std::string why_;
  double analog_bound_use_ = 0;
  bool measure_ = true;
  ErrorAccumulator acc_;
  size_t mask_mismatches_ = 0;
};

struct PromiseResult {
  bool holds = false;
  std::string why;   // "" when it holds
  ErrorStats error;  // as compare(original, decoded) when the shapes agree
  // Over the lossy analog channels (FORMAT.md 5.7): the largest error as a fraction of its
  // channel's bound (0 without such channels).
  double analog_bound_use = 0;
};
// The whole check on two whole takes (in memory).
PromiseResult check_promise(const Take& original, const Take& decoded, const Promise& promise);

}  // namespace capz
