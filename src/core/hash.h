// capz — the content checksum of an original file: XXH3-128 (libxxhash), fed in pieces.
//
// Contract: Hasher h; h.update(a, n1); h.update(b, n2); h.digest() equals the XXH3-128 of the
// bytes a[0..n1) b[0..n2) taken as one buffer, however they are split (the seed is 0). The
// digest's stored form is XXH3's canonical one: 16 bytes, the high 64 bits first, each half
// big-endian (the bytes `xxhsum -H2` prints as hex).
#pragma once

#include <array>
#include <cstddef>
#include <cstdint>
#include <memory>
#include <string>

namespace capz {

using Digest128 = std::array<uint8_t, 16>;

class Hasher {
 public:
  Hasher();
  ~Hasher();
  Hasher(const Hasher&) = delete;
  Hasher& operator=(const Hasher&) = delete;

  void update(const void* data, size_t size);
  // The digest of every byte given so far; update() may go on after it.
  Digest128 digest() const;

 private:
  struct State;
  std::unique_ptr<State> state_;
};

// XXH3-128 of one buffer.
Digest128 hash128(const void* data, size_t size);
// XXH3-128 of a whole file, read in 1 MiB pieces (Error(kIo) when it cannot be read).
Digest128 hash128_file(const std::string& path);
// 32 lower-case hex digits of the canonical form.
std::string digest_hex(const Digest128& d);

}  // namespace capz
