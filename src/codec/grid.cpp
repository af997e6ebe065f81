// The grid shared by encoder and decoder (grid.h). Part of the decoder library.
#include "codec/grid.h"

namespace capz {

const char* mode_name(PosMode m) {
  switch (m) {
    case PosMode::kGrid:
      return "grid";
    case PosMode::kDecimal:
      return "decimal-grid";
    case PosMode::kFloat32:
      return "float32-bits";
    case PosMode::kFloat64:
      return "float64-bits";
    case PosMode::kFloat32Grid:
      return "float32-grid";
  }
  return "?";
}

void dequantise_all(const Grid& g, const WindowInts& wi, std::vector<double>* rec) {
  const size_t n = wi.frames * wi.points * 3;
  rec->resize(n);
  double* out = rec->data();
  const int32_t* q = wi.q.data();
  const uint32_t* lo = g.mode == PosMode::kFloat64 ? wi.lo.data() : nullptr;
  with_mode(g.mode, [&](auto m) {
    for (size_t k = 0; k < n; ++k)
      out[k] = dequantise_as<decltype(m)::value>(g, q[k], lo ? lo[k] : 0);
  });
}

std::vector<int32_t> grid_prediction(const std::vector<double>& recon, double step) {
  std::vector<int32_t> t(recon.size());
  for (size_t i = 0; i < recon.size(); ++i) {
    double v = recon[i] / step;
    if (!(v >= -kMaxGridIndex)) v = -kMaxGridIndex;  // also NaN
    if (v > kMaxGridIndex) v = kMaxGridIndex;
    t[i] = round_to_int(v);
  }
  return t;
}

}  // namespace capz
