// Raster frames, the decoding side (docs/FORMAT.md "Scans (format 1.1)", "Raster frames").
#include "coding/scan_raster.h"

namespace capz {
namespace scan {
namespace raster {

void read_pixels(IntDecoder* dec, const Header& h, Pixels* px) {
  px->delta = h.delta;
  px->v.assign(3 * size_t{h.pixels}, 0.0);
  const double unit = 1.0 / static_cast<double>(uint64_t{1} << h.exponent);  // exact
  int32_t prev[2][3] = {{0, 0, 0}, {0, 0, 0}};                               // V[p-1], V[p-2]
  for (size_t p = 0; p < h.pixels; ++p) {
    for (int a = 0; a < 3; ++a) {
      const int32_t pred = wrap_sub(wrap_add(prev[0][a], prev[0][a]), prev[1][a]);
      const int32_t v = wrap_add(pred, dec->get_signed(kCtxTable + a));
      prev[1][a] = prev[0][a];
      prev[0][a] = v;
      px->v[3 * p + static_cast<size_t>(a)] = static_cast<double>(v) * unit;
    }
  }
}

}  // namespace raster
}  // namespace scan
}  // namespace capz
