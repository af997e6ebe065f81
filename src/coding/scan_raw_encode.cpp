// Raw windows encoded (scan_raw.h; docs/FORMAT.md "Raw windows").
#include <algorithm>
#include <cmath>

#include "capz/error.h"
#include "coding/bytes.h"
#include "coding/lzma_block.h"
#include "coding/quantiser.h"
#include "coding/scan_raw.h"

namespace capz {
namespace scan {

namespace {

// The first n points' bits, point after point (FORMAT.md "Raw windows"): a gap as three quiet
// NaN. Throws Error(kInternal) naming `source` when a valid value is not finite.
std::vector<uint8_t> raw_bits(const double* xyz, const uint8_t* valid, size_t n, int bytes,
                              const std::string& source) {
  ByteWriter w;
  w.buffer().reserve(n * 3 * static_cast<size_t>(bytes));
  for (size_t i = 0; i < 3 * n; ++i) {
    const double v = xyz[i];
    if (valid[i / 3] && !std::isfinite(v))
      fail(ErrorCode::kInternal, source, "a valid point with a coordinate that is not finite");
    if (bytes == 4)
      w.u32(valid[i / 3] ? float_bits(static_cast<float>(v)) : 0x7FC00000u);
    else if (valid[i / 3])
      w.f64(v);
    else
      w.u64(0x7FF8000000000000ull);
  }
  return std::move(w.buffer());
}

}  // namespace

std::vector<uint8_t> encode_raw_window(const std::vector<uint32_t>& counts, const double* xyz,
                                       const uint8_t* valid, size_t n, int bytes,
                                       const std::string& source) {
  ByteWriter w;
  w.varint(counts.size());
  for (uint32_t c : counts) w.varint(c);
  std::vector<uint8_t> out = std::move(w.buffer());
  const std::vector<uint8_t> bits = raw_bits(xyz, valid, n, bytes, source);
  const std::vector<uint8_t> packed = lzma2_encode_words(bits.data(), bits.size());
  out.insert(out.end(), packed.begin(), packed.end());
  return out;
}

size_t raw_window_estimate(const double* xyz, const uint8_t* valid, size_t n, int bytes) {
  const size_t m = std::min<size_t>(n, 16384);
  if (m == 0) return 0;
  const std::vector<uint8_t> bits = raw_bits(xyz, valid, m, bytes, "");
  const double quick = static_cast<double>(lzma2_quick_size(bits.data(), bits.size()));
  return static_cast<size_t>(quick * static_cast<double>(n) / static_cast<double>(m));
}

}  // namespace scan
}  // namespace capz
