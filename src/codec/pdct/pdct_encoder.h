// Codec pdct, encode side: predictive-spectral coding in local frames (Amjoun & Strasser 2007,
// "Predictive- spectral compression of dynamic 3D meshes"), on point sequences without
// connectivity. The stages: seeds.h (seed triangles, kdtree.h), lcf.h (local frames), cluster.h
// (theta clustering), predict.h (closed loop shared by encoder and decoder), dct.h (DCT +
// quantiser). Options and bitstream: docs/CODEC-PDCT.md.
#pragma once

#include <cstddef>
#include <cstdint>
#include <string>
#include <vector>

#include "codec/pdct/pdct_decoder.h"
#include "codec/transform.h"

namespace capz {

// The codec's options (TransformParams::options keys in parentheses), resolved.
struct PdctOptions {
  // (mode) "grid": predictive coding on the bound layer's grid (needs a max error; exact on the
  // grid, no DCT); "dct": the paper's DCT path; "auto" (default): grid with a max error, else dct.
  std::string mode = "auto";
  double zero_share = 0;  // (zero_share) share of each block's DCT coefficients set to zero, [0, 1)
  int coef_bits = 12;     // (coef_bits) without --max-error: coefficient step = 2 M / 2^coef_bits,
                          // M = largest |coefficient| of an open-loop pass (the paper: 8-12)
  int first_bits = 12;    // (first_bits) without --max-error: frame-0 step = D / 2^first_bits
  int seed_bits = 16;     // (seed_bits) without --max-error: frame-point step = D / 2^seed_bits
  // With --max-error e the steps are factors of 2e (the bound layer's grid):
  double coef_factor = 1.0;   // (coef_factor)
  double first_factor = 1.0;  // (first_factor)
  double seed_factor = 0.5;   // (seed_factor)
  int seed_order =
      2;  // (seed_order) 1 = the paper's differential coding of frame points, 2 = linear
  int local_order = 1;        // (local_order) 1 = the paper's q~(f-1), 2 = 2 q~(f-1) - q~(f-2)
  size_t dct_block = 64;      // (dct_block) longest DCT along a cluster, 1..4096
  int knn = 12;               // (knn) neighbours examined for each seed triangle
  double min_angle_deg = 10;  // (min_angle_deg) triangle rejection, see seeds.h
  double min_edge = 1e-3;     // (min_edge) triangle rejection, share of the frame-0 diagonal
};

// Parses TransformParams::options; throws Error(kInvalidParameter) on an unknown key or a value
// out of range.
PdctOptions parse_pdct_options(const TransformParams& params);

// Cluster count used when TransformParams::clusters is 0: min(40, max(1, points / 8)).
size_t pdct_default_clusters(size_t points);

class PdctCodec : public TransformCodec {
 public:
  static constexpr uint8_t kId = PdctDecoder::kId;
  const TransformDecoder& decoder() const override { return decoder_; }
  void check_params(const TransformParams& params) const override { parse_pdct_options(params); }
  void encode(const PositionsView& in, const TransformParams& params, std::vector<uint8_t>* out,
              std::vector<double>* recon) const override;

 private:
  PdctDecoder decoder_;
};

// What encode() decided, for benchmarks and tests (filled by encode_pdct when non-null).
struct PdctReport {
  size_t clusters = 0;      // clusters with a local frame (triangle or identity)
  size_t frame_points = 0;  // triangle vertices, coded on the seed grid
  double seed_step = 0, first_step = 0, coef_step = 0;
  size_t payload_bytes = 0;
  size_t layout_bytes = 0;                                 // header + layout
  size_t seed_bytes = 0, first_bytes = 0, coef_bytes = 0;  // the three integer streams
  bool grid_mode = false;
  size_t predictors[4] = {0, 0, 0, 0};  // grid mode: points per PointPredictor kind
};

// encode() with its decisions reported.
void encode_pdct(const PositionsView& in, const TransformParams& params, std::vector<uint8_t>* out,
                 std::vector<double>* recon, PdctReport* report);

}  // namespace capz
