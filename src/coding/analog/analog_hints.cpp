// What a take's C3D parameters say of its analog channels' physics (analog_physics: scale,
// offset, units, the stored range), read by the encoder's bounds and by describe(); the
// encoder's representation hints are analog_hints_encode.cpp.
#include <algorithm>
#include <cctype>
#include <cfloat>
#include <cmath>

#include "capz/error.h"
#include "capz/take.h"
#include "coding/analog/analog_codec.h"
#include "coding/c3d_params.h"

namespace capz {

namespace {
std::string trimmed(const std::string& s) {
  const size_t a = s.find_first_not_of(" \t\r\n");
  if (a == std::string::npos) return "";
  return s.substr(a, s.find_last_not_of(" \t\r\n") - a + 1);
}
}  // namespace

std::string canonical_analog_unit(const std::string& unit) {
  const std::string u = trimmed(unit);
  std::string k;  // lower case, without separators
  for (char ch : u)
    if (ch != ' ' && ch != '.' && ch != '-' && ch != '*' && ch != '_')
      k += static_cast<char>(std::tolower(static_cast<unsigned char>(ch)));
  static const std::pair<const char*, const char*> kAliases[] = {{"v", "V"},
                                                                 {"volt", "V"},
                                                                 {"volts", "V"},
                                                                 {"mv", "mV"},
                                                                 {"millivolt", "mV"},
                                                                 {"millivolts", "mV"},
                                                                 {"uv", "uV"},
                                                                 {"\xc2\xb5v", "uV"},
                                                                 {"microvolt", "uV"},
                                                                 {"microvolts", "uV"},
                                                                 {"n", "N"},
                                                                 {"nt", "N"},
                                                                 {"newton", "N"},
                                                                 {"newtons", "N"},
                                                                 {"nm", "Nm"},
                                                                 {"ntm", "Nm"},
                                                                 {"newtonmetre", "Nm"},
                                                                 {"newtonmeter", "Nm"},
                                                                 {"nmm", "Nmm"},
                                                                 {"ntmm", "Nmm"},
                                                                 {"newtonmillimetre", "Nmm"},
                                                                 {"newtonmillimeter", "Nmm"}};
  for (const auto& a : kAliases)
    if (k == a.first) return a.second;
  return u;
}

std::vector<AnalogPhysics> analog_physics(const Take& t) {
  const size_t C = static_cast<size_t>(std::max(0, t.analog.channels));
  std::vector<AnalogPhysics> out(C);
  bool integers = false, unsigned_ = false;
  std::vector<float> s, o;
  std::vector<std::string> units;
  float g = 1;
  if (t.c3d) {
    integers = !t.c3d->float_storage;
    const C3DParameter* gen = t.c3d->param("ANALOG", "GEN_SCALE");
    const C3DParameter* format = t.c3d->param("ANALOG", "FORMAT");
    try {
      s = c3d::float_list(*t.c3d, "ANALOG", "SCALE");
      o = c3d::float_list(*t.c3d, "ANALOG", "OFFSET");
      if (gen && !gen->as_floats().empty()) g = gen->as_floats()[0];
      units = c3d::string_list(*t.c3d, "ANALOG", "UNITS");
      if (format && format->type == -1) {
        std::string f = trimmed(format->as_string());
        for (char& ch : f) ch = static_cast<char>(std::toupper(static_cast<unsigned char>(ch)));
        unsigned_ = f == "UNSIGNED";
      }
    } catch (const Error&) {
    }
  }
  for (size_t c = 0; c < C; ++c) {
    AnalogPhysics& p = out[c];
    if (c < s.size()) {
      p.scale = static_cast<double>(s[c]) * static_cast<double>(g);
      p.factor = std::fabs(p.scale);
    }
    if (c < o.size()) p.offset = static_cast<double>(o[c]);
    if (c < units.size()) p.unit = trimmed(units[c]);
    p.integers = integers;
    p.lo = integers ? (unsigned_ ? 0.0 : -32768.0) : -static_cast<double>(FLT_MAX);
    p.hi = integers ? (unsigned_ ? 65535.0 : 32767.0) : static_cast<double>(FLT_MAX);
  }
  return out;
}

}  // namespace capz
