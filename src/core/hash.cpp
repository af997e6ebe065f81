// capz — XXH3-128 content checksum (see hash.h).
#include "core/hash.h"

#include <xxhash.h>

#include <algorithm>
#include <vector>

#include "capz/error.h"
#include "core/input_file.h"

namespace capz {

struct Hasher::State {
  XXH3_state_t* s = nullptr;
};

Hasher::Hasher() : state_(new State) {
  state_->s = XXH3_createState();
  if (!state_->s || XXH3_128bits_reset(state_->s) != XXH_OK)
    fail(ErrorCode::kInternal, "", "XXH3: cannot create a hash state");
}

Hasher::~Hasher() {
  XXH3_freeState(state_->s);
}

void Hasher::update(const void* data, size_t size) {
  if (size == 0) return;
  if (XXH3_128bits_update(state_->s, data, size) != XXH_OK)
    fail(ErrorCode::kInternal, "", "XXH3: update failed");
}

Digest128 Hasher::digest() const {
  XXH128_canonical_t c;
  XXH128_canonicalFromHash(&c, XXH3_128bits_digest(state_->s));
  Digest128 d;
  for (size_t i = 0; i < d.size(); ++i) d[i] = c.digest[i];
  return d;
}

Digest128 hash128(const void* data, size_t size) {
  Hasher h;
  h.update(data, size);
  return h.digest();
}

Digest128 hash128_file(const std::string& path) {
  InputFile in(path);
  Hasher h;
  std::vector<uint8_t> buf(size_t{1} << 20);
  for (uint64_t at = 0; at < in.size();) {
    const size_t n = static_cast<size_t>(std::min<uint64_t>(buf.size(), in.size() - at));
    in.read_at(at, buf.data(), n);
    h.update(buf.data(), n);
    at += n;
  }
  return h.digest();
}

std::string digest_hex(const Digest128& d) {
  static const char* kHex = "0123456789abcdef";
  std::string s;
  for (uint8_t b : d) {
    s += kHex[b >> 4];
    s += kHex[b & 15];
  }
  return s;
}

}  // namespace capz
