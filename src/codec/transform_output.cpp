// Transform-output POSW bodies (transform_output.h). Part of the decoder library.
#include "codec/transform_output.h"

#include "capz/error.h"
#include "coding/bytes.h"

namespace capz {

std::vector<uint8_t> transform_only_positions(const std::vector<uint8_t>& codec_bytes) {
  ByteWriter b;
  b.varint(codec_bytes.size());
  b.bytes(codec_bytes);
  return std::move(b.buffer());
}

CodecOnly split_transform_only(const uint8_t* data, size_t size, const std::string& what) {
  ByteReader r(data, size, what);
  CodecOnly c;
  const uint64_t n = r.varint();
  if (n == 0 || n > r.remaining())
    fail(ErrorCode::kCorrupt, what,
         "transform output: codec block length " + std::to_string(n) + " with " +
             std::to_string(r.remaining()) + " bytes left");
  c.size = static_cast<size_t>(n);
  c.data = r.bytes(c.size);
  if (r.remaining() != 0)
    fail(ErrorCode::kCorrupt, what, "transform output: bytes after the codec block");
  return c;
}

}  // namespace capz
