// Fuzz target: a take built from the fuzz bytes (fuzz_take.h says how) -> compress -> decompress
// must come back with the same shape and gap mask, every valid coordinate within the bound
// (bit-exact when lossless; for a KG target with a transform, whose reconstruction is the output
// and has no bound, finite with a KG error at most the target), and the same rate, units and
// labels. compress may refuse an impossible target (kInvalidParameter); any other capz::Error, in
// particular a failed self-check (kInternal), is a finding.
#include <cstddef>
#include <cstdint>
#include <cstdio>
#include <cstdlib>

#include "capz/codec.h"
#include "capz/error.h"
#include "fuzz_take.h"

extern "C" int LLVMFuzzerTestOneInput(const uint8_t* data, size_t size) {
  capz_fuzz::RoundTripCase c;
  if (!capz_fuzz::round_trip_case(data, size, &c)) return 0;
  std::vector<uint8_t> bytes;
  try {
    bytes = capz::compress(c.take, c.opts);
  } catch (const capz::Error& e) {
    if (e.code() == capz::ErrorCode::kInvalidParameter) return 0;
    std::fprintf(stderr, "compress failed: %s\n", e.what());
    std::abort();
  }
  capz_fuzz::check_round_trip(c, bytes);
  return 0;
}
