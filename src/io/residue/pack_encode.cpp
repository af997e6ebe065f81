// Residue payloads packed (pack.h): as they are, or zstd without or with the dictionary,
// whichever is smallest; pack.cpp unpacks them.
#include <zstd.h>

#include <memory>
#include <string>

#include "capz/error.h"
#include "io/residue/pack.h"

namespace capz {
namespace residue {

namespace {

struct CCtxFree {
  void operator()(ZSTD_CCtx* c) const { ZSTD_freeCCtx(c); }
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

}  // namespace residue
}  // namespace capz
