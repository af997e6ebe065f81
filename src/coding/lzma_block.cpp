// Raw LZMA2 blocks decoded (lzma_block.h; docs/FORMAT.md 2.6), the options both sides use, and
// the preset dictionaries; the encoder is lzma_block_encode.cpp.
#include "coding/lzma_block.h"

#include <lzma.h>

#include "capz/error.h"
#include "coding/lzma_options.h"

namespace capz {

namespace {

// META coding 3's dictionary 1: docs/format/meta-dict-1.bin, made a C array by CMakeLists.txt.
const uint8_t kMetaDict1[] = {
#include "meta_dict_1.inc"
};

}  // namespace

lzma_options_lzma lzma2_options(LzmaPreset preset) {
  lzma_options_lzma o;
  lzma_lzma_preset(&o, 9 | LZMA_PRESET_EXTREME);
  o.dict_size = kLzmaDictBytes;
  if (preset.size) {
    o.preset_dict = preset.data;
    o.preset_dict_size = static_cast<uint32_t>(preset.size);
  }
  return o;
}

LzmaPreset meta_dictionary(int number) {
  LzmaPreset p;
  if (number == 1) {
    p.data = kMetaDict1;
    p.size = sizeof kMetaDict1;
  }
  return p;
}

std::vector<uint8_t> lzma2_decode(const uint8_t* data, size_t size, size_t n,
                                  const std::string& what, LzmaPreset preset) {
  lzma_options_lzma o = lzma2_options(preset);
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
