// capz._capz: a take's C3D metadata (the parameter section, read and set; residuals and camera
// masks; header events; analog in its units) and a TRC's columns (py_common.h).
#include <pybind11/stl.h>

#include <algorithm>
#include <cctype>
#include <cstdint>
#include <cstdlib>
#include <cstring>
#include <optional>
#include <string>
#include <vector>

#include "capz/error.h"
#include "capz/io.h"
#include "capz/take.h"
#include "py_common.h"

namespace capz_py {

namespace {

bool valid_utf8(const std::string& s) {
  size_t i = 0;
  while (i < s.size()) {
    const auto c = static_cast<unsigned char>(s[i]);
    const size_t n = c < 0x80 ? 1 : (c >> 5) == 6 ? 2 : (c >> 4) == 14 ? 3 : (c >> 3) == 30 ? 4 : 0;
    if (n == 0 || i + n > s.size()) return false;
    for (size_t k = 1; k < n; ++k)
      if ((static_cast<unsigned char>(s[i + k]) >> 6) != 2) return false;
    i += n;
  }
  return true;
}

bool all_utf8(const std::vector<std::string>& v) {
  return std::all_of(v.begin(), v.end(), valid_utf8);
}

}  // namespace

py::list events_list(const std::vector<capz::C3DEvent>& events) {
  py::list out;
  for (const capz::C3DEvent& e : events) {
    py::dict d;
    d["label"] = text(e.label);
    d["context"] = text(e.context);
    d["time"] = e.time;
    d["description"] = text(e.description);
    d["subject"] = text(e.subject);
    d["icon_id"] = e.icon_id;
    d["generic_flag"] = e.generic_flag;
    out.append(d);
  }
  return out;
}

bool latin1_text(const capz::Take& t) {
  if (!all_utf8(t.labels) || !all_utf8(t.descriptions) || !all_utf8(t.analog.labels)) return true;
  if (t.c3d)
    for (const capz::C3DGroup& g : t.c3d->groups) {
      if (!valid_utf8(g.name) || !valid_utf8(g.description)) return true;
      for (const capz::C3DParameter& p : g.params)
        if (!valid_utf8(p.name) || !valid_utf8(p.description) ||
            (p.type == -1 && !valid_utf8(std::string(p.data.begin(), p.data.end()))))
          return true;
    }
  return false;
}

std::string file_text(const py::handle& s, bool latin1) {
  if (latin1) {
    PyObject* b = PyUnicode_AsLatin1String(s.ptr());
    if (b) return py::reinterpret_steal<py::bytes>(b).cast<std::string>();
    PyErr_Clear();  // a character Latin-1 has no byte for: UTF-8
  }
  return s.cast<std::string>();
}

namespace {

// A C3D parameter's value: a char array of at most one dimension as a str, of more as a list
// of str (dims[0] characters each, the other dimensions flattened in file order); numbers as a
// numpy array of the stored type (uint8, int16, float32), its shape the C3D dimensions reversed
// (C order, so the last index varies fastest, as C3D's first dimension does); a number without
// dimensions as a Python number.
py::object parameter_value(const capz::C3DParameter& p) {
  const size_t count = p.element_count(), size = static_cast<size_t>(std::abs(p.type));
  if (size == 0 || p.data.size() != count * size)
    capz::fail(capz::ErrorCode::kInternal, "",
               "parameter " + p.name + " holds " + std::to_string(p.data.size()) + " bytes");
  const char* bytes = reinterpret_cast<const char*>(p.data.data());
  if (p.type == -1) {
    if (p.dims.size() <= 1) return text(p.as_string());
    return texts(p.as_strings());
  }
  const char* dt = p.type == 1 ? "u1" : p.type == 2 ? "<i2" : "<f4";
  if (p.dims.empty()) {
    if (p.type == 4) {
      float f;
      std::memcpy(&f, bytes, 4);
      return py::float_(static_cast<double>(f));
    }
    if (p.type == 2) {
      int16_t v;
      std::memcpy(&v, bytes, 2);
      return py::int_(static_cast<int>(v));
    }
    return py::int_(static_cast<int>(p.data[0]));
  }
  std::vector<py::ssize_t> shape;
  for (size_t i = p.dims.size(); i-- > 0;) shape.push_back(std::max(0, p.dims[i]));
  py::array a(py::dtype(dt), shape);
  if (!p.data.empty()) std::memcpy(a.mutable_data(), bytes, p.data.size());
  return std::move(a);
}

// Appends x to data as a little-endian int16 (a value in -32768 .. 65535).
void put_int16(long long x, std::vector<uint8_t>* data) {
  if (x < -32768 || x > 65535) invalid("set_parameter: " + std::to_string(x) + " is not int16");
  const uint16_t u = static_cast<uint16_t>(x);
  data->push_back(static_cast<uint8_t>(u & 0xFF));
  data->push_back(static_cast<uint8_t>(u >> 8));
}

// Appends x to data as a float32's bytes.
void put_float32(double x, std::vector<uint8_t>* data) {
  const float f = static_cast<float>(x);
  uint8_t b[4];
  std::memcpy(b, &f, 4);
  data->insert(data->end(), b, b + 4);
}

// A list or tuple of str as a 2-D char parameter, each string blank padded to the longest.
void strings_parameter(const py::handle& v, bool latin1, capz::C3DParameter* p) {
  std::vector<std::string> strings;
  for (const py::handle& e : v) {
    if (!py::isinstance<py::str>(e)) invalid("set_parameter: a list value must hold str only");
    strings.push_back(file_text(e, latin1));
  }
  size_t width = 0;
  for (const std::string& x : strings) width = std::max(width, x.size());
  p->type = -1;
  p->dims = {static_cast<int>(width), static_cast<int>(strings.size())};
  for (std::string x : strings) {
    x.resize(width, ' ');
    p->data.insert(p->data.end(), x.begin(), x.end());
  }
}

// A numpy array as a byte, int16 or float32 parameter, its dimensions the shape reversed.
void array_parameter(const py::array& a, capz::C3DParameter* p) {
  const char kind = a.dtype().kind();
  if (a.ndim() > 7) invalid("set_parameter: a C3D parameter has at most 7 dimensions");
  for (py::ssize_t k = a.ndim(); k-- > 0;) p->dims.push_back(static_cast<int>(a.shape(k)));
  if (kind == 'u' && a.itemsize() == 1) {
    p->type = 1;
    const py::array_t<uint8_t, py::array::c_style | py::array::forcecast> b(a);
    p->data.assign(b.data(), b.data() + b.size());
  } else if (kind == 'i' || kind == 'u') {
    p->type = 2;
    const py::array_t<long long, py::array::c_style | py::array::forcecast> b(a);
    for (py::ssize_t i = 0; i < b.size(); ++i) put_int16(b.data()[i], &p->data);
  } else if (kind == 'f') {
    p->type = 4;
    const py::array_t<double, py::array::c_style | py::array::forcecast> b(a);
    for (py::ssize_t i = 0; i < b.size(); ++i) put_float32(b.data()[i], &p->data);
  } else {
    invalid("set_parameter: numpy dtype " + py::str(a.dtype()).cast<std::string>() +
            " has no C3D type (uint8, integers, floats)");
  }
}

// Take.set_parameter's value as a C3D parameter's type, dimensions and bytes: a str is a char
// array of one dimension, a list or tuple of str a 2-D one (blank padded to the longest); an int
// an int16, a float a float32; a numpy array uint8 (byte), any other integer type (int16, each
// value in -32768 .. 65535) or float (float32), its dimensions the array's shape reversed.
void parameter_from_python(const py::handle& v, bool latin1, capz::C3DParameter* p) {
  p->data.clear();
  p->dims.clear();
  if (py::isinstance<py::str>(v)) {
    const std::string s = file_text(v, latin1);
    p->type = -1;
    p->dims = {static_cast<int>(s.size())};
    p->data.assign(s.begin(), s.end());
  } else if (py::isinstance<py::list>(v) || py::isinstance<py::tuple>(v)) {
    strings_parameter(v, latin1, p);
  } else if (py::isinstance<py::bool_>(v)) {
    invalid("set_parameter: a bool has no C3D type (give 0 or 1)");
  } else if (py::isinstance<py::int_>(v)) {
    p->type = 2;
    put_int16(v.cast<long long>(), &p->data);
  } else if (py::isinstance<py::float_>(v)) {
    p->type = 4;
    put_float32(v.cast<double>(), &p->data);
  } else if (py::isinstance<py::array>(v)) {
    array_parameter(py::reinterpret_borrow<py::array>(v), p);
  } else {
    invalid(
        "set_parameter: the value must be a str, a list of str, an int, a float or a numpy "
        "array");
  }
  for (int d : p->dims)
    if (d > 255)
      invalid("set_parameter: a C3D dimension holds at most 255, not " + std::to_string(d));
}

bool same_name(const std::string& a, const std::string& b) {
  return a.size() == b.size() && std::equal(a.begin(), a.end(), b.begin(), [](char x, char y) {
           return std::toupper(static_cast<unsigned char>(x)) ==
                  std::toupper(static_cast<unsigned char>(y));
         });
}

// Sets (or adds) parameter GROUP:NAME; a new group gets the next free group number. A take
// without a parameter section (from_arrays, TRC, PCD) first gets the one write_c3d would give it
// (docs/PYTHON.md), so that the section holds what a C3D reader needs besides what is set.
void set_parameter(capz::Take& t, const std::string& group, const std::string& name,
                   const py::handle& value, const py::object& described) {
  const bool latin1 = latin1_text(t);
  std::optional<std::string> description;
  if (!described.is_none()) {
    if (!py::isinstance<py::str>(described)) invalid("set_parameter: a description is a str");
    description = file_text(described, latin1);
  }
  for (const std::string* n : {&group, &name})
    if (n->empty() || n->size() > 127 || n->find('\0') != std::string::npos ||
        n->find(' ') != std::string::npos)
      invalid("set_parameter: '" + *n + "' is not a C3D name (1 to 127 characters, no blanks)");
  if (description && description->size() > 255)
    invalid("set_parameter: a description holds at most 255 characters");
  capz::C3DParameter p;
  parameter_from_python(value, latin1, &p);
  if (!t.c3d) t.c3d = capz::new_c3d_parameters(t, "set_parameter");
  capz::C3DGroup* g = nullptr;
  int top = 0;
  for (capz::C3DGroup& x : t.c3d->groups) {
    top = std::max(top, std::abs(x.id));
    if (!g && same_name(x.name, group)) g = &x;
  }
  if (!g) {
    if (top >= 127) invalid("set_parameter: no free C3D group number for " + group);
    capz::C3DGroup ng;
    ng.id = top + 1;
    ng.name = group;
    t.c3d->groups.push_back(std::move(ng));
    g = &t.c3d->groups.back();
  }
  for (capz::C3DParameter& q : g->params)
    if (same_name(q.name, name)) {
      q.type = p.type;
      q.dims = std::move(p.dims);
      q.data = std::move(p.data);
      if (description) q.description = *description;
      return;
    }
  p.name = name;
  if (description) p.description = *description;
  g->params.push_back(std::move(p));
}

// Take.set_events: a list of dicts with the keys Take.events gives (time required, the others
// "" or 0 when left out) as the EVENT group's events; a take without a section gets
// set_parameter's. A refusal changes nothing.
void set_events(capz::Take& t, const py::list& events) {
  const bool latin1 = latin1_text(t);
  std::vector<capz::C3DEvent> v;
  for (size_t i = 0; i < events.size(); ++i) {
    const std::string at = "set_events: event " + std::to_string(i);
    if (!py::isinstance<py::dict>(events[i])) invalid(at + " is not a dict");
    capz::C3DEvent e;
    bool timed = false;
    for (const auto& kv : py::cast<py::dict>(events[i])) {
      const std::string key = py::str(kv.first);
      const py::handle val = kv.second;
      std::string* text = key == "label"         ? &e.label
                          : key == "context"     ? &e.context
                          : key == "description" ? &e.description
                          : key == "subject"     ? &e.subject
                                                 : nullptr;
      int* number = key == "icon_id"        ? &e.icon_id
                    : key == "generic_flag" ? &e.generic_flag
                                            : nullptr;
      if (text) {
        if (!py::isinstance<py::str>(val)) invalid(at + ": " + key + " is not a str");
        *text = file_text(val, latin1);
      } else if (number) {
        if (!py::isinstance<py::int_>(val) || py::isinstance<py::bool_>(val))
          invalid(at + ": " + key + " is not an int");
        const long long x = val.cast<long long>();
        if (x < -32768 || x > 32767) invalid(at + ": " + key + " is not int16");
        *number = static_cast<int>(x);
      } else if (key == "time") {
        if (!(py::isinstance<py::float_>(val) || py::isinstance<py::int_>(val)) ||
            py::isinstance<py::bool_>(val))
          invalid(at + ": time is not a number of seconds");
        e.time = val.cast<double>();
        timed = true;
      } else {
        invalid(at + ": unknown key '" + key +
                "' (label, context, time, description, subject, icon_id, generic_flag)");
      }
    }
    if (!timed) invalid(at + " has no time");
    v.push_back(std::move(e));
  }
  // set_c3d_events changes nothing when it refuses, and a section made here is kept only then.
  std::shared_ptr<capz::C3DExtra> x = t.c3d ? t.c3d : capz::new_c3d_parameters(t, "set_events");
  capz::set_c3d_events(x.get(), v);
  t.c3d = std::move(x);
}

// A view (frames, points) of one of the C3D sample words (residual, camera_mask), or None when
// the take has none.
template <typename T>
py::object sample_words(const py::object& self, std::vector<T> capz::C3DExtra::*words) {
  const auto& t = self.cast<const capz::Take&>();
  if (!t.c3d || ((*t.c3d).*words).size() != t.frames * t.points) return py::none();
  return view(self, py::dtype::of<T>(), {ss(t.frames), ss(t.points)}, ((*t.c3d).*words).data());
}

py::dict parameters_of(const capz::Take& t) {
  py::dict d;
  if (!t.c3d) return d;
  for (const capz::C3DGroup& g : t.c3d->groups) {
    const py::str key = text(g.key());
    py::dict params = d.contains(key) ? py::dict(d[key]) : py::dict();
    for (const capz::C3DParameter& p : g.params) params[text(p.name)] = parameter_value(p);
    d[key] = params;
  }
  return d;
}

py::object parameter_of(const capz::Take& t, const std::string& group, const std::string& name) {
  if (!t.c3d) return py::none();
  for (const capz::C3DGroup& g : t.c3d->groups) {
    if (!same_name(g.key(), group)) continue;
    const capz::C3DParameter* p = g.find(name);
    if (!p) continue;
    py::dict d;
    d["value"] = parameter_value(*p);
    d["description"] = text(p->description);
    d["type"] = p->type_name();
    d["dims"] = p->dims;
    d["locked"] = p->locked;
    d["group_description"] = text(g.description);
    return std::move(d);
  }
  return py::none();
}

// Take's C3D parameters: set_parameter, parameters and parameter.
void bind_take_c3d_parameters(TakeClass* cls) {
  (*cls)
      .def("set_parameter", &set_parameter, py::arg("group"), py::arg("name"), py::arg("value"),
           py::arg("description") = py::none(),
           "sets C3D parameter GROUP:NAME (added when absent; names matched without regard to "
           "case); a take without a section (from_arrays, TRC, PCD) first gets the one write() "
           "would give it alone. value a str, a list of str, an int (int16), a float "
           "(float32) or a numpy array (uint8 -> byte, integers -> int16, floats -> float32; "
           "its shape reversed as the C3D dimensions, each at most 255). write() and compress() "
           "keep it; write() rewrites the POINT, ANALOG, TRIAL and ROTATION fields that "
           "describe the data from the take")
      .def_property_readonly(
          "parameters", [](const capz::Take& t) { return parameters_of(t); },
          "the C3D parameter section: dict group -> dict parameter -> value (str for a char "
          "array, list of str for a 2-D one, numpy uint8/int16/float32 array with the C3D "
          "dimensions reversed, a number when it has no dimensions); {} when the take has no "
          "section (not read from C3D, nothing set). A copy: changing it does not change the "
          "take")
      .def(
          "parameter",
          [](const capz::Take& t, const std::string& group, const std::string& name) {
            return parameter_of(t, group, name);
          },
          py::arg("group"), py::arg("name"),
          "one C3D parameter, names matched without regard to case: dict with value (as in "
          "parameters), description, type (\"char\", \"byte\", \"int16\", \"float\"), dims (as "
          "the file gives them, first varying fastest), locked and group_description; None when "
          "absent");
}

// Take's C3D sample words: residuals and camera masks.
void bind_take_c3d_samples(TakeClass* cls) {
  (*cls)
      .def_property_readonly(
          "residuals",
          [](const py::object& self) { return sample_words(self, &capz::C3DExtra::residual); },
          "C3D point residuals, float32 (frames, points) in the take's units as the file "
          "stores them (-1 at a gap); None when the take did not come from C3D (a view, like "
          "xyz)")
      .def_property_readonly(
          "camera_masks",
          [](const py::object& self) { return sample_words(self, &capz::C3DExtra::camera_mask); },
          "C3D camera masks, uint8 (frames, points): bit k set when camera k + 1 saw the "
          "point (0 at a gap); None when the take did not come from C3D (a view, like xyz)");
}

// Take's C3D events: the EVENT group's, setting them, and the header's event table.
void bind_take_c3d_events(TakeClass* cls) {
  (*cls)
      .def_property_readonly(
          "events",
          [](const capz::Take& t) {
            return t.c3d ? events_list(capz::c3d_events(*t.c3d)) : py::list();
          },
          "the C3D EVENT group's events (foot strikes, foot offs, ...) in stored order: list of "
          "dict label, context (\"Left\", \"Right\", \"General\"), time (s: TIMES' minutes x "
          "60 + seconds), description, subject, icon_id, generic_flag; [] without an EVENT group. "
          "The header's event table is header_events")
      .def("set_events", &set_events, py::arg("events"),
           "replaces the C3D EVENT group's events with a list of dicts of the keys events gives "
           "(time in seconds required; label, context, description, subject \"\" and "
           "icon_id, generic_flag 0 when left out), at most 255; a take without a parameter "
           "section first gets the one write() would give it alone. write() and compress() "
           "keep them; a refusal changes nothing")
      .def_property_readonly(
          "header_events",
          [](const capz::Take& t) {
            py::list out;
            if (t.c3d)
              for (const capz::C3DHeaderEvent& e : t.c3d->header_events) {
                py::dict d;
                d["label"] = text(e.label);
                d["time"] = static_cast<double>(e.time);
                d["display"] = e.display;
                out.append(d);
              }
            return out;
          },
          "the C3D header's event table (at most 18, labels of 4 characters, older writers): "
          "list of dict label, time (s), display. Most files keep their events in the EVENT "
          "group: events");
}

}  // namespace

// Take: the C3D parameter section, sample words and header events.
void bind_take_c3d(TakeClass* cls) {
  bind_take_c3d_parameters(cls);
  bind_take_c3d_samples(cls);
  bind_take_c3d_events(cls);
}

// Take: a TRC file's Time and Frame# columns and its header's rates.
void bind_take_trc(TakeClass* cls) {
  (*cls).def_property_readonly(
      "trc",
      [](const capz::Take& t) -> py::object {
        if (!t.trc) return py::none();
        const capz::TRCExtra& x = *t.trc;
        py::dict d;
        d["times"] = py::array_t<double>(ss(x.times.size()), x.times.data());
        d["frame_numbers"] =
            py::array_t<int64_t>(ss(x.frame_numbers.size()), x.frame_numbers.data());
        d["camera_rate"] = x.camera_rate;
        d["orig_data_rate"] = x.orig_data_rate;
        d["orig_data_start_frame"] = x.orig_data_start_frame;
        d["orig_num_frames"] = x.orig_num_frames;
        return std::move(d);
      },
      "a TRC file's Time column (float64 seconds, one per frame), Frame# column (int64) and "
      "its header's CameraRate, OrigDataRate, OrigDataStartFrame and OrigNumFrames, as a dict "
      "of copies; None when the take did not come from TRC");
}

}  // namespace capz_py
