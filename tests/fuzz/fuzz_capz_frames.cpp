// Fuzz target: the .capz frame source (open_capz_frames), which decodes only the windows a frame
// range touches. Bytes: [0] number of reads - 1 (low 3 bits), [1..3] seed of the ranges; the rest
// is the stream, written to a scratch file as given and again with every chunk CRC made valid.
// Opening and reading may throw capz::Error; anything else is a finding, and so is a block whose
// shape is wrong for the range asked. When decompress() accepts the whole stream, every range
// must read too and give exactly the frames of the whole decode (positions bit for bit, gap
// mask, analog values, C3D 4th words).
#include <algorithm>
#include <cstddef>
#include <cstdint>
#include <cstring>
#include <memory>
#include <vector>

#include "capz/codec.h"
#include "capz/error.h"
#include "capz/stream.h"
#include "fuzz_common.h"
#include "fuzz_temp_file.h"
#include "fuzz_util_capz.h"

namespace {

// Checks one block read from frames [first, first + count) against the header and, when the
// whole stream decoded, against that decode.
void check_block(const capz::Take& h, const capz::FrameBlock& b, size_t first, size_t count,
                 const capz::Take* whole) {
  const size_t f0 = std::min(first, h.frames), n = std::min(count, h.frames - f0);
  const size_t row = static_cast<size_t>(std::max(0, h.analog.samples_per_frame)) *
                     static_cast<size_t>(std::max(0, h.analog.channels));
  // Points of the range: n x points, or for frames of their own counts (format 1.1) the header's
  // frame offsets, which the source reads on open.
  const size_t p0 = h.frame_begin(f0), pn = h.frame_begin(f0 + n) - p0;
  CAPZ_FUZZ_CHECK(b.first == f0 && b.frames == n && b.points == h.points);
  CAPZ_FUZZ_CHECK(b.xyz.size() == pn * 3 && b.valid.size() == pn);
  CAPZ_FUZZ_CHECK(b.analog.size() == n * row);
  if (!whole) return;
  CAPZ_FUZZ_CHECK(b.xyz.empty() ||
                  std::memcmp(b.xyz.data(), &whole->xyz[p0 * 3], b.xyz.size() * 8) == 0);
  CAPZ_FUZZ_CHECK(std::equal(b.valid.begin(), b.valid.end(), whole->valid.begin() + p0));
  CAPZ_FUZZ_CHECK(b.analog.empty() || std::memcmp(b.analog.data(), &whole->analog.values[f0 * row],
                                                  b.analog.size() * 8) == 0);
  if (whole->c3d && !whole->c3d->residual.empty()) {
    CAPZ_FUZZ_CHECK(b.residual.size() == pn);
    CAPZ_FUZZ_CHECK(b.residual.empty() || std::memcmp(b.residual.data(), &whole->c3d->residual[p0],
                                                      b.residual.size() * 4) == 0);
  }
}

// Opens the stream in `file` and reads `reads` ranges drawn from `seed`.
void read_ranges(const capz_fuzz::TempFile& file, const uint8_t* stream, size_t size, int reads,
                 uint32_t seed) {
  file.write(stream, size);
  capz::Take whole;
  bool whole_ok = false;
  try {
    whole = capz::decompress(stream, size, "fuzz.capz", capz_fuzz::decode_options());
    whole_ok = true;
  } catch (const capz::Error&) {
  }
  std::unique_ptr<capz::FrameSource> src;
  try {
    src = capz::open_capz_frames(file.path(), capz_fuzz::decode_options());
  } catch (const capz::Error&) {
    CAPZ_FUZZ_CHECK(!whole_ok);  // a stream decompress() accepts must open
    return;
  }
  const capz::Take& h = src->header();
  CAPZ_FUZZ_CHECK(h.xyz.empty() && h.valid.empty());
  if (whole_ok)
    CAPZ_FUZZ_CHECK(
        capz_fuzz::decoded_shape_matches(h.frames, h.ragged(), h.total_points(), whole) &&
        (whole.ragged() ? h.frame_offsets == whole.frame_offsets
                        : h.ragged() || h.points == whole.points));
  CAPZ_FUZZ_CHECK(!h.ragged() || h.frame_offsets.size() == h.frames + 1);
  uint32_t x = seed | 1;
  auto next = [&x] {  // xorshift32
    x ^= x << 13;
    x ^= x >> 17;
    x ^= x << 5;
    return x;
  };
  for (int r = 0; r < reads; ++r) {
    // Ranges may start past the end and run past it (the source clips them).
    const size_t first = next() % (h.frames + 3), count = next() % 67;
    capz::FrameBlock b;
    try {
      src->read(first, count, &b);
    } catch (const capz::Error&) {
      CAPZ_FUZZ_CHECK(!whole_ok);  // a damaged window, which the whole decode would have met
      continue;
    }
    check_block(h, b, first, count, whole_ok ? &whole : nullptr);
  }
}

}  // namespace

extern "C" int LLVMFuzzerTestOneInput(const uint8_t* data, size_t size) {
  static const capz_fuzz::TempFile file("capz_frames");
  if (size < 4) return 0;
  const int reads = 1 + (data[0] & 7);
  const uint32_t seed = static_cast<uint32_t>(data[1]) | static_cast<uint32_t>(data[2]) << 8 |
                        static_cast<uint32_t>(data[3]) << 16;
  read_ranges(file, data + 4, size - 4, reads, seed);
  std::vector<uint8_t> fixed = capz_fuzz::with_fixed_crcs(data + 4, size - 4);
  if (fixed != std::vector<uint8_t>(data + 4, data + size))
    read_ranges(file, fixed.data(), fixed.size(), reads, seed);
  return 0;
}
