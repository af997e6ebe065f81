// capz — residue payload packing (see pack.h).
#include "io/residue/pack.h"

#include <zstd.h>

#include <algorithm>
#include <memory>

#include "capz/error.h"

namespace capz {
namespace residue {

namespace {

struct CCtxFree {
  void operator()(ZSTD_CCtx* c) const { ZSTD_freeCCtx(c); }
};
struct DCtxFree {
  void operator()(ZSTD_DCtx* d) const { ZSTD_freeDCtx(d); }
};

std::vector<uint8_t> zstd(const std::vector<uint8_t>& data, const std::vector<uint8_t>* dict,
                          int level) {
  std::unique_ptr<ZSTD_CCtx, CCtxFree> c(ZSTD_createCCtx());
  if (!c) fail(ErrorCode::kInternal, "", "zstd: cannot create a context");
  ZSTD_CCtx_setParameter(c.get(), ZSTD_c_compressionLevel, level);
  ZSTD_CCtx_setParameter(c.get(), ZSTD_c_checksumFlag, 0);
  ZSTD_CCtx_setParameter(c.get(), ZSTD_c_contentSizeFlag, 0);  // the size is stored beside it
  ZSTD_CCtx_setParameter(c.get(), ZSTD_c_dictIDFlag, 0);
  if (dict) ZSTD_CCtx_refPrefix(c.get(), dict->data(), dict->size());
  std::vector<uint8_t> out(ZSTD_compressBound(data.size()));
  const size_t n = ZSTD_compress2(c.get(), out.data(), out.size(), data.data(), data.size());
  if (ZSTD_isError(n)) fail(ErrorCode::kInternal, "", std::string("zstd: ") + ZSTD_getErrorName(n));
  out.resize(n);
  return out;
}

}  // namespace

void pack(const std::vector<uint8_t>& data, const std::vector<uint8_t>& dict, ByteWriter& out,
          int level) {
  uint8_t method = 0;
  std::vector<uint8_t> best = data;
  if (!data.empty()) {
    std::vector<uint8_t> z = zstd(data, nullptr, level);
    if (z.size() < best.size()) best = std::move(z), method = 1;
    if (!dict.empty()) {
      std::vector<uint8_t> zd = zstd(data, &dict, level);
      if (zd.size() < best.size()) best = std::move(zd), method = 2;
    }
  }
  out.u8(method);
  out.varint(data.size());
  out.varint(best.size());
  out.bytes(best);
}

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
