// The scan benchmark's frame files (tools/scan_bench): a sequence of frames, each a uint32 LE
// point count then count x 3 float32 LE (x y z). The harness writes them from the PCD frames
// (NaN points left out); the peer probes read them and write their decoded points the same way.
#pragma once

#include <cstdint>
#include <cstdio>
#include <ctime>
#include <stdexcept>
#include <string>
#include <vector>

namespace scan_bench {

using Frame = std::vector<float>;  // x y z per point

inline std::vector<Frame> read_frames(const std::string& path) {
  std::FILE* f = std::fopen(path.c_str(), "rb");
  if (!f) throw std::runtime_error(path + ": cannot open");
  std::vector<Frame> frames;
  unsigned char b[4];
  while (std::fread(b, 1, 4, f) == 4) {
    const uint32_t n = static_cast<uint32_t>(b[0]) | static_cast<uint32_t>(b[1]) << 8 |
                       static_cast<uint32_t>(b[2]) << 16 | static_cast<uint32_t>(b[3]) << 24;
    if (n > (1u << 28))
      throw std::runtime_error(path + ": frame of " + std::to_string(n) + " points");
    Frame fr(static_cast<size_t>(n) * 3);
    if (std::fread(fr.data(), 4, fr.size(), f) != fr.size()) {
      std::fclose(f);
      throw std::runtime_error(path + ": truncated frame");
    }
    frames.push_back(std::move(fr));
  }
  std::fclose(f);
  return frames;
}

inline void write_frames(const std::string& path, const std::vector<Frame>& frames) {
  std::FILE* f = std::fopen(path.c_str(), "wb");
  if (!f) throw std::runtime_error(path + ": cannot create");
  for (const Frame& fr : frames) {
    const uint32_t n = static_cast<uint32_t>(fr.size() / 3);
    const unsigned char b[4] = {static_cast<unsigned char>(n), static_cast<unsigned char>(n >> 8),
                                static_cast<unsigned char>(n >> 16),
                                static_cast<unsigned char>(n >> 24)};
    std::fwrite(b, 1, 4, f);
    std::fwrite(fr.data(), 4, fr.size(), f);
  }
  if (std::fclose(f) != 0) throw std::runtime_error(path + ": write failed");
}

// Writes a probe's decoded frames to `path` and prints its JSON line: the coded bytes and the
// CPU seconds of its encode and decode loops.
inline void finish(const std::string& path, const std::vector<Frame>& decoded, size_t bytes,
                   double encode_s, double decode_s) {
  write_frames(path, decoded);
  std::printf("{\"bytes\": %zu, \"encode_s\": %.6f, \"decode_s\": %.6f}\n", bytes, encode_s,
              decode_s);
}

// Process CPU seconds (user + system), the figure the probes report for one thread.
inline double cpu_seconds() {
  return static_cast<double>(std::clock()) / CLOCKS_PER_SEC;
}

}  // namespace scan_bench
