// Raw windows encoded (scan_raw.h; docs/FORMAT.md "Raw windows").
#include <algorithm>
#include <cmath>
#include <cstring>

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
  const size_t point = 3 * static_cast<size_t>(bytes);
  std::vector<uint8_t> out(n * point);
  for (size_t i = 0; i < n; ++i)
    for (size_t a = 0; a < 3; ++a) {
      uint8_t* p = &out[i * point + a * static_cast<size_t>(bytes)];
      const double v = valid[i] ? xyz[3 * i + a] : std::nan("");
      if (valid[i] && !std::isfinite(v))
        fail(ErrorCode::kInternal, source, "a valid point with a coordinate that is not finite");
      if (bytes == 4) {
        const uint32_t u = valid[i] ? float_bits(static_cast<float>(v)) : 0x7FC00000u;
        for (int k = 0; k < 4; ++k) p[k] = static_cast<uint8_t>(u >> (8 * k));
      } else {
        uint64_t u = 0x7FF8000000000000ull;
        if (valid[i]) std::memcpy(&u, &v, 8);
        for (int k = 0; k < 8; ++k) p[k] = static_cast<uint8_t>(u >> (8 * k));
      }
    }
  return out;
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
