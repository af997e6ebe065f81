// Fuzz target: the C3D reader (read_c3d_bytes) on arbitrary bytes. It must return a well-formed
// Take or throw capz::Error. For a file it accepts, the parameter section must survive the trip
// the .capz container gives it (encode_c3d_parameters -> decode_c3d_parameters) without an
// error: otherwise a take that compresses could not be decompressed. Its EVENT group's events
// read, and set back give the same list (labels and count).
#include <cmath>
#include <cstddef>
#include <cstdint>
#include <cstdio>

#include "capz/error.h"
#include "capz/io.h"
#include "coding/c3d_params.h"
#include "fuzz_common.h"

extern "C" int LLVMFuzzerTestOneInput(const uint8_t* data, size_t size) {
  capz::Take t;
  try {
    t = capz::read_c3d_bytes(data, size, "fuzz.c3d");
  } catch (const capz::Error&) {
    return 0;
  }
  capz_fuzz::check_take_shape(t);
  CAPZ_FUZZ_CHECK(t.c3d != nullptr);
  const capz::C3DExtra& x = *t.c3d;
  CAPZ_FUZZ_CHECK(x.residual.size() == t.frames * t.points);
  CAPZ_FUZZ_CHECK(x.camera_mask.size() == t.frames * t.points);
  for (size_t i = 0; i < t.frames * t.points; ++i)
    if (t.valid[i])
      for (int a = 0; a < 3; ++a) CAPZ_FUZZ_CHECK(std::isfinite(t.xyz[i * 3 + a]));
  // The EVENT group's events (what capz info and Python list) read from any section, and set
  // back: no more than TIMES holds, and the same list again.
  const std::vector<capz::C3DEvent> events = capz::c3d_events(x);
  bool settable = events.size() <= 255;
  for (const capz::C3DEvent& e : events)
    settable = settable && std::isfinite(e.time) && e.time >= 0 && e.time < 1e9 &&
               e.icon_id >= -32768 && e.icon_id <= 32767 && e.generic_flag >= -32768 &&
               e.generic_flag <= 32767;
  if (settable) {
    capz::C3DExtra copy = x;
    capz::set_c3d_events(&copy, events);  // events it reads, it can set: never throws
    const std::vector<capz::C3DEvent> again = capz::c3d_events(copy);
    CAPZ_FUZZ_CHECK(again.size() == events.size());
    for (size_t i = 0; i < events.size(); ++i) CAPZ_FUZZ_CHECK(again[i].label == events[i].label);
  }
  try {
    std::vector<uint8_t> params = capz::encode_c3d_parameters(x);
    capz::C3DExtra back;
    capz::decode_c3d_parameters(params.data(), params.size(), "re-encoded parameters", &back);
    CAPZ_FUZZ_CHECK(back.groups.size() == x.groups.size());
  } catch (const capz::Error& e) {
    std::fprintf(stderr, "parameters of an accepted C3D do not survive re-encoding: %s\n",
                 e.what());
    std::abort();
  }
  return 0;
}
