// Raw windows decoded (scan_raw.h; docs/FORMAT.md "Raw windows").
#include "coding/scan_raw.h"

#include <algorithm>
#include <cmath>

#include "capz/error.h"
#include "coding/bytes.h"
#include "coding/lzma_block.h"
#include "coding/quantiser.h"

namespace capz {
namespace scan {

namespace {

// The frame counts at r (a varint frame count, then a varint a frame), their number checked
// against the bytes left (a count is at least a byte) before any is stored.
std::vector<uint64_t> read_counts(ByteReader* r) {
  const uint64_t fn = r->varint();
  if (fn > r->remaining())
    fail(ErrorCode::kCorrupt, r->what(), "a raw window's frame counts run past its chunk");
  std::vector<uint64_t> counts(static_cast<size_t>(fn));
  for (uint64_t& n : counts) n = r->varint();
  return counts;
}

}  // namespace

std::vector<uint64_t> raw_frame_counts(const uint8_t* data, size_t size, const std::string& what) {
  ByteReader r(data, size, what);
  return read_counts(&r);
}

RawWindow decode_raw_window(const uint8_t* data, size_t size, const std::string& what,
                            size_t frames, uint64_t total, int bytes) {
  ByteReader r(data, size, what);
  const std::vector<uint64_t> counts = read_counts(&r);
  if (counts.size() != frames)
    fail(ErrorCode::kCorrupt, what,
         "a raw window of " + std::to_string(counts.size()) + " frames, the window has " +
             std::to_string(frames));
  RawWindow w;
  uint64_t sum = 0;
  for (uint64_t n : counts) {
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
  const std::vector<uint8_t> bits =
      lzma2_decode(data + r.offset(), size - r.offset(), n * 3 * static_cast<size_t>(bytes), what);
  ByteReader b(bits.data(), bits.size(), what);
  w.valid.assign(n, 0);
  w.xyz.assign(n * 3, 0.0);
  for (size_t i = 0; i < n; ++i) {
    double v[3];
    for (double& x : v) x = bytes == 4 ? static_cast<double>(b.f32()) : b.f64();
    if (!(std::isfinite(v[0]) && std::isfinite(v[1]) && std::isfinite(v[2]))) continue;
    w.valid[i] = 1;
    std::copy(v, v + 3, &w.xyz[3 * i]);
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
