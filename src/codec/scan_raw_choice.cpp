// Raw windows for the ragged encoder (scan_raw_choice.h).
#include "codec/scan_raw_choice.h"

#include "capz/codec.h"
#include "coding/bytes.h"
#include "coding/scan_raw.h"

namespace capz {

static_assert(scan::kRawWindowKey == kRawWindowsKey, "raw windows' key in the reports");

std::vector<uint8_t> raw_scan_payload(size_t w, const FrameBlock& b, PosMode m,
                                      const std::string& source) {
  std::vector<uint32_t> counts;
  for (size_t k = 0; k < b.frames; ++k) counts.push_back(static_cast<uint32_t>(b.frame_points(k)));
  const size_t n = b.total_points();
  ByteWriter pw;
  pw.varint(w);
  pw.varint(n);
  pw.u8(scan::kRawWindowBit);  // gaps: no origin points
  std::vector<uint8_t> payload = std::move(pw.buffer());
  const std::vector<uint8_t> raw = scan::encode_raw_window(counts, b.xyz.data(), b.valid.data(), n,
                                                           m == PosMode::kFloat64 ? 8 : 4, source);
  payload.insert(payload.end(), raw.begin(), raw.end());
  return payload;
}

std::vector<int32_t> raw_scan_ints(const FrameBlock& b, PosMode m) {
  if (m == PosMode::kFloat64) return {};
  return scan::raw_window_ints(b.xyz, b.valid);
}

bool raw_may_win(const FrameBlock& b, size_t scan_bytes) {
  const size_t n = b.total_points();
  if (n == 0) return false;
  const size_t estimate = scan::raw_window_estimate(b.xyz.data(), b.valid.data(), n, 4);
  return estimate < scan_bytes;
}

}  // namespace capz
