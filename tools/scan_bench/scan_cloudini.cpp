// Cloudini's per-cloud encoder as a scan benchmark peer (tools/scan_bench). Built out of the
// repository by build_peers.sh against Cloudini's library; never part of capz.
//
//   scan_cloudini IN.frames RESOLUTION OUT.frames
//
// Encodes every frame of IN.frames (frames_io.h) as one cloud: x y z float32, lossy at
// RESOLUTION (Cloudini's max error is half of it), zstd second stage, one thread; then decodes
// every cloud and writes the decoded points to OUT.frames in their order (Cloudini keeps it).
// Prints JSON: compressed bytes (each cloud's whole output, header included) and the CPU
// seconds of the encode and decode loops (file reading excluded).
#include <cstdio>
#include <cstdlib>
#include <cstring>
#include <ctime>
#include <exception>

#include "cloudini_lib/cloudini.hpp"
#include "frames_io.h"

int main(int argc, char** argv) {
  if (argc != 4) {
    std::fprintf(stderr, "usage: scan_cloudini IN.frames RESOLUTION OUT.frames\n");
    return 2;
  }
  try {
    const auto frames = scan_bench::read_frames(argv[1]);
    const float res = static_cast<float>(std::atof(argv[2]));
    Cloudini::EncodingInfo info;
    info.fields = {{"x", 0, Cloudini::FieldType::FLOAT32, res},
                   {"y", 4, Cloudini::FieldType::FLOAT32, res},
                   {"z", 8, Cloudini::FieldType::FLOAT32, res}};
    info.height = 1;
    info.point_step = 12;
    info.encoding_opt = Cloudini::EncodingOptions::LOSSY;
    info.compression_opt = Cloudini::CompressionOption::ZSTD;
    info.use_threads = false;

    std::vector<std::vector<uint8_t>> coded(frames.size());
    size_t bytes = 0;
    const double t0 = scan_bench::cpu_seconds();
    for (size_t f = 0; f < frames.size(); ++f) {
      info.width = static_cast<uint32_t>(frames[f].size() / 3);
      Cloudini::PointcloudEncoder enc(info);
      const auto* p = reinterpret_cast<const uint8_t*>(frames[f].data());
      enc.encode(Cloudini::ConstBufferView(p, frames[f].size() * 4), coded[f]);
      bytes += coded[f].size();
    }
    const double t1 = scan_bench::cpu_seconds();
    std::vector<scan_bench::Frame> out(frames.size());
    Cloudini::PointcloudDecoder dec;
    for (size_t f = 0; f < frames.size(); ++f) {
      Cloudini::ConstBufferView in(coded[f].data(), coded[f].size());
      const Cloudini::EncodingInfo got = Cloudini::DecodeHeader(in);
      std::vector<uint8_t> raw;
      dec.decode(got, in, raw);
      out[f].resize(raw.size() / 4);
      std::memcpy(out[f].data(), raw.data(), raw.size());
    }
    const double t2 = scan_bench::cpu_seconds();
    scan_bench::finish(argv[3], out, bytes, t1 - t0, t2 - t1);
  } catch (const std::exception& e) {
    std::fprintf(stderr, "scan_cloudini: %s\n", e.what());
    return 1;
  }
  return 0;
}
