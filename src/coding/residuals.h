// Residual coding primitives that ANLG (analog_entropy.h, docs/FORMAT.md 11.10) and ATTR
// (attributes_entropy.h, 13.6) both build on, each under its own context numbering: the running
// magnitude that picks an integer residual's context, the zig-zag map of 64-bit differences,
// and raw fields of up to 64 bits.
#pragma once

#include <cstdint>

#include "coding/entropy.h"

namespace capz {

// The contexts a running magnitude picks from (0 .. kMagnitudeContexts - 1).
constexpr int kMagnitudeContexts = 48;

// Running magnitude of a residual sequence: avg in 1/16 units, updated by an exponential mean
// with weight 1/8. Encoder and decoder update it identically after every residual.
struct Magnitude {
  uint64_t avg = 0;
  int context() const {
    // Half-bit steps of log2(avg): 2 * bit length + the bit below the top one.
    const uint64_t a = avg >> 2;
    if (a < 2) return static_cast<int>(a);
    const int bits = 64 - __builtin_clzll(a);
    const int c = 2 * bits - 2 + static_cast<int>((a >> (bits - 2)) & 1);
    return c < kMagnitudeContexts ? c : kMagnitudeContexts - 1;
  }
  void update(uint32_t u) {
    const uint64_t t = static_cast<uint64_t>(u) << 4;
    avg = avg + (t >> 3) - (avg >> 3);
  }
};

inline uint64_t zigzag64(int64_t v) {
  return (static_cast<uint64_t>(v) << 1) ^ static_cast<uint64_t>(v >> 63);
}
inline int64_t unzigzag64(uint64_t u) {
  return static_cast<int64_t>((u >> 1) ^ (0 - (u & 1)));
}

// The n (1..63) low bits of u, raw: in one field when fewer than 32, else the low 32 bits and
// then the rest.
inline void put_raw64(IntEncoder::Cursor* enc, uint64_t u, int n) {
  if (n < 32) {
    enc->raw_bits(static_cast<uint32_t>(u) & ((1u << n) - 1), n);
  } else {
    enc->raw_bits(static_cast<uint32_t>(u), 32);
    enc->raw_bits(static_cast<uint32_t>(u >> 32) & ((1u << (n - 32)) - 1), n - 32);
  }
}
// put_raw64's n bits.
inline uint64_t get_raw64(IntDecoder::Cursor* dec, int n) {
  if (n < 32) return dec->raw_bits(n);
  const uint64_t lo = dec->raw_bits(32);
  return lo | static_cast<uint64_t>(dec->raw_bits(n - 32)) << 32;
}

}  // namespace capz
