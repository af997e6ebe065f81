// The float32 split's exponent of a lossless window and SCNW's bytes after `total`
// (scan_split_choice.h).
#include "codec/scan_split_choice.h"

#include <cmath>
#include <cstddef>
#include <cstdint>
#include <type_traits>
#include <utility>

#include "coding/bytes.h"
#include "coding/scan_split.h"

namespace capz {

namespace {

// The split exponents the encoder searches (FORMAT.md "Lossless ragged streams", informative):
// from kSplitStart, steps of kSplitStep within [kSplitLeast, kSplitMost] while the size falls,
// then the best one's neighbours, so at most one beyond either end (the warm start's steps of 1
// keep to the same [kSplitLeast - 1, kSplitMost + 1]). Most of the shared sweeps' best is 16 or 17.
constexpr int kSplitStart = 17, kSplitStep = 3, kSplitLeast = 8, kSplitMost = 23;

}  // namespace

std::vector<uint8_t> scan_body(const ScanGeometry& g, const ScanHints& hints, bool mode2, int e,
                               const std::vector<uint32_t>& t, ScanWorkspace* ws,
                               const std::vector<uint8_t>* coded, std::vector<uint8_t>* geo_out) {
  ByteWriter w;
  if (mode2) w.u8(static_cast<uint8_t>(static_cast<int8_t>(e)));
  const std::vector<uint8_t> geo = coded ? *coded : encode_scan_geometry(g, hints, ws);
  if (geo_out) *geo_out = geo;
  if (e != scan::kNoSplit) w.varint(geo.size());
  w.bytes(geo.data(), geo.size());
  if (e != scan::kNoSplit) {
    const std::vector<uint8_t> c = scan::encode_split(e, g.q, t, g.valid);
    w.bytes(c.data(), c.size());
  }
  return std::move(w.buffer());
}

int choose_split(const FrameBlock& b, const std::vector<uint32_t>& counts, const ScanHints& hints,
                 const std::vector<int32_t>& bits, int start, ScanWorkspace* ws) {
  ScanGeometry g;
  g.counts.assign(
      counts.begin(),
      counts.begin() + std::min<std::ptrdiff_t>(2, static_cast<std::ptrdiff_t>(counts.size())));
  size_t n = 0;
  for (uint32_t c : g.counts) n += c;
  const auto upto = [](const auto& v, size_t k) {
    return std::vector<typename std::decay_t<decltype(v)>::value_type>(
        v.begin(), v.begin() + static_cast<std::ptrdiff_t>(k));
  };
  g.valid = upto(b.valid, n);
  g.q = upto(bits, 3 * n);
  ScanHints h;
  if (!hints.ring.empty()) h.ring = upto(hints.ring, n);
  if (!hints.distance.empty()) h.distance = upto(hints.distance, n);
  h.xyz = upto(hints.xyz, 3 * n);
  int best = scan::kNoSplit;
  size_t best_size = scan_body(g, h, true, best, {}, ws).size();
  std::vector<uint32_t> t;
  // The size at exponent e (SIZE_MAX where it does not apply), the best kept.
  const auto trial = [&](int e) {
    if (!scan::split_coordinates(b.xyz.data(), g.valid.data(), n, e, kSplitLimit, &g.q, &t))
      return SIZE_MAX;
    h.grid_per_unit = std::ldexp(1.0, e);
    const size_t size = scan_body(g, h, true, e, t, ws).size();
    if (size < best_size) best = e, best_size = size;
    return size;
  };
  // From `from` in steps of `step`: down while the size falls, else up while it falls.
  const auto descend = [&](int from, int step) {
    const size_t mid = trial(from);
    for (int dir : {-step, step}) {
      size_t last = mid;
      bool fell = false;
      for (int e = from + dir; e >= kSplitLeast - 1 && e <= kSplitMost + 1; e += dir) {
        const size_t size = trial(e);
        if (size >= last) break;
        last = size;
        fell = true;
      }
      if (fell) break;
    }
  };
  if (start != scan::kNoSplit) {
    descend(start, 1);
    return best;
  }
  descend(kSplitStart, kSplitStep);
  if (best != scan::kNoSplit) {
    const int at = best;
    trial(at - 1);
    trial(at + 1);
  }
  return best;
}

}  // namespace capz
