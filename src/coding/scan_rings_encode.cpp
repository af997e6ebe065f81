// The encoder's ring check (scan_table.h, rings_differ; scan_geometry.h, scan_rings_differ):
// whether the rings found from the elevations are the ring field's.
#include <algorithm>
#include <cstddef>
#include <cstdint>
#include <vector>

#include "coding/scan_geometry.h"
#include "coding/scan_shared.h"
#include "coding/scan_table.h"
#include "coding/scan_trial_gates.h"

namespace capz {

namespace {

// Whether ring labels a (ka rings) and b (kb rings) give the valid points nearly the same
// rings, up to the rings' numbering: all but 1 % of them on the ring most of their ring's points
// have in the other labelling, both ways (a ring field and the elevations' rings of a sensor
// whose cones hold: the same).
bool same_rings(const std::vector<uint8_t>& valid_points, const std::vector<uint32_t>& a, size_t ka,
                const std::vector<uint32_t>& b, size_t kb) {
  if (ka == 0 || kb == 0 || ka * kb > (size_t{1} << 22)) return false;
  std::vector<uint32_t> pairs(ka * kb, 0);  // (a's ring, b's ring): points
  size_t valid = 0;
  for (size_t i = 0; i < valid_points.size(); ++i)
    if (valid_points[i]) ++valid, ++pairs[a[i] * kb + b[i]];
  std::vector<size_t> most_a(ka, 0), most_b(kb, 0);
  for (size_t i = 0; i < ka; ++i)
    for (size_t j = 0; j < kb; ++j) {
      most_a[i] = std::max<size_t>(most_a[i], pairs[i * kb + j]);
      most_b[j] = std::max<size_t>(most_b[j], pairs[i * kb + j]);
    }
  size_t agree_a = 0, agree_b = 0;
  for (size_t v : most_a) agree_a += v;
  for (size_t v : most_b) agree_b += v;
  return 100 * (valid - std::min(agree_a, agree_b)) <= valid;
}

// The quick ring check's share of the points: every kPeakStride-th.
constexpr size_t kPeakStride = 16;

// With ws remembering (a take's windows in turn), a window after one whose rings were the same is
// checked first on every kPeakStride-th point, on that window's elevation peaks: when those
// points' rings are the same, so are the window's (the elevation rings were 5 % of a pandar64
// folder's encode, the sensor's lasers the same in every window); else, and in every other
// window, on all its points and its own peaks.
}  // namespace

namespace scan {

// The geometry rings a decoder finds in `payload`, coded from g's points under the rings of
// `fit` (FORMAT.md predictor 13): in a spherical frame without cells or raster, each valid
// point's ring is its fit's (the loop codes the ring it is given); every other point has none.
std::vector<uint16_t> payload_rings(const ScanGeometry& g, const RingFit& fit,
                                    const std::vector<uint8_t>& payload) {
  const Header h = read_header(payload.data(), payload.size(), "scan geometry", SIZE_MAX);
  std::vector<uint16_t> rings(g.total(), ScanGeometry::kNoRing);
  size_t first = 0;
  for (size_t f = 0; f < h.counts.size(); ++f) {
    const uint8_t fl = h.flags[f];
    const size_t end = first + h.counts[f];
    if ((fl & kSpherical) && !(fl & (kCells | kRaster)) && end <= g.total() &&
        fit.polar.size() >= end)
      for (size_t i = first; i < end; ++i)
        if (g.valid[i]) rings[i] = static_cast<uint16_t>(fit.polar[i].ring);
    first = end;
  }
  return rings;
}

bool rings_differ(const ScanGeometry& g, const ScanHints& hints, FoundRings* found,
                  ScanWorkspace* ws) {
  std::vector<uint32_t> field, elevations;
  ws = ws && ws->remember ? ws : nullptr;  // one take's windows in order
  if (ws && !ws->ring_peaks.empty()) {
    std::vector<uint8_t> has;
    const size_t ka = placed_rings(g, hints, true, &field, found);
    const size_t kb = peak_rings(g, hints, ws->ring_peaks, kPeakStride, found, &elevations, &has);
    for (size_t j = 0; j < has.size(); ++j) field[j] = field[j * kPeakStride];
    field.resize(has.size());
    if (same_rings(has, field, ka, elevations, kb)) return false;
    ws->ring_peaks.clear();
  }
  // The rings alone (placed_rings), not the rest of two fits: a third of the instructions.
  const size_t kb = placed_rings(g, hints, false, &elevations, found);
  if (kb == 0) return false;
  const size_t ka = placed_rings(g, hints, true, &field, found);
  const bool differ = !same_rings(g.valid, field, ka, elevations, kb);
  if (ws && !differ) ws->ring_peaks = found->peaks;
  return differ;
}

}  // namespace scan

bool scan_rings_differ(const ScanGeometry& g, const ScanHints& hints) {
  return scan::rings_differ(g, hints, nullptr, nullptr);
}

namespace scan {

bool rings_run_downward(const ScanGeometry& g, const RingFit& fit) {
  if (fit.rings() < 2) return false;
  size_t up = 0, down = 0;
  const size_t valid = ring_passes(g.valid, fit.polar, fit.rings(), 0,
                                   std::min(g.valid.size(), fit.polar.size()), &up, &down);
  return up >= kWalkFlags * valid && down < kDownwardFlags * valid;
}

void flip_rings(const ScanGeometry& g, RingFit* fit) {
  const size_t K = fit->rings();
  if (K < 2) return;
  for (size_t i = 0; i < g.valid.size() && i < fit->polar.size(); ++i)
    if (g.valid[i]) fit->polar[i].ring = static_cast<uint32_t>(K - 1 - fit->polar[i].ring);
  std::reverse(fit->phi.begin(), fit->phi.end());
  std::reverse(fit->slope.begin(), fit->slope.end());
  std::reverse(fit->z0.begin(), fit->z0.end());
  std::reverse(fit->unit.begin(), fit->unit.end());
  std::reverse(fit->offset.begin(), fit->offset.end());
  std::reverse(fit->share.begin(), fit->share.end());
  std::reverse(fit->slot.begin(), fit->slot.end());
  fit->flipped = !fit->flipped;
}

}  // namespace scan
}  // namespace capz
