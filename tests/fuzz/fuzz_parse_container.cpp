// Fuzz target: the .capz container layer alone: file header, chunk framing and CRC
// (read_chunk), and the HEAD / META / INDX payload decoders, plus describe() (what `capz info`
// reads). CRCs are made valid first so the payload decoders see the mutations.
#include <cstddef>
#include <cstdint>

#include "capz/codec.h"
#include "capz/error.h"
#include "coding/container.h"
#include "coding/meta.h"
#include "fuzz_common.h"
#include "fuzz_util_capz.h"

extern "C" int LLVMFuzzerTestOneInput(const uint8_t* data, size_t size) {
  std::vector<uint8_t> v = capz_fuzz::with_fixed_crcs(data, size);
  try {
    capz::describe(v.data(), v.size(), "fuzz.capz");
  } catch (const capz::Error&) {
  }
  try {
    capz::check_file_header(v.data(), v.size(), "fuzz.capz");
    capz::StreamHeader h;
    bool have_head = false;
    size_t off = capz::kFileHeaderBytes;
    while (off < v.size()) {
      capz::Chunk c = capz::read_chunk(v.data(), v.size(), off, "fuzz.capz");
      CAPZ_FUZZ_CHECK(c.end > off && c.end <= v.size());
      off = c.end;
      try {
        if (c.type == "HEAD") {
          // decode_meta's precondition, as in the decoder; a later HEAD that fails it must not
          // replace the one META is read with.
          capz::StreamHeader next = capz::decode_header(c, "fuzz.capz");
          capz::check_header_fits(next, v.size(), "fuzz.capz");
          h = next;
          have_head = true;
        } else if (c.type == "META" && have_head) {
          capz::Take t;
          t.frames = static_cast<size_t>(h.frames);
          t.points = h.points;
          bool words = false;
          capz::decode_meta(c, "fuzz.capz", &t, &words);
        } else if (c.type == "INDX") {
          capz::decode_index(c, "fuzz.capz");
        }
      } catch (const capz::Error&) {
      }
    }
  } catch (const capz::Error&) {
  }
  return 0;
}
