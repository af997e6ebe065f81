#include "coding/entropy.h"

#include <algorithm>

namespace capz {
namespace {

template <typename T, typename Map>
std::vector<uint8_t> encode_stream(const std::vector<T>& values, Map map) {
  IntEncoder enc(kIntStreamContexts);
  int ctx = 0;
  for (T v : values) {
    uint32_t u = map(v);
    int nbits;
    int tok = token_of(u, &nbits);
    enc.put(u, ctx);
    ctx = std::min(tok, kIntStreamContexts - 1);
  }
  return enc.finish();
}

template <typename T, typename Unmap>
std::vector<T> decode_stream(const uint8_t* data, size_t size, size_t count,
                             const std::string& what, Unmap unmap) {
  if (count > kMaxSymbolsPerByte * size)
    throw Error(ErrorCode::kCorrupt, what + ": " + std::to_string(count) +
                                         " values cannot fit in " + std::to_string(size) + " bytes");
  IntDecoder dec(data, size, kIntStreamContexts, what);
  std::vector<T> out(count);
  int ctx = 0;
  for (size_t i = 0; i < count; ++i) {
    int tok;
    out[i] = unmap(dec.get_tok(ctx, &tok));
    ctx = std::min(tok, kIntStreamContexts - 1);
  }
  if (!dec.at_end()) dec.coder()->corrupt("entropy-coded block has bytes past its last value");
  return out;
}

}  // namespace

std::vector<uint8_t> encode_ints(const std::vector<int32_t>& values) {
  return encode_stream(values, zigzag);
}
std::vector<uint8_t> encode_uints(const std::vector<uint32_t>& values) {
  return encode_stream(values, [](uint32_t u) { return u; });
}
std::vector<int32_t> decode_ints(const uint8_t* data, size_t size, size_t count,
                                 const std::string& what) {
  return decode_stream<int32_t>(data, size, count, what, unzigzag);
}
std::vector<uint32_t> decode_uints(const uint8_t* data, size_t size, size_t count,
                                   const std::string& what) {
  return decode_stream<uint32_t>(data, size, count, what, [](uint32_t u) { return u; });
}

}  // namespace capz
