// The scan encoder's laser table inference (docs/FORMAT.md "Scans (format 1.1)").
#pragma once

#include <cstddef>
#include <vector>

#include "coding/scan_shared.h"

namespace capz {
namespace scan {

// The table of a window's points and every valid point's ring, column and range under it; an
// empty table (no rings) when none can be inferred. The azimuth step is the one found in the
// data divided by step_divisor (finer columns for sensors whose azimuths are not on one step).
Table infer_table(const ScanGeometry& g, const ScanHints& hints, double step_divisor,
                  std::vector<Polar>* polar);

// True when every valid point of points [first, first + n) may be coded spherically.
bool spherical_ok(const ScanGeometry& g, size_t first, size_t n);

}  // namespace scan
}  // namespace capz
