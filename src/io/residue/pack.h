// capz — residue payload packing: a byte string stored as it is or as one zstd frame, optionally
// with a "prefix dictionary" both sides can derive from what the archive already holds.
//
// Stored form (docs/FORMAT.md 2.7, "Packed byte strings"):
//   u8 method      0 stored, 1 zstd, 2 zstd with the caller's prefix dictionary
//   varint size    bytes once unpacked
//   varint n       bytes that follow
//   n bytes        the payload
#pragma once

#include <cstddef>
#include <cstdint>
#include <string>
#include <vector>

#include "coding/bytes.h"

namespace capz {
namespace residue {

// Appends `data` packed to `out`: the smallest of stored, zstd (level 19, long matches) and,
// when `dict` is not empty, zstd with `dict` as its prefix. `level`: zstd's (an encoder's choice:
// the stored form is the same).
void pack(const std::vector<uint8_t>& data, const std::vector<uint8_t>& dict, ByteWriter& out,
          int level = 19);

// Reads one packed string. `dict` must be the bytes the packer was given (only method 2 uses
// it). Throws Error(kCorrupt) naming `in.what()` when the method is unknown, the zstd frame is
// damaged or its size is not the stored one. Memory grows with the bytes really produced, never
// with the stored size alone; a stored size above `limit` is corrupt (a bound the caller knows,
// e.g. the original file's size, so a damaged frame cannot make it expand without end).
std::vector<uint8_t> unpack(ByteReader& in, const std::vector<uint8_t>& dict,
                            uint64_t limit = UINT64_MAX);

// A file's whole residue: the file-level payload and one payload per window of frames, in order.
struct FileResidue {
  std::vector<uint8_t> file_part;
  std::vector<std::vector<uint8_t>> windows;
  size_t bytes() const;  // file part + every window
};

}  // namespace residue
}  // namespace capz
