// Raw LZMA2 blocks encoded (lzma_block.h; docs/FORMAT.md 2.6): the smallest of a few literal
// context and position settings, or one fast setting; the decoder is lzma_block.cpp.
#include <lzma.h>

#include "capz/error.h"
#include "coding/lzma_block.h"
#include "coding/lzma_options.h"

namespace capz {

namespace {

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

// liblzma's preset `level` with the fixed dictionary and lc 0 lp 0 pb 0.
lzma_options_lzma plain_options(uint32_t level) {
  lzma_options_lzma o;
  lzma_lzma_preset(&o, level);
  o.dict_size = kLzmaDictBytes;
  o.lc = 0;
  o.lp = 0;
  o.pb = 0;
  return o;
}

}  // namespace

std::vector<uint8_t> lzma2_encode(const uint8_t* data, size_t n, LzmaPreset preset) {
  // The literal context and position bits travel in the stream (LZMA2's properties byte), so
  // the encoder may pick them: the preset's (lc 3, pb 2) and, for text-like bytes, pb 0 with
  // lc 0..3. The smallest is kept (ties: the first). After a preset dictionary: lc 3 and lc 0
  // with pb 0, and the hash-chain match finder, which reads the dictionary in about a third of
  // the binary tree's time (30 ms for dictionary 1 here) for a few bytes more or less on the
  // C3D parameter sections measured.
  static const uint32_t kTrials[][2] = {{3, 2}, {3, 0}, {2, 0}, {1, 0}, {0, 0}};
  static const uint32_t kPresetTrials[][2] = {{3, 0}, {0, 0}};
  std::vector<uint8_t> best;
  auto trial = [&](uint32_t lc, uint32_t pb) {
    lzma_options_lzma o = lzma2_options(preset);
    o.lc = lc;
    o.pb = pb;
    if (preset.size) o.mf = LZMA_MF_HC4;
    std::vector<uint8_t> out = encode_with(o, data, n);
    if (best.empty() || out.size() < best.size()) best = std::move(out);
  };
  if (preset.size)
    for (const auto& lc_pb : kPresetTrials) trial(lc_pb[0], lc_pb[1]);
  else
    for (const auto& lc_pb : kTrials) trial(lc_pb[0], lc_pb[1]);
  return best;
}

std::vector<uint8_t> lzma2_encode_fast(const uint8_t* data, size_t n) {
  return encode_with(plain_options(6), data, n);
}

std::vector<uint8_t> lzma2_encode_words(const uint8_t* data, size_t n) {
  lzma_options_lzma o = plain_options(6);
  o.lp = 2;
  o.pb = 2;
  return encode_with(o, data, n);
}

size_t lzma2_quick_size(const uint8_t* data, size_t n) {
  return encode_with(plain_options(3), data, n).size();
}

}  // namespace capz
