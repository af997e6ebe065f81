// ts codec, encode side — temporal segmentation (Luo, Cordier & Seo 2013) as a
// capz::TransformCodec: align ► cluster ► PCA per cluster ► quantise ► LPC (first fragment) / LCPS
// (later fragments). Options (TransformParams::options, documented in docs/CODEC-TS.md): lpc_order,
// lcps_k, basis_bits, basis_bits_min, basis_bits_max, basis_predict, basis_free_step, align,
// segments, segment_align, max_clusters, kmeans_restarts, seed,
// trunc_share, rms_per_bound.
#pragma once

#include <cstddef>
#include <cstdint>
#include <string>
#include <vector>

#include "codec/transform.h"
#include "codec/ts/ts_decoder.h"

namespace capz {

// What the last encode decided, for benchmarks and tests (not part of the payload contract).
struct TsEncodeReport {
  int clusters = 0;
  int segments = 0;             // point segments (1 = the paper's model)
  std::vector<int> pcs;         // PCs kept per (segment, cluster), segment-major
  std::vector<int> basis_bits;  // quantiser bits of every kept PC, in the order of pcs
  double coef_step = 0;
  std::vector<size_t> cluster_frames;
  std::vector<size_t> segment_points;
  double kg_target = 0;  // percent
  double kg_error = 0;   // percent, of the reconstruction returned
  size_t bytes = 0;
  int trials = 0;  // payloads built while searching
  double t_align = 0, t_segment = 0, t_cluster = 0, t_pca = 0, t_quant = 0, t_lcps = 0,
         t_total = 0;  // seconds
};

class TsCodec : public TransformCodec {
 public:
  static constexpr uint8_t kId = TsDecoder::kId;
  const TransformDecoder& decoder() const override { return decoder_; }
  void check_params(const TransformParams& params) const override;
  void encode(const PositionsView& in, const TransformParams& params, std::vector<uint8_t>* out,
              std::vector<double>* recon) const override;

  // encode() that also says what it chose.
  void encode_report(const PositionsView& in, const TransformParams& params,
                     std::vector<uint8_t>* out, std::vector<double>* recon,
                     TsEncodeReport* report) const;

 private:
  TsDecoder decoder_;
};

}  // namespace capz
