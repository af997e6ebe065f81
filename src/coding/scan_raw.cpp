// Raw windows decoded (scan_raw.h; docs/FORMAT.md "Raw windows").
#include "coding/scan_raw.h"

#include <cmath>
#include <cstring>

#include "capz/error.h"
#include "coding/bytes.h"
#include "coding/lzma_block.h"
#include "coding/quantiser.h"

namespace capz {
namespace scan {

namespace {

// The little-endian value of `bytes` bytes at p as a double (a float32's exactly).
double value_at(const uint8_t* p, int bytes) {
  if (bytes == 4) {
    uint32_t u = 0;
    for (int k = 0; k < 4; ++k) u |= static_cast<uint32_t>(p[k]) << (8 * k);
    return static_cast<double>(bits_float(u));
  }
  uint64_t u = 0;
  for (int k = 0; k < 8; ++k) u |= static_cast<uint64_t>(p[k]) << (8 * k);
  double d;
  std::memcpy(&d, &u, 8);
  return d;
}

}  // namespace

std::vector<uint64_t> raw_frame_counts(const uint8_t* data, size_t size, const std::string& what) {
  ByteReader r(data, size, what);
  const uint64_t fn = r.varint();
  if (fn > r.remaining())  // a count is at least a byte
    fail(ErrorCode::kCorrupt, what, "a raw window's frame counts run past its chunk");
  std::vector<uint64_t> counts(static_cast<size_t>(fn));
  for (uint64_t& n : counts) n = r.varint();
  return counts;
}

RawWindow decode_raw_window(const uint8_t* data, size_t size, const std::string& what,
                            size_t frames, uint64_t total, int bytes) {
  ByteReader r(data, size, what);
  const uint64_t fn = r.varint();
  if (fn != frames)
    fail(ErrorCode::kCorrupt, what,
         "a raw window of " + std::to_string(fn) + " frames, the window has " +
             std::to_string(frames));
  RawWindow w;
  uint64_t sum = 0;
  for (size_t f = 0; f < frames; ++f) {
    const uint64_t n = r.varint();
    sum += n;
    if (n > total || sum > total)
      fail(ErrorCode::kCorrupt, what,
           "raw window frame counts beyond the chunk's " + std::to_string(total) + " points");
    w.counts.push_back(static_cast<uint32_t>(n));
  }
  if (sum != total)
    fail(ErrorCode::kCorrupt, what,
         "raw window frame counts sum to " + std::to_string(sum) + " points, the chunk says " +
             std::to_string(total));
  const size_t n = static_cast<size_t>(total);
  const size_t point = 3 * static_cast<size_t>(bytes);
  const std::vector<uint8_t> bits =
      lzma2_decode(data + r.offset(), size - r.offset(), n * point, what);
  w.valid.assign(n, 0);
  w.xyz.assign(n * 3, 0.0);
  for (size_t i = 0; i < n; ++i) {
    double v[3];
    for (size_t a = 0; a < 3; ++a) v[a] = value_at(&bits[i * point + a * size_t(bytes)], bytes);
    if (!(std::isfinite(v[0]) && std::isfinite(v[1]) && std::isfinite(v[2]))) continue;
    w.valid[i] = 1;
    for (size_t a = 0; a < 3; ++a) w.xyz[3 * i + a] = v[a];
  }
  return w;
}

std::vector<int32_t> raw_window_ints(const std::vector<double>& xyz,
                                     const std::vector<uint8_t>& valid) {
  std::vector<int32_t> q(valid.size() * 3, 0);
  for (size_t i = 0; i < valid.size(); ++i)
    if (valid[i])
      for (size_t a = 0; a < 3; ++a)
        q[3 * i + a] = float_to_ordered(static_cast<float>(xyz[3 * i + a]));
  return q;
}

}  // namespace scan
}  // namespace capz
