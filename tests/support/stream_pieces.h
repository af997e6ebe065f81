// Test helpers: a .capz stream cut into its chunks and put together again
// with valid CRCs and a recomputed INDX, so a test changes one thing and only that is wrong.
#pragma once

#include <gtest/gtest.h>

#include <cstdint>
#include <string>
#include <vector>

#include "capz/codec.h"
#include "capz/error.h"
#include "coding/bytes.h"
#include "coding/container.h"
#include "coding/crc32c.h"

namespace capz_test {

struct Piece {
  std::string type;
  std::vector<uint8_t> payload;
};

// Splits a stream into its chunks (no checks: the input is one this test just wrote).
inline std::vector<Piece> pieces(const std::vector<uint8_t>& b) {
  std::vector<Piece> out;
  for (size_t off = capz::kFileHeaderBytes; off + 12 <= b.size();) {
    const uint32_t n = static_cast<uint32_t>(b[off + 4]) | static_cast<uint32_t>(b[off + 5]) << 8 |
                       static_cast<uint32_t>(b[off + 6]) << 16 |
                       static_cast<uint32_t>(b[off + 7]) << 24;
    out.push_back(
        {std::string(b.begin() + static_cast<long>(off), b.begin() + static_cast<long>(off) + 4),
         std::vector<uint8_t>(b.begin() + static_cast<long>(off) + 8,
                              b.begin() + static_cast<long>(off + 8 + n))});
    off += 12 + n;
  }
  return out;
}

// Reassembles chunks with valid CRCs and a recomputed INDX (one window per POSW; a window's
// extent runs to the next POSW or to INDX), so only the deliberate change is wrong.
inline std::vector<uint8_t> assemble(const std::vector<uint8_t>& original, std::vector<Piece> ps) {
  std::vector<uint8_t> out(original.begin(),
                           original.begin() + static_cast<long>(capz::kFileHeaderBytes));
  auto put = [&](const Piece& p) {
    capz::ByteWriter w;
    for (char c : p.type) w.u8(static_cast<uint8_t>(c));
    w.u32(static_cast<uint32_t>(p.payload.size()));
    w.bytes(p.payload);
    std::vector<uint8_t> tp(p.type.begin(), p.type.end());
    tp.insert(tp.end(), p.payload.begin(), p.payload.end());
    w.u32(capz::crc32c(tp.data(), tp.size()));
    out.insert(out.end(), w.buffer().begin(), w.buffer().end());
  };
  std::vector<uint64_t> starts;
  for (const Piece& p : ps) {
    if (p.type == "INDX") continue;
    if (p.type == "POSW") starts.push_back(out.size());
    put(p);
  }
  capz::ByteWriter ix;
  ix.varint(starts.size());
  for (size_t w = 0; w < starts.size(); ++w) {
    ix.u64(starts[w]);
    ix.u64((w + 1 < starts.size() ? starts[w + 1] : out.size()) - starts[w]);
  }
  const uint32_t len = static_cast<uint32_t>(ix.buffer().size() + 4);
  ix.u32(len);
  put({"INDX", ix.buffer()});
  return out;
}

// The message of decompress()'s error on a crafted stream, which must be kCorrupt ("" when
// it decodes).
inline std::string decode_error(const std::vector<uint8_t>& b) {
  try {
    capz::decompress(b.data(), b.size(), "crafted");
  } catch (const capz::Error& e) {
    EXPECT_EQ(e.code(), capz::ErrorCode::kCorrupt) << e.what();
    return e.what();
  }
  return "";
}

}  // namespace capz_test
