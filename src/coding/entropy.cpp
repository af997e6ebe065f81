// The entropy coder's decoding side (entropy.h, docs/FORMAT.md 2); the encoding side is
// entropy_encode.cpp.
#include "coding/entropy.h"

#include <algorithm>

#include "coding/bytes.h"

namespace capz {

void throw_corrupt(const std::string& what, const char* msg) {
  throw Error(ErrorCode::kCorrupt, what + ": " + msg);
}

IntDecoder::IntDecoder(const uint8_t* data, size_t size, int contexts, const std::string& what)
    : what_(what), models_(static_cast<size_t>(contexts)) {
  ByteReader r(data, size, what);
  const size_t n = static_cast<size_t>(r.count(1, "length of the range-coded part"));
  const size_t h = r.offset();
  cur_.rc_ = RangeDecoder::start(data + h, n, what_);
  cur_.bits_ = BitReader(data + h + n, size - h - n);
  cur_.models_ = models_.data();
  cur_.escape_ = escape_;
  cur_.what_ = &what_;
}

namespace {

template <typename T, typename Unmap>
std::vector<T> decode_stream(const uint8_t* data, size_t size, size_t count,
                             const std::string& what, Unmap unmap) {
  if (count > kMaxSymbolsPerByte * size)
    throw Error(ErrorCode::kCorrupt, what + ": " + std::to_string(count) +
                                         " values cannot fit in " + std::to_string(size) +
                                         " bytes");
  IntDecoder dec(data, size, kIntStreamContexts, what);
  std::vector<T> out(count);
  int ctx = 0;
  for (size_t i = 0; i < count; ++i) {
    int tok;
    out[i] = unmap(dec.get(ctx, &tok));
    ctx = std::min(tok, kIntStreamContexts - 1);
  }
  if (!dec.at_end()) dec.corrupt("entropy-coded block has bytes past its last value");
  return out;
}

}  // namespace

std::vector<int32_t> decode_ints(const uint8_t* data, size_t size, size_t count,
                                 const std::string& what) {
  return decode_stream<int32_t>(data, size, count, what, unzigzag);
}
std::vector<uint32_t> decode_uints(const uint8_t* data, size_t size, size_t count,
                                   const std::string& what) {
  return decode_stream<uint32_t>(data, size, count, what, [](uint32_t u) { return u; });
}

std::vector<uint8_t> decode_bytes(const uint8_t* data, size_t size, size_t count,
                                  const std::string& what) {
  if (count > kMaxSymbolsPerByte / 2 * size)
    throw Error(ErrorCode::kCorrupt, what + ": " + std::to_string(count) +
                                         " bytes cannot be coded in " + std::to_string(size));
  RangeDecoder dec(data, size, what);
  std::vector<SymbolModel> hi(256), lo(256);
  std::vector<uint8_t> out(count);
  int h1 = 0, h2 = 0;
  for (size_t i = 0; i < count; ++i) {
    const int a = hi[static_cast<size_t>(h1 | (h2 << 4))].decode(&dec);
    const int b = lo[static_cast<size_t>((a << 4) | h1)].decode(&dec);
    out[i] = static_cast<uint8_t>((a << 4) | b);
    h2 = h1;
    h1 = a;
  }
  if (!dec.at_end()) dec.corrupt("byte block has bytes past its end");
  return out;
}

}  // namespace capz
