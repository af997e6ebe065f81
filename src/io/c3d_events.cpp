// capz — the C3D EVENT group read and written as a list of events (take.h: c3d_events,
// set_c3d_events): the C3D writers' place for a take's events (foot strikes, foot offs).
// Decoder library (capz_decode).
#include <algorithm>
#include <cmath>
#include <cstdint>
#include <cstdio>
#include <string>
#include <vector>

#include "capz/error.h"
#include "capz/take.h"
#include "io/c3d_internal.h"

namespace capz {

std::vector<C3DEvent> c3d_events(const C3DExtra& x) {
  std::vector<C3DEvent> out;
  if (!x.group("EVENT")) return out;
  const std::vector<float> times = c3d::float_list(x, "EVENT", "TIMES");
  size_t n = times.size() / 2;
  const C3DParameter* used = x.param("EVENT", "USED");
  if (used && (used->type == 1 || used->type == 2)) {  // read unsigned, as every count is
    const std::vector<int> v = used->as_ints();
    if (!v.empty()) n = std::min<size_t>(n, static_cast<uint16_t>(v[0]));
  }
  const auto labels = c3d::string_list(x, "EVENT", "LABELS");
  const auto contexts = c3d::string_list(x, "EVENT", "CONTEXTS");
  const auto descriptions = c3d::string_list(x, "EVENT", "DESCRIPTIONS");
  const auto subjects = c3d::string_list(x, "EVENT", "SUBJECTS");
  const auto icons = c3d::float_list(x, "EVENT", "ICON_IDS");
  const auto flags = c3d::float_list(x, "EVENT", "GENERIC_FLAGS");
  auto text = [](const std::vector<std::string>& v, size_t i) {
    return i < v.size() ? v[i] : std::string();
  };
  auto integer = [](const std::vector<float>& v, size_t i) {
    return i < v.size() && std::fabs(v[i]) < 1e9f ? static_cast<int>(v[i]) : 0;
  };
  out.resize(n);
  for (size_t i = 0; i < n; ++i) {
    C3DEvent& e = out[i];
    e.label = text(labels, i);
    e.context = text(contexts, i);
    e.description = text(descriptions, i);
    e.subject = text(subjects, i);
    e.time = 60.0 * static_cast<double>(times[2 * i]) + static_cast<double>(times[2 * i + 1]);
    e.icon_id = integer(icons, i);
    e.generic_flag = integer(flags, i);
  }
  return out;
}

void set_c3d_events(C3DExtra* x, const std::vector<C3DEvent>& events) {
  const size_t n = events.size();
  if (n > 255)
    fail(ErrorCode::kInvalidParameter, "",
         std::to_string(n) + " events: the C3D EVENT group holds at most 255");
  std::vector<uint8_t> times(8 * n);
  std::vector<std::string> labels, contexts, descriptions, subjects;
  std::vector<int> icons, flags;
  for (size_t i = 0; i < n; ++i) {
    const C3DEvent& e = events[i];
    if (!(std::isfinite(e.time) && e.time >= 0 && e.time < 1e9)) {
      char t[32];
      std::snprintf(t, sizeof t, "%.9g", e.time);
      fail(ErrorCode::kInvalidParameter, "",
           "event " + std::to_string(i) + ": time " + t +
               " is not a time in seconds (finite, 0 to 1e9)");
    }
    for (int v : {e.icon_id, e.generic_flag})
      if (v < -32768 || v > 32767)
        fail(ErrorCode::kInvalidParameter, "",
             "event " + std::to_string(i) + ": icon id or flag " + std::to_string(v) +
                 " is not int16");
    const double minutes = std::floor(e.time / 60);
    c3d::put_f32le(static_cast<float>(minutes), &times[8 * i]);
    c3d::put_f32le(static_cast<float>(e.time - 60 * minutes), &times[8 * i + 4]);
    labels.push_back(e.label);
    contexts.push_back(e.context);
    descriptions.push_back(e.description);
    subjects.push_back(e.subject);
    icons.push_back(e.icon_id);
    flags.push_back(e.generic_flag);
  }
  C3DGroup& g = c3d::ensure_group(x->groups, "EVENT", "Event group");
  c3d::set_int16(c3d::ensure_param(g, "USED", "Number of events"), static_cast<int>(n));
  C3DParameter& t = c3d::ensure_param(g, "TIMES", "Event times (minutes, seconds)");
  t.type = 4;
  t.dims = {2, static_cast<int>(n)};
  t.data = std::move(times);
  c3d::set_string_list(g, "LABELS", labels, "Event labels");
  c3d::set_string_list(g, "CONTEXTS", contexts, "Event contexts");
  c3d::set_string_list(g, "DESCRIPTIONS", descriptions, "Event descriptions");
  c3d::set_string_list(g, "SUBJECTS", subjects, "Event subjects");
  c3d::set_int16_array(c3d::ensure_param(g, "ICON_IDS", "Event icon ids"), icons);
  c3d::set_int16_array(c3d::ensure_param(g, "GENERIC_FLAGS", "Event flags"), flags);
}

}  // namespace capz
