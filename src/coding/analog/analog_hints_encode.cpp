// The encoder's channel hints from a take's C3D parameters (analog_codec.h): the stored-value
// step and offset the representation search tries first.
#include "capz/error.h"
#include "capz/take.h"
#include "coding/analog/analog_codec.h"
#include "coding/c3d_params.h"

namespace capz {

AnalogHints analog_hints(const Take& t) {
  AnalogHints h;
  if (!t.c3d) return h;
  const C3DParameter* gen = t.c3d->param("ANALOG", "GEN_SCALE");
  std::vector<float> s, o;
  float g = 1;
  try {
    s = c3d::float_list(*t.c3d, "ANALOG", "SCALE");
    o = c3d::float_list(*t.c3d, "ANALOG", "OFFSET");
    if (gen && !gen->as_floats().empty()) g = gen->as_floats()[0];
  } catch (const Error&) {
  }
  for (int c = 0; c < t.analog.channels; ++c) {
    analog::ChannelHint ch;
    if (static_cast<size_t>(c) < s.size()) ch.scale = static_cast<double>(s[c]) * g;
    if (static_cast<size_t>(c) < o.size()) ch.offset = -static_cast<double>(o[c]);
    h.channel.push_back(ch);
  }
  return h;
}

}  // namespace capz
