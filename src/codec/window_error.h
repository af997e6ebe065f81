// Encoder stage: squared errors of a window, for the KG checks of transform output (a window
// within the KG target makes the take meet it, docs/FORMAT.md 4.3). Shapes: fn frames x n points;
// a, b: fn x n x 3 coordinates; valid: fn x n.
#pragma once

#include <cstddef>
#include <cstdint>

namespace capz {

// Sum over valid samples of (a - b)^2. written_scale > 0: b as the C3D writer stores it at that
// int16 scale (rounded to its multiples), so the error of the written file.
double window_sq_error(size_t fn, size_t n, const double* a, const double* b, const uint8_t* valid,
                       double written_scale = 0);
// Sum over valid samples of the squared distance to their frame's centroid (metrics.h).
double centred_sq_window(size_t fn, size_t n, const double* x, const uint8_t* valid);

}  // namespace capz
