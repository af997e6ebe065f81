// Decoder library (capz_decode). Raw LZMA2 blocks (lzma_block.h; docs/FORMAT.md 5.1).
#include "coding/lzma_block.h"

#include <lzma.h>

#include "capz/error.h"

namespace capz {

namespace {

lzma_options_lzma lzma2_options() {
  lzma_options_lzma o;
  lzma_lzma_preset(&o, 9 | LZMA_PRESET_EXTREME);
  o.dict_size = kLzmaDictBytes;
  return o;
}

// One raw LZMA2 stream with options o.
std::vector<uint8_t> encode_with(lzma_options_lzma o, const uint8_t* data, size_t n) {
  const lzma_filter filters[] = {{LZMA_FILTER_LZMA2, &o}, {LZMA_VLI_UNKNOWN, nullptr}};
  // LZMA2 stores incompressible data in chunks with 3 bytes of header per 64 KiB.
  std::vector<uint8_t> out(n + n / 16384 * 3 + 64);
  size_t pos = 0;
  const lzma_ret r =
      lzma_raw_buffer_encode(filters, nullptr, data, n, out.data(), &pos, out.size());
  if (r != LZMA_OK)
    fail(ErrorCode::kInternal, "", "liblzma failed to encode (" + std::to_string(r) + ")");
  out.resize(pos);
  return out;
}

}  // namespace

std::vector<uint8_t> lzma2_encode(const uint8_t* data, size_t n) {
  // The literal context and position bits travel in the stream (LZMA2's properties byte), so
  // the encoder may pick them: the preset's (lc 3, pb 2) and, for text-like bytes, pb 0 with
  // lc 0..3. The smallest is kept (ties: the first).
  static const uint32_t kTrials[][2] = {{3, 2}, {3, 0}, {2, 0}, {1, 0}, {0, 0}};
  std::vector<uint8_t> best;
  for (const auto& lc_pb : kTrials) {
    lzma_options_lzma o = lzma2_options();
    o.lc = lc_pb[0];
    o.pb = lc_pb[1];
    std::vector<uint8_t> out = encode_with(o, data, n);
    if (best.empty() || out.size() < best.size()) best = std::move(out);
  }
  return best;
}

std::vector<uint8_t> lzma2_encode_fast(const uint8_t* data, size_t n) {
  lzma_options_lzma o;
  lzma_lzma_preset(&o, 6);
  o.dict_size = kLzmaDictBytes;
  o.lc = 0;
  o.lp = 0;
  o.pb = 0;
  return encode_with(o, data, n);
}

std::vector<uint8_t> lzma2_decode(const uint8_t* data, size_t size, size_t n,
                                  const std::string& what) {
  lzma_options_lzma o = lzma2_options();
  const lzma_filter filters[] = {{LZMA_FILTER_LZMA2, &o}, {LZMA_VLI_UNKNOWN, nullptr}};
  std::vector<uint8_t> out(n);
  size_t in_pos = 0, out_pos = 0;
  const lzma_ret r =
      lzma_raw_buffer_decode(filters, nullptr, data, &in_pos, size, out.data(), &out_pos, n);
  // The buffer API returns LZMA_OK once the stream's end is reached; LZMA_BUF_ERROR when the
  // output fills first (the stream holds more than n bytes) or the input ends first.
  if (r != LZMA_OK || out_pos != n || in_pos != size)
    fail(ErrorCode::kCorrupt, what,
         "the LZMA2 block does not decode to exactly " + std::to_string(n) + " bytes");
  return out;
}

}  // namespace capz
