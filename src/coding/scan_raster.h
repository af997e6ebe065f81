// Raster frames of the scan geometry payload (docs/FORMAT.md "Scans (format 1.1)", "Raster
// frames"): a sensor that fires a fixed set of directions (a flash or solid-state LiDAR) codes
// each point as a pixel of a table of direction vectors, a range in quanta (predicted by the
// previous point's or the pixel's last one) and x y z against the range along the pixel's vector.
//
// Floating-point use as scan_shared.h says: binary64 products and floor only, no FMA contraction.
#pragma once

#include <cstddef>
#include <cstdint>
#include <vector>

#include "coding/scan_shared.h"

namespace capz {
namespace scan {
namespace raster {

// Contexts (27 from kCtxRaster, FORMAT.md "Raster frames").
constexpr int kCtxTable = kCtxRaster;      // 3: the pixel vectors' axes
constexpr int kCtxPixel = kCtxRaster + 3;  // 2: previous pixel residual zero or not
constexpr int kCtxRange = kCtxRaster + 5;  // 16: the chosen predictor's recent error
constexpr int kCtxXyz = kCtxRaster + 21;   // 3 axes x 2: previous residual zero or not
static_assert(kCtxXyz + 6 == kCtxImage, "raster contexts end where the fraction-rule ones begin");

// The pixel table: P vectors (x y z, binary64, exact) and the range quantum.
struct Pixels {
  std::vector<double> v;  // 3 P
  double delta = 0;       // grid units per range quantum
  size_t count() const { return v.size() / 3; }
};

// The state raster frames keep from frame to frame.
struct State {
  explicit State(size_t pixels = 0) : range(pixels, 0), has(pixels, 0) {}
  std::vector<int32_t> range;  // M[p]
  std::vector<uint8_t> has;
  int32_t last = 0;  // L
  uint32_t score[2] = {0, 0};
  uint8_t z[3] = {0, 0, 0};
};

// The prediction of axis a of pixel p at range rho (quanta).
inline int32_t predict(const Pixels& px, size_t p, int a, int32_t rho) {
  const double w = static_cast<double>(rho) * px.delta;
  return round_clamp(w * px.v[3 * p + static_cast<size_t>(a)]);
}

// One raster frame's points. Io provides, as scan_shared.h's code_frame's:
//   int32_t sym(int32_t actual, int32_t pred, int ctx); bool flag(bool actual, int ctx);
//   bool actual_valid(size_t i);
// and int32_t pixel_residual(size_t i, int64_t pix), int64_t check_pixel(int64_t p, size_t P)
// (the decoder's checks the decoded pixel against the table), int32_t rho(size_t i,
// int32_t pred) (the range coded against the prediction pred; the encoder's may choose it
// then) and int32_t coord(size_t i, int a, int32_t h) (axis a's integer against h).
template <class Io>
void code_frame(Io& io, const Pixels& px, State& st, uint8_t flags, size_t first, size_t n,
                int32_t* q_out, uint8_t* valid_out) {
  const uint8_t vmode = flags & 3;
  bool prev_valid = true;
  int64_t pix = -1;
  int32_t prev_s = 1;
  for (size_t i = 0; i < n; ++i) {
    const bool v = point_valid(io, vmode, first + i, &prev_valid);
    valid_out[i] = v;
    int32_t* q = q_out + 3 * i;
    if (!v) {
      q[0] = q[1] = q[2] = 0;
      continue;
    }
    const int32_t s = io.sym(io.pixel_residual(first + i, pix), 0, kCtxPixel + (prev_s != 0));
    const int64_t p = io.check_pixel(pix + 1 + s, px.count());
    pix = p, prev_s = s;
    const auto pu = static_cast<size_t>(p);
    const int32_t c0 = st.last, c1 = st.has[pu] ? st.range[pu] : st.last;
    const int j = st.score[1] < st.score[0] ? 1 : 0;
    const int rctx = kCtxRange + std::min(bit_length(st.score[j] >> 1), 15);
    const int32_t pred = j ? c1 : c0;
    const int32_t rho = io.sym_plain(io.rho(first + i, pred), pred, rctx);
    scan::detail::score(&st.score[0], rho, c0);  // as the other frames' scores (scan_loop.h)
    scan::detail::score(&st.score[1], rho, c1);
    st.range[pu] = rho, st.has[pu] = 1, st.last = rho;
    for (int ax = 0; ax < 3; ++ax) {
      const int32_t h = predict(px, pu, ax, rho);
      q[ax] = io.sym(io.coord(first + i, ax, h), h, kCtxXyz + 2 * ax + st.z[ax]);
      st.z[ax] = q[ax] != h;
    }
  }
}

// Decoder (scan_raster.cpp): the pixel table at the block's start (h.pixels > 0); the frames
// with scan_decode.cpp's Io.
void read_pixels(IntDecoder* dec, const Header& h, Pixels* px);

// Encoder (scan_raster_encode.cpp): replaces *best by a raster payload of g when the window is
// a raster's (FORMAT.md, the encoder's note) and that payload is smaller. fine_q (when not null)
// gets the integers the decoder gives back from *best when it is a raster payload of fine shift
// above 0 (other integers than g's), else is left empty. moving (when not null) is set when the
// window's second frame did not repeat the directions of its first (a spinning sensor's), the
// quick test that ends the trial, and left as it is otherwise.
void keep_smaller(const ScanGeometry& g, const ScanHints& hints, std::vector<uint8_t>* best,
                  std::vector<int32_t>* fine_q = nullptr, bool* moving = nullptr);

}  // namespace raster
}  // namespace scan
}  // namespace capz
