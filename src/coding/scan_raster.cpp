// Raster frames, the decoding side (docs/FORMAT.md "Scans (format 1.1)", "Raster frames").
#include "coding/scan_raster.h"

namespace capz {
namespace scan {
namespace raster {

namespace {

// The decoding Io of code_frame: values come from the block, actual ones are unused.
class DecodeIo {
 public:
  explicit DecodeIo(IntDecoder* dec) : dec_(dec) {}
  int32_t sym(int32_t, int32_t pred, int ctx) { return wrap_add(pred, dec_->get_signed(ctx)); }
  bool flag(bool, int ctx) {
    int tok;
    const uint32_t v = dec_->get(ctx, &tok);
    if (v > 1) dec_->corrupt("point validity flag is neither 0 nor 1");
    return v == 1;
  }
  bool actual_valid(size_t) const { return false; }
  const int32_t* actual(size_t) const { return zero_; }
  int32_t pixel_residual(size_t, int64_t) const { return 0; }
  int32_t rho(size_t) const { return 0; }
  int64_t check_pixel(int64_t p, size_t pixels) {
    if (p < 0 || static_cast<uint64_t>(p) >= pixels)
      dec_->corrupt("pixel outside the raster table");
    return p;
  }

 private:
  IntDecoder* dec_;
  int32_t zero_[3] = {0, 0, 0};
};

}  // namespace

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

void decode_frame(IntDecoder* dec, const Pixels& px, State* st, uint8_t flags, size_t n,
                  int32_t* q_out, uint8_t* valid_out) {
  DecodeIo io(dec);
  code_frame(io, px, *st, flags, 0, n, q_out, valid_out);
}

}  // namespace raster
}  // namespace scan
}  // namespace capz
