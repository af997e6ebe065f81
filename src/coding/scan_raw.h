// Raw windows of a lossless ragged stream (docs/FORMAT.md "Raw windows"): a window's
// coordinates kept as their float32 (mode 2) or float64 (mode 3) bits, point after point, in
// one raw LZMA2 stream, where the scan geometry payload would cost more (a cloud without a
// sweep's geometry) or cannot hold them (float64 on no decimal grid).
#pragma once

#include <cstddef>
#include <cstdint>
#include <map>
#include <string>
#include <vector>

#include "coding/scan_split.h"

namespace capz {
namespace scan {

// SCNW's gaps byte: bit 0, origin points; bit 1, a raw window.
constexpr uint8_t kOriginGapsBit = 1, kRawWindowBit = 2;

// A raw window decoded: its frames' counts, each point's validity (1: its three values are
// finite) and coordinates (3 per point, 0 at gaps).
struct RawWindow {
  std::vector<uint32_t> counts;
  std::vector<uint8_t> valid;
  std::vector<double> xyz;
};

// Decodes the rest of a raw window's SCNW payload (after its gaps byte): `frames` counts that
// sum to `total`, then the LZMA2 stream of 3 x `bytes` x total bytes (`bytes` 4 or 8). Throws
// Error(kCorrupt) naming `what` on another frame count, counts that do not sum to `total`, or a
// stream that does not decode to exactly those bytes. The caller has bounded `total`.
RawWindow decode_raw_window(const uint8_t* data, size_t size, const std::string& what,
                            size_t frames, uint64_t total, int bytes);

// The frame counts at the start of a raw window's payload (after its gaps byte), unchecked.
// Throws Error(kCorrupt) naming `what` when the bytes end first.
std::vector<uint64_t> raw_frame_counts(const uint8_t* data, size_t size, const std::string& what);

// The key of raw windows in CompressStats / StreamInfo::float32_split_windows (split exponents
// are kNoSplit or -64..64).
constexpr int kRawWindowKey = -127;

// Whether windows counted by split exponent (the keys: kNoSplit, kRawWindowKey or an exponent) have
// a float32 split.
inline bool has_split_windows(const std::map<int, size_t>& windows) {
  for (const auto& kv : windows)
    if (kv.first != kRawWindowKey && kv.first != kNoSplit && kv.second > 0) return true;
  return false;
}

// A mode 2 raw window's grid integers for ATTR (FORMAT.md "Raw windows"): each valid
// coordinate's float32 ordered integer, 0 at gaps (3 per point).
std::vector<int32_t> raw_window_ints(const std::vector<double>& xyz,
                                     const std::vector<uint8_t>& valid);

// Encoder side (scan_raw_encode.cpp). The payload after the gaps byte for the window of
// `counts` (summing to n) whose n points are xyz (3 per point) and valid: each valid point's
// three values as float32 (bytes 4; each must be one) or float64 (bytes 8) bits, each gap three
// quiet NaN. Throws Error(kInternal) naming `source` when a valid value is not finite.
std::vector<uint8_t> encode_raw_window(const std::vector<uint32_t>& counts, const double* xyz,
                                       const uint8_t* valid, size_t n, int bytes,
                                       const std::string& source);

// An estimate of encode_raw_window's size for those points, from liblzma's quick coding of
// the first points (at most 16,384) scaled to n: 15 % above it on a depth camera's and on LiDAR
// sweeps (docs/lab/2026-11-30-raw-windows.md).
size_t raw_window_estimate(const double* xyz, const uint8_t* valid, size_t n, int bytes);

}  // namespace scan
}  // namespace capz
