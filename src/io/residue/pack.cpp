// Residue payloads unpacked (pack.h); pack_encode.cpp packs them.
#include "io/residue/pack.h"

#include <zstd.h>

#include <algorithm>
#include <memory>

#include "capz/error.h"

namespace capz {
namespace residue {

namespace {

struct DCtxFree {
  void operator()(ZSTD_DCtx* d) const { ZSTD_freeDCtx(d); }
};

}  // namespace

std::vector<uint8_t> unpack(ByteReader& in, const std::vector<uint8_t>& dict, uint64_t limit) {
  const uint8_t method = in.u8();
  const uint64_t size = in.varint();
  if (size > limit)
    fail(ErrorCode::kCorrupt, in.what(),
         "packed bytes of " + std::to_string(size) + " bytes, at most " + std::to_string(limit) +
             " possible");
  const uint64_t n = in.count(1, "packed size");
  const uint8_t* src = in.bytes(static_cast<size_t>(n));
  if (method == 0) {
    if (size != n)
      fail(ErrorCode::kCorrupt, in.what(),
           "stored bytes: size " + std::to_string(size) + " but " + std::to_string(n) + " stored");
    return std::vector<uint8_t>(src, src + n);
  }
  if (method > 2)
    fail(ErrorCode::kCorrupt, in.what(), "unknown packing method " + std::to_string(method));
  std::unique_ptr<ZSTD_DCtx, DCtxFree> d(ZSTD_createDCtx());
  if (!d) fail(ErrorCode::kInternal, in.what(), "zstd: cannot create a context");
  if (method == 2) ZSTD_DCtx_refPrefix(d.get(), dict.data(), dict.size());
  std::vector<uint8_t> out;
  ZSTD_inBuffer ib{src, static_cast<size_t>(n), 0};
  size_t ret = 1;
  while (ret != 0) {
    // Grow by what zstd asks for, never past the stored size (+1 to catch a longer frame).
    const size_t have = out.size();
    if (have > size)
      fail(ErrorCode::kCorrupt, in.what(), "zstd frame longer than " + std::to_string(size));
    const size_t step = static_cast<size_t>(
        std::min<uint64_t>(size - have + 1, std::max<size_t>(ZSTD_DStreamOutSize(), have)));
    out.resize(have + step);
    ZSTD_outBuffer ob{out.data() + have, step, 0};
    ret = ZSTD_decompressStream(d.get(), &ob, &ib);
    out.resize(have + ob.pos);
    if (ZSTD_isError(ret))
      fail(ErrorCode::kCorrupt, in.what(), std::string("zstd: ") + ZSTD_getErrorName(ret));
    if (ret != 0 && ib.pos == ib.size && ob.pos < step)
      fail(ErrorCode::kCorrupt, in.what(), "zstd frame cut short");
  }
  if (ib.pos != ib.size || out.size() != size)
    fail(ErrorCode::kCorrupt, in.what(),
         "zstd frame gives " + std::to_string(out.size()) + " bytes, " + std::to_string(size) +
             " stored");
  return out;
}

size_t FileResidue::bytes() const {
  size_t n = file_part.size();
  for (const auto& w : windows) n += w.size();
  return n;
}

}  // namespace residue
}  // namespace capz
