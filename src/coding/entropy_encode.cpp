// The entropy coder's encoding side (entropy.h, docs/FORMAT.md 2): a block finished, and the
// blocks of integers and bytes the decoder's decode_ints, decode_uints and decode_bytes read.
#include <algorithm>

#include "coding/bytes.h"
#include "coding/entropy.h"

namespace capz {

std::vector<uint8_t> IntEncoder::finish() {
  RangeEncoder::Core& rc = cur_.rc_;
  rc.flush(&rc_out_);
  BitWriter::Core& bits = cur_.bits_;
  bits.flush(&bits_out_);
  ByteWriter w;
  w.varint(rc_out_.size());
  w.bytes(rc_out_);
  w.bytes(bits_out_);
  rc = RangeEncoder::Core();
  bits = BitWriter::Core();
  rc_out_.clear();
  bits_out_.clear();
  return std::move(w.buffer());
}

namespace {

template <typename T, typename Map>
std::vector<uint8_t> encode_stream(const std::vector<T>& values, Map map) {
  IntEncoder enc(kIntStreamContexts);
  int ctx = 0;
  for (T v : values) {
    int tok = enc.put(map(v), ctx);
    ctx = std::min(tok, kIntStreamContexts - 1);
  }
  return enc.finish();
}

}  // namespace

std::vector<uint8_t> encode_ints(const std::vector<int32_t>& values) {
  return encode_stream(values, zigzag);
}
std::vector<uint8_t> encode_uints(const std::vector<uint32_t>& values) {
  return encode_stream(values, [](uint32_t u) { return u; });
}

std::vector<uint8_t> encode_bytes(const uint8_t* data, size_t size) {
  RangeEncoder enc;
  std::vector<SymbolModel> hi(256), lo(256);
  int h1 = 0, h2 = 0;
  for (size_t i = 0; i < size; ++i) {
    const int x = data[i];
    hi[static_cast<size_t>(h1 | (h2 << 4))].encode(&enc, x >> 4);
    lo[static_cast<size_t>(((x >> 4) << 4) | h1)].encode(&enc, x & 15);
    h2 = h1;
    h1 = x >> 4;
  }
  return enc.finish();
}

}  // namespace capz
