// capz — raw LZMA2 blocks (docs/FORMAT.md 2.6): META coding 2, through liblzma.
#pragma once

#include <cstddef>
#include <cstdint>
#include <string>
#include <vector>

namespace capz {

// LZMA2 with a fixed 2^20-byte dictionary, preset 9e; the decoder needs nothing else.
constexpr uint32_t kLzmaDictBytes = uint32_t{1} << 20;

// A preset dictionary (FORMAT.md 2.6): bytes the LZMA2 window holds before the first byte of the
// stream, which its matches may reach. The empty one is none (a stream that starts with a
// dictionary reset, FORMAT.md 2.6).
struct LzmaPreset {
  const uint8_t* data = nullptr;
  size_t size = 0;
};

// `n` bytes as a raw LZMA2 stream (liblzma lzma_raw_buffer_encode), after `preset`. Throws
// Error(kInternal) if liblzma fails.
std::vector<uint8_t> lzma2_encode(const uint8_t* data, size_t n, LzmaPreset preset = {});

// The same stream format, faster: preset 6 (not extreme), one setting lc 0 lp 0 pb 0 (bytes
// without text-like context, e.g. byte planes of numbers). About 3x faster than lzma2_encode.
std::vector<uint8_t> lzma2_encode_fast(const uint8_t* data, size_t n);

// The same stream format for arrays of 4- or 8-byte numbers: preset 6, lc 0 lp 2 pb 2 (a
// number's bytes aligned on 4; docs/FORMAT.md "Raw windows").
std::vector<uint8_t> lzma2_encode_words(const uint8_t* data, size_t n);

// The size of a raw LZMA2 stream of the same bytes coded quickly (liblzma's preset 3: fast mode,
// the hash-chain match finder; lc 0 lp 0 pb 0): an estimate of lzma2_encode_fast's size, about
// 4x cheaper on byte planes of numbers, typically 0-12 % larger.
size_t lzma2_quick_size(const uint8_t* data, size_t n);

// Decodes a raw LZMA2 stream that must give exactly `n` bytes and end exactly at `size`.
// Throws Error(kCorrupt) naming `what` otherwise. Memory: the output and the fixed dictionary.
std::vector<uint8_t> lzma2_decode(const uint8_t* data, size_t size, size_t n,
                                  const std::string& what, LzmaPreset preset = {});

// The preset dictionaries of META coding 3 (FORMAT.md 5.8): number 1, or the empty preset for
// a number the format does not define.
LzmaPreset meta_dictionary(int number);

}  // namespace capz
