// Fuzz target: the float32 split of lossless scan windows (coding/scan_split.h; docs/FORMAT.md
// "Lossless ragged streams"), through the scan geometry coder as SCNW carries it. Byte 0 picks
// the mode:
//   even: the rest is SCNW's body after its point count and gaps byte in mode 2 with a split: the
//     exponent E (int8), the geometry's length (varint), the geometry (at most 4096 points) and the
//     corrections block, decoded as the decoder does. It must return or throw capz::Error; what
//     decodes is float32 at every valid coordinate, and split again at E gives the same
//     integers and corrections that decode to the same coordinates;
//   odd: byte 1 the exponent (-64..64), byte 2 the frame count (1..4); the rest are float32
//     coordinates, 12 bytes a point (a NaN x a gap). When they split under the encoder's limit
//     (|q| < 2^29), the geometry and corrections coded and decoded give back every bit.
#include <algorithm>
#include <cmath>
#include <cstddef>
#include <cstdint>
#include <cstring>
#include <vector>

#include "capz/error.h"
#include "coding/bytes.h"
#include "coding/scan_geometry.h"
#include "coding/scan_split.h"
#include "fuzz_common.h"

namespace {

constexpr size_t kMaxPoints = 4096;
constexpr int64_t kEncoderLimit = int64_t{1} << 29;  // scan_encoder.cpp's kSplitLimit

uint32_t bits_of(float f) {
  uint32_t b;
  std::memcpy(&b, &f, 4);
  return b;
}

// Decodes a split's geometry and corrections (the decoder's decode_window_scan).
std::vector<double> decode(const uint8_t* geo, size_t geo_size, const uint8_t* corr,
                           size_t corr_size, int e, capz::ScanGeometry* g) {
  *g = capz::decode_scan_geometry(geo, geo_size, "fuzz SCNW", kMaxPoints);
  std::vector<double> xyz(3 * g->total(), 0.0);
  capz::scan::decode_split(corr, corr_size, "fuzz SCNW", e, g->q, g->valid, xyz.data());
  return xyz;
}

// Splits xyz at e, codes geometry and corrections, decodes them: the same coordinates.
void round_trip(const capz::ScanGeometry& shape, const std::vector<double>& xyz, int e,
                int64_t limit) {
  capz::ScanGeometry g = shape;
  std::vector<uint32_t> t;
  if (!capz::scan::split_coordinates(xyz.data(), g.valid.data(), g.total(), e, limit, &g.q, &t))
    return;
  const std::vector<uint8_t> geo = capz::encode_scan_geometry(g);
  const std::vector<uint8_t> corr = capz::scan::encode_split(e, g.q, t, g.valid);
  capz::ScanGeometry h;
  const std::vector<double> back = decode(geo.data(), geo.size(), corr.data(), corr.size(), e, &h);
  CAPZ_FUZZ_CHECK(h.counts == g.counts && h.valid == g.valid);
  for (size_t i = 0; i < xyz.size(); ++i)
    if (g.valid[i / 3])
      CAPZ_FUZZ_CHECK(bits_of(static_cast<float>(back[i])) == bits_of(static_cast<float>(xyz[i])));
}

void decode_body(const uint8_t* data, size_t size) {
  capz::ScanGeometry g;
  std::vector<double> xyz;
  int e = 0;
  try {
    capz::ByteReader r(data, size, "fuzz SCNW");
    e = static_cast<int8_t>(r.u8());
    const uint64_t len = r.varint();
    if (len > r.remaining()) return;
    const size_t at = r.offset(), geo = static_cast<size_t>(len);
    xyz = decode(data + at, geo, data + at + geo, size - at - geo, e, &g);
  } catch (const capz::Error&) {
    return;
  }
  for (size_t i = 0; i < xyz.size(); ++i)
    if (g.valid[i / 3]) CAPZ_FUZZ_CHECK(static_cast<double>(static_cast<float>(xyz[i])) == xyz[i]);
  round_trip(g, xyz, e, capz::scan::kMaxSplitInt);
}

}  // namespace

extern "C" int LLVMFuzzerTestOneInput(const uint8_t* data, size_t size) {
  if (size < 1) return 0;
  if (data[0] % 2 == 0) {
    decode_body(data + 1, size - 1);
    return 0;
  }
  if (size < 3) return 0;
  const int e = static_cast<int>(data[1] % 129) - 64;
  const size_t frames = 1 + data[2] % 4;
  const size_t n = std::min((size - 3) / 12, kMaxPoints);
  capz::ScanGeometry g;
  for (size_t f = 0; f < frames; ++f)
    g.counts.push_back(static_cast<uint32_t>(n * (f + 1) / frames - n * f / frames));
  g.valid.assign(n, 1);
  std::vector<double> xyz(3 * n);
  for (size_t i = 0; i < 3 * n; ++i) {
    float v;
    std::memcpy(&v, data + 3 + 4 * i, 4);
    xyz[i] = v;
  }
  for (size_t p = 0; p < n; ++p) g.valid[p] = !std::isnan(xyz[3 * p]);
  round_trip(g, xyz, e, kEncoderLimit);
  return 0;
}
