// LZF compression, the byte format PCL's binary_compressed PCD bodies use (liblzf's): a stream
// of runs, each a control byte c then
//   c < 32: c + 1 literal bytes;
//   else a copy of len bytes from `distance` bytes back: len = (c >> 5) + 2, plus a following
//   byte when c >> 5 == 7; then a byte b, distance = ((c & 31) << 8) + b + 1 (at most 8192).
// Written here (a hash of 3-byte prefixes, greedy matches) so capz writes PCD files itself;
// PCL's reader decompresses them.
#pragma once

#include <cstddef>
#include <cstdint>
#include <string>
#include <vector>

namespace capz {

std::vector<uint8_t> lzf_compress(const uint8_t* data, size_t size);
// The same bytes into out[0, lzf_bound(size)) (the caller's buffer); returns their count.
size_t lzf_compress_into(const uint8_t* data, size_t size, uint8_t* out);
// The most bytes lzf_compress gives for `size` bytes (the input and a control byte per 32).
size_t lzf_bound(size_t size);

// The LZF compressors capz reproduces (docs/FORMAT.md 14.3): its own (above) and variant 1,
// liblzf's greedy compressor as PCL's io/src/lzf.cpp builds it with a 2^13-slot table (its
// "(h >> 11) - h" hash of 3 bytes, one position indexed after a match, offset 0 never matched),
// which wrote PCL's binary_compressed PCD files (pandar64-factory20's among them).
enum class LzfVariant : uint8_t { kCapz = 0, kLiblzf13 = 1 };
std::vector<uint8_t> lzf_compress(const uint8_t* data, size_t size, LzfVariant variant);

// Decompresses exactly `size` bytes into out[0, size): false (out's bytes unspecified) when the
// stream is malformed, references before its start, or does not give exactly `size` bytes.
bool lzf_decompress_into(const uint8_t* data, size_t n, uint8_t* out, size_t size);
// The runs of the same stream that give out[0, prefix) (prefix at most size; out[prefix, size)
// unspecified): false when one of them is malformed, references before the start or passes
// `size`, or the stream ends before `prefix` bytes. A stream lzf_decompress_into takes gives
// the same prefix here; one it refuses may still give its prefix.
bool lzf_decompress_prefix(const uint8_t* data, size_t n, uint8_t* out, size_t size, size_t prefix);

// Decompresses exactly `size` bytes; throws Error(kCorrupt) naming `what` on a stream that is
// malformed, references before its start, or does not give exactly `size` bytes.
std::vector<uint8_t> lzf_decompress(const uint8_t* data, size_t n, size_t size,
                                    const std::string& what);

}  // namespace capz
