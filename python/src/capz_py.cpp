// capz._capz: the library's Take and calls for Python (python/capz/__init__.py wraps this module
// and checks arguments; docs/PYTHON.md documents the package).
//
// - A Take's arrays are numpy views of the Take's own storage (no copy on the way out); each
//   view keeps the Take alive. Gap samples' coordinates are unspecified by contract (take.h),
//   so a Take handed to Python has NaN there.
// - Arrays on the way in arrive checked and contiguous (the Python layer) and are copied once
//   into the Take's storage.
// - Reading, writing and coding run with the GIL released; each call works on its own Take, so
//   several threads can code separate Takes at once.
// - capz::Error becomes capz.Error (python/capz/_error.py) with the code's name, the message and
//   the CLI's exit status.
#include <pybind11/numpy.h>
#include <pybind11/pybind11.h>
#include <pybind11/stl.h>

#include <algorithm>
#include <cctype>
#include <cmath>
#include <cstdio>
#include <cstring>
#include <fstream>
#include <limits>
#include <map>
#include <memory>
#include <optional>
#include <string>
#include <utility>
#include <vector>

#include "capz/codec.h"
#include "capz/compress_file.h"
#include "capz/error.h"
#include "capz/file.h"
#include "capz/io.h"
#include "capz/metrics.h"
#include "capz/original.h"
#include "capz/version.h"

namespace py = pybind11;

namespace {

using TakePtr = std::shared_ptr<capz::Take>;

[[noreturn]] void invalid(const std::string& what) {
  capz::fail(capz::ErrorCode::kInvalidParameter, "", what);
}

// A Take for Python: its arrays checked against its counts (the views rely on them), validity
// as 0 or 1 (numpy's bool), gaps set to NaN (their values are unspecified by contract).
TakePtr adopt(capz::Take&& t) {
  auto p = std::make_shared<capz::Take>(std::move(t));
  const size_t n = p->frames * p->points;
  if (p->xyz.size() != n * 3 || p->valid.size() != n)
    capz::fail(capz::ErrorCode::kInternal, p->source,
               "take arrays do not match its frame and point counts");
  const double nan = std::numeric_limits<double>::quiet_NaN();
  for (size_t i = 0; i < n; ++i) {
    p->valid[i] = p->valid[i] ? 1 : 0;
    if (!p->valid[i]) p->xyz[3 * i] = p->xyz[3 * i + 1] = p->xyz[3 * i + 2] = nan;
  }
  return p;
}

// A numpy array over `data` (C order unless `strides` are given) that keeps `owner` alive.
py::array view(py::handle owner, const py::dtype& dt, const std::vector<py::ssize_t>& shape,
               const void* data, std::vector<py::ssize_t> strides = {}) {
  if (strides.empty()) {
    strides.assign(shape.size(), dt.itemsize());
    for (size_t i = shape.size(); i-- > 1;) strides[i - 1] = strides[i] * shape[i];
  }
  return py::array(dt, shape, strides, data, owner);
}

py::ssize_t ss(size_t v) {
  return static_cast<py::ssize_t>(v);
}

// Text from a C3D file as a Python str: UTF-8 when it is valid UTF-8, else Latin-1 (older
// files), so that no label or parameter fails to read.
py::str text(const std::string& s) {
  PyObject* o = PyUnicode_DecodeUTF8(s.data(), ss(s.size()), nullptr);
  if (!o) {
    PyErr_Clear();
    o = PyUnicode_DecodeLatin1(s.data(), ss(s.size()), nullptr);
  }
  if (!o) throw py::error_already_set();
  return py::reinterpret_steal<py::str>(o);
}

py::list texts(const std::vector<std::string>& v) {
  py::list out;
  for (const std::string& x : v) out.append(text(x));
  return out;
}

// numpy's name of a PCD field type: 'F' 4 -> "<f4", 'U' 2 -> "<u2", 'I' 8 -> "<i8".
std::string attribute_dtype(char type, int size) {
  const char kind = type == 'F' ? 'f' : type == 'U' ? 'u' : type == 'I' ? 'i' : '?';
  const bool ok = kind != '?' && (size == 1 || size == 2 || size == 4 || size == 8) &&
                  (kind != 'f' || size == 4 || size == 8);
  if (!ok)
    invalid("attribute type " + std::string(1, type) + " of " + std::to_string(size) +
            " bytes has no numpy dtype");
  return std::string("<") + kind + std::to_string(size);
}

py::dict attributes_of(py::handle self, const capz::Take& t) {
  py::dict d;
  std::map<std::string, int> seen;
  for (const capz::PointAttribute& a : t.attributes) {
    const size_t count = static_cast<size_t>(a.count);
    if (a.count < 1 || a.data.size() != t.frames * t.points * a.bytes_per_point())
      capz::fail(capz::ErrorCode::kInternal, t.source,
                 "attribute '" + a.name + "' holds " + std::to_string(a.data.size()) +
                     " bytes, not frames x points x count x size");
    std::vector<py::ssize_t> shape = {ss(t.frames), ss(t.points)};
    if (count > 1) shape.push_back(ss(count));
    // A name repeated in the source (PCD padding "_") gets "#2", "#3", ...
    const int n = ++seen[a.name];
    const std::string key = n == 1 ? a.name : a.name + "#" + std::to_string(n);
    d[py::str(key)] = view(self, py::dtype(attribute_dtype(a.type, a.size)), shape, a.data.data());
  }
  return d;
}

// A char array's strings: each `width` characters, trailing blanks and NULs removed.
std::string trim_text(const char* p, size_t n) {
  while (n > 0 && (p[n - 1] == ' ' || p[n - 1] == '\0')) --n;
  return std::string(p, n);
}

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
    if (p.dims.size() <= 1) return text(trim_text(bytes, p.data.size()));
    const size_t width = static_cast<size_t>(std::max(0, p.dims[0]));
    py::list out;
    if (width > 0)
      for (size_t i = 0; i + width <= p.data.size(); i += width)
        out.append(text(trim_text(bytes + i, width)));
    return std::move(out);
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

const char* parameter_type(int8_t type) {
  return type == -1 ? "char" : type == 1 ? "byte" : type == 2 ? "int16" : "float";
}

// A group's key in Take.parameters: its name, or "#<id>" for parameters whose group has no
// entry in the file.
std::string group_key(const capz::C3DGroup& g) {
  return g.name.empty() ? "#" + std::to_string(g.id) : g.name;
}

// Take.set_parameter's value as a C3D parameter's type, dimensions and bytes: a str is a char
// array of one dimension, a list or tuple of str a 2-D one (blank padded to the longest); an int
// an int16, a float a float32; a numpy array uint8 (byte), any other integer type (int16, each
// value in -32768 .. 65535) or float (float32), its dimensions the array's shape reversed.
void parameter_from_python(const py::handle& v, capz::C3DParameter* p) {
  auto put16 = [&](long long x) {
    if (x < -32768 || x > 65535) invalid("set_parameter: " + std::to_string(x) + " is not int16");
    const uint16_t u = static_cast<uint16_t>(x);
    p->data.push_back(static_cast<uint8_t>(u & 0xFF));
    p->data.push_back(static_cast<uint8_t>(u >> 8));
  };
  auto put32 = [&](double x) {
    const float f = static_cast<float>(x);
    uint8_t b[4];
    std::memcpy(b, &f, 4);
    p->data.insert(p->data.end(), b, b + 4);
  };
  p->data.clear();
  p->dims.clear();
  if (py::isinstance<py::str>(v)) {
    const std::string s = v.cast<std::string>();
    p->type = -1;
    p->dims = {static_cast<int>(s.size())};
    p->data.assign(s.begin(), s.end());
  } else if (py::isinstance<py::list>(v) || py::isinstance<py::tuple>(v)) {
    std::vector<std::string> strings;
    for (const py::handle& e : v) {
      if (!py::isinstance<py::str>(e)) invalid("set_parameter: a list value must hold str only");
      strings.push_back(e.cast<std::string>());
    }
    size_t width = 0;
    for (const std::string& x : strings) width = std::max(width, x.size());
    p->type = -1;
    p->dims = {static_cast<int>(width), static_cast<int>(strings.size())};
    for (std::string x : strings) {
      x.resize(width, ' ');
      p->data.insert(p->data.end(), x.begin(), x.end());
    }
  } else if (py::isinstance<py::bool_>(v)) {
    invalid("set_parameter: a bool has no C3D type (give 0 or 1)");
  } else if (py::isinstance<py::int_>(v)) {
    p->type = 2;
    put16(v.cast<long long>());
  } else if (py::isinstance<py::float_>(v)) {
    p->type = 4;
    put32(v.cast<double>());
  } else if (py::isinstance<py::array>(v)) {
    const py::array a = py::reinterpret_borrow<py::array>(v);
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
      for (py::ssize_t i = 0; i < b.size(); ++i) put16(b.data()[i]);
    } else if (kind == 'f') {
      p->type = 4;
      const py::array_t<double, py::array::c_style | py::array::forcecast> b(a);
      for (py::ssize_t i = 0; i < b.size(); ++i) put32(b.data()[i]);
    } else {
      invalid("set_parameter: numpy dtype " + py::str(a.dtype()).cast<std::string>() +
              " has no C3D type (uint8, integers, floats)");
    }
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

// Sets (or adds) parameter GROUP:NAME of a take read from C3D; a new group gets the next free
// group number. A take without a parameter section is refused: its C3D is written from the
// take alone, and a section of one parameter would change how (docs/PYTHON.md).
void set_parameter(capz::Take& t, const std::string& group, const std::string& name,
                   const py::handle& value, const std::optional<std::string>& description) {
  if (!t.c3d)
    invalid(
        "set_parameter: the take has no C3D parameter section (a take read from a C3D or "
        "its archive has one)");
  for (const std::string* n : {&group, &name})
    if (n->empty() || n->size() > 127 || n->find('\0') != std::string::npos ||
        n->find(' ') != std::string::npos)
      invalid("set_parameter: '" + *n + "' is not a C3D name (1 to 127 characters, no blanks)");
  if (description && description->size() > 255)
    invalid("set_parameter: a description holds at most 255 characters");
  capz::C3DParameter p;
  parameter_from_python(value, &p);
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
    const py::str key = text(group_key(g));
    py::dict params = d.contains(key) ? py::dict(d[key]) : py::dict();
    for (const capz::C3DParameter& p : g.params) params[text(p.name)] = parameter_value(p);
    d[key] = params;
  }
  return d;
}

py::object parameter_of(const capz::Take& t, const std::string& group, const std::string& name) {
  if (!t.c3d) return py::none();
  for (const capz::C3DGroup& g : t.c3d->groups) {
    std::string key = group_key(g);
    if (key.size() != group.size() ||
        !std::equal(key.begin(), key.end(), group.begin(), [](char a, char b) {
          return std::toupper(static_cast<unsigned char>(a)) ==
                 std::toupper(static_cast<unsigned char>(b));
        }))
      continue;
    const capz::C3DParameter* p = g.find(name);
    if (!p) continue;
    py::dict d;
    d["value"] = parameter_value(*p);
    d["description"] = text(p->description);
    d["type"] = parameter_type(p->type);
    d["dims"] = p->dims;
    d["locked"] = p->locked;
    d["group_description"] = text(g.description);
    return std::move(d);
  }
  return py::none();
}

py::dict error_stats(const capz::ErrorStats& e) {
  py::dict d;
  d["max_error_per_coordinate"] = e.max_abs;
  d["max_error_euclidean"] = e.max_error;
  d["rmse"] = e.rmse;
  d["kg_error_percent"] = e.kg_error;
  d["psnr_db"] = e.psnr;
  d["samples"] = e.samples;
  d["mask_mismatches"] = e.mask_mismatches;
  return d;
}

py::dict compress_stats(const capz::CompressStats& s) {
  py::dict d;
  d["bytes"] = s.bytes;
  d["raw_float32_position_bytes"] = s.raw_bytes;
  d["bpvf"] = s.bpvf;
  d["grid_step"] = s.step;
  d["mode"] = s.mode;
  d["codec"] = s.codec;
  d["lossless"] = s.lossless;
  d["error"] = error_stats(s.error);
  d["position_bytes"] = s.position_bytes;
  d["analog_bytes"] = s.analog_bytes;
  d["rotation_bytes"] = s.rotation_bytes;
  d["other_bytes"] = s.other_bytes;
  return d;
}

// The same members as `capz info --json` on a .capz (apps/capz/cmd_info_capz.cpp).
py::dict info_dict(const std::string& path, const std::vector<uint8_t>& bytes) {
  const capz::StreamInfo si = capz::describe(bytes.data(), bytes.size(), path);
  py::dict d;
  d["file"] = path;
  d["format"] = "capz";
  d["version"] = std::to_string(si.major) + "." + std::to_string(si.minor);
  d["bytes"] = bytes.size();
  d["source_format"] = capz::format_name(si.source_format);
  d["source_name"] = text(si.source_name);
  d["frames"] = si.frames;
  d["points"] = si.points;
  d["rate"] = si.rate;
  d["units"] = text(si.units);
  d["mode"] = si.mode;
  d["codec"] = si.codec;
  d["lossless"] = si.lossless;
  d["grid_step"] = si.step;
  d["max_error"] = si.max_error;
  if (si.transform_output) d["kg_target"] = si.kg_target;
  d["window_frames"] = si.window_frames;
  d["windows"] = si.windows;
  d["analog_channels"] = si.analog_channels;
  d["analog_samples_per_frame"] = si.analog_samples_per_frame;
  py::list bounds;  // the lossy analog channels (FORMAT.md 5.2), as `capz info --json`
  for (size_t c = 0; c < si.analog_bounds.size(); ++c)
    if (si.analog_bounds[c] > 0) {
      py::dict b;
      b["channel"] = c;
      b["label"] = text(c < si.analog_labels.size() ? si.analog_labels[c] : std::string());
      b["unit"] = text(c < si.analog_units.size() ? si.analog_units[c] : std::string());
      b["bound"] = si.analog_bounds[c];
      bounds.append(b);
    }
  d["analog_bounds"] = bounds;
  py::dict rot;
  rot["segments"] = si.rotation_segments;
  rot["samples"] = si.rotation_segments > 0
                       ? si.frames * static_cast<size_t>(si.rotation_samples_per_frame)
                       : size_t{0};
  rot["rate"] = si.rotation_rate;
  rot["samples_per_frame"] = si.rotation_samples_per_frame;
  rot["labels"] = texts(si.rotation_labels);
  d["rotations"] = rot;
  const capz::OriginalInfo orig = capz::original_info(path);  // HASH: the original file
  if (orig.hashed) {
    py::dict o;
    o["bytes"] = orig.size;
    o["xxh3_128"] = orig.hash_hex;
    o["byte_exact"] = orig.exact;
    d["original"] = o;
  } else {
    d["original"] = py::none();
  }
  d["bpvf"] = capz::bpvf(bytes.size(), si.frames, si.points);
  py::dict chunks;
  for (const auto& kv : si.chunk_bytes) chunks[py::str(kv.first)] = kv.second;
  d["chunk_bytes"] = chunks;
  return d;
}

// True for a file that starts with the .capz magic.
bool file_is_capz(const std::string& path) {
  std::ifstream in(path, std::ios::binary);
  uint8_t head[16] = {};
  in.read(reinterpret_cast<char*>(head), sizeof head);
  return in.gcount() > 0 && capz::is_capz(head, static_cast<size_t>(in.gcount()));
}

// Contiguous bytes of a Python array as the Python layer hands them over.
const uint8_t* array_bytes(const py::array& a, size_t expect_bytes, const char* what) {
  if (!(a.flags() & py::array::c_style) || static_cast<size_t>(a.nbytes()) != expect_bytes)
    invalid(std::string(what) + ": expected a C-contiguous array of " +
            std::to_string(expect_bytes) + " bytes");
  return static_cast<const uint8_t*>(a.data());
}

// Take.from_arrays after the Python layer's checks: xyz float64 (F, N, 3), valid uint8 (F, N),
// analog float64 (S, C) or None, attributes [(name, type, size, count, array)].
TakePtr take_from_arrays(const py::array& xyz, const py::array& valid, double rate,
                         const std::string& units, const std::vector<std::string>& labels,
                         int64_t first_frame, const std::optional<py::array>& analog,
                         double analog_rate, const std::vector<std::string>& analog_labels,
                         const std::vector<py::tuple>& attributes,
                         const std::optional<py::tuple>& rotations) {
  if (xyz.ndim() != 3 || xyz.shape(2) != 3) invalid("xyz must have shape (frames, points, 3)");
  capz::Take t;
  const size_t F = static_cast<size_t>(xyz.shape(0)), N = static_cast<size_t>(xyz.shape(1));
  t.resize(F, N);
  if (F * N > 0) {
    std::memcpy(t.xyz.data(), array_bytes(xyz, F * N * 3 * sizeof(double), "xyz"),
                F * N * 3 * sizeof(double));
    std::memcpy(t.valid.data(), array_bytes(valid, F * N, "valid"), F * N);
  }
  for (size_t i = 0; i < F * N; ++i) {
    t.valid[i] = t.valid[i] ? 1 : 0;
    for (int a = 0; t.valid[i] && a < 3; ++a)
      if (!std::isfinite(t.xyz[3 * i + static_cast<size_t>(a)]))
        invalid("xyz[" + std::to_string(i / N) + ", " + std::to_string(i % N) +
                "] is marked valid but is not a finite number");
  }
  t.rate = rate;
  t.units = units;
  t.first_frame = first_frame;
  t.labels = labels;
  if (t.labels.empty()) t.labels.assign(N, "");
  if (t.labels.size() != N) invalid("labels: one per point expected");
  if (analog) {
    const py::array& an = *analog;
    if (an.ndim() != 2) invalid("analog must have shape (samples, channels)");
    const size_t S = static_cast<size_t>(an.shape(0)), C = static_cast<size_t>(an.shape(1));
    if (C > 0) {
      if (F == 0 || S % F != 0 || S == 0)
        invalid("analog: samples must be a positive multiple of the frames");
      t.analog.channels = static_cast<int>(C);
      t.analog.samples_per_frame = static_cast<int>(S / F);
      t.analog.rate = analog_rate;
      t.analog.labels = analog_labels;
      if (t.analog.labels.empty()) t.analog.labels.assign(C, "");
      if (t.analog.labels.size() != C) invalid("analog_labels: one per channel expected");
      t.analog.values.resize(S * C);
      std::memcpy(t.analog.values.data(), array_bytes(an, S * C * sizeof(double), "analog"),
                  S * C * sizeof(double));
    }
  }
  if (rotations) {  // (matrices float32 (S, G, 16) column-major, reliability (S, G), labels, rate)
    const py::tuple& r = *rotations;
    const py::array mats = r[0].cast<py::array>(), rel = r[1].cast<py::array>();
    if (mats.ndim() != 3 || mats.shape(2) != 16) invalid("rotation matrices: shape (S, G, 16)");
    const size_t S = static_cast<size_t>(mats.shape(0)), G = static_cast<size_t>(mats.shape(1));
    if (G > 0) {
      if (F == 0 || S == 0 || S % F != 0)
        invalid("rotations: samples must be a positive multiple of the frames");
      capz::Rotations& ro = t.rotations;
      ro.segments = static_cast<int>(G);
      ro.samples_per_frame = static_cast<int>(S / F);
      ro.labels = r[2].cast<std::vector<std::string>>();
      ro.rate = r[3].cast<double>();
      if (ro.labels.size() != G) invalid("rotation labels: one per segment expected");
      ro.matrices.resize(S * G * 16);
      ro.reliability.resize(S * G);
      std::memcpy(ro.matrices.data(), array_bytes(mats, S * G * 16 * 4, "rotation matrices"),
                  S * G * 16 * 4);
      std::memcpy(ro.reliability.data(), array_bytes(rel, S * G * 4, "rotation reliability"),
                  S * G * 4);
    }
  }
  for (const py::tuple& at : attributes) {
    capz::PointAttribute a;
    a.name = at[0].cast<std::string>();
    a.type = at[1].cast<std::string>().at(0);
    a.size = at[2].cast<int>();
    a.count = at[3].cast<int>();
    attribute_dtype(a.type, a.size);
    if (a.count < 1) invalid("attribute '" + a.name + "': count must be >= 1");
    const py::array arr = at[4].cast<py::array>();
    a.data.resize(F * N * a.bytes_per_point());
    if (!a.data.empty())
      std::memcpy(a.data.data(), array_bytes(arr, a.data.size(), a.name.c_str()), a.data.size());
    t.attributes.push_back(std::move(a));
  }
  return adopt(std::move(t));
}

capz::CompressOptions coding_options(const std::string& codec, int clusters, size_t window,
                                     bool check,
                                     const std::map<std::string, std::string>& codec_options,
                                     int threads, const std::map<std::string, double>& attr_error,
                                     bool drop_fields,
                                     const std::map<std::string, double>& analog_max_error) {
  capz::CompressOptions o;
  o.threads = threads;
  o.attr_error = attr_error;
  o.analog_max_error = analog_max_error;
  o.drop_fields = drop_fields;
  o.codec = codec;
  o.clusters = clusters;
  o.window_frames = window;
  o.check = check;
  o.codec_options = codec_options;
  return o;
}

capz::CompressTarget target_of(bool lossless, std::optional<double> kg_error,
                               std::optional<std::string> max_error) {
  capz::CompressTarget t;
  t.lossless = lossless;
  t.kg_error = kg_error;
  t.max_error = std::move(max_error);
  return t;
}

// capz.compress: (bytes, stats). `units` is given to a take without units, as --units does.
py::tuple compress_take(const capz::Take& take, bool lossless, std::optional<double> kg_error,
                        std::optional<std::string> max_error, const std::string& units,
                        const std::string& codec, int clusters, size_t window, bool check,
                        const std::map<std::string, std::string>& codec_options, int threads,
                        const std::map<std::string, double>& attr_error, bool drop_fields,
                        const std::map<std::string, double>& analog_max_error) {
  std::vector<uint8_t> bytes;
  capz::CompressStats st;
  {
    py::gil_scoped_release nogil;
    if (!units.empty() && capz::units_to_metres(units) == 0)
      invalid("units: unknown unit '" + units + "'");
    const bool give_units = !units.empty() && capz::units_to_metres(take.units) == 0;
    std::unique_ptr<capz::Take> with_units;
    if (give_units) {  // a copy: the caller's take is left as it is
      with_units = std::make_unique<capz::Take>(take);
      with_units->units = units;
    }
    const capz::Take& t = give_units ? *with_units : take;
    capz::CompressOptions opts = coding_options(codec, clusters, window, check, codec_options,
                                                threads, attr_error, drop_fields, analog_max_error);
    std::unique_ptr<capz::FrameSource> src = capz::take_frames(t);
    capz::set_compress_target(*src, target_of(lossless, kg_error, std::move(max_error)), &opts);
    bytes = capz::compress(t, opts, &st);
  }
  return py::make_tuple(py::bytes(reinterpret_cast<const char*>(bytes.data()), bytes.size()),
                        compress_stats(st));
}

// A .capz opened for random access: the file's bytes in memory, frames decoded on demand.
class CapzFile {
 public:
  CapzFile(const std::string& path, uint64_t memory_limit) : path_(path) {
    opts_.memory_limit = memory_limit;
    py::gil_scoped_release nogil;
    bytes_ = capz::read_file(path);
    info_ = capz::describe(bytes_.data(), bytes_.size(), path);
  }
  TakePtr read_frames(size_t first, std::optional<size_t> count) const {
    const size_t n = count ? *count : info_.frames;
    capz::Take t;
    {
      py::gil_scoped_release nogil;
      t = capz::decompress_frames(bytes_.data(), bytes_.size(), first, n, path_, opts_);
    }
    return adopt(std::move(t));
  }
  py::dict info() const { return info_dict(path_, bytes_); }
  size_t frames() const { return info_.frames; }
  size_t points() const { return info_.points; }
  const std::string& path() const { return path_; }

 private:
  std::string path_;
  std::vector<uint8_t> bytes_;
  capz::StreamInfo info_;
  capz::DecompressOptions opts_;
};

void translate_errors(std::exception_ptr p) {  // NOLINT: pybind11 passes it by value
  try {
    if (p) std::rethrow_exception(p);
  } catch (const capz::Error& e) {
    py::object cls = py::module_::import("capz._error").attr("Error");
    py::object exc = cls(capz::error_code_name(e.code()), e.what(), static_cast<int>(e.code()));
    PyErr_SetObject(cls.ptr(), exc.ptr());
  }
}

using TakeClass = py::class_<capz::Take, TakePtr>;

// Take: positions, gaps and what names them.
void bind_take_positions(TakeClass* cls) {
  (*cls)
      .def_property_readonly(
          "xyz",
          [](const py::object& self) {
            const auto& t = self.cast<const capz::Take&>();
            return view(self, py::dtype::of<double>(), {ss(t.frames), ss(t.points), 3},
                        t.xyz.data());
          },
          "positions, float64 (frames, points, 3) in the take's units; NaN at gaps. A view of "
          "the take's storage (no copy): writing to it changes the take")
      .def_property_readonly(
          "valid",
          [](const py::object& self) {
            const auto& t = self.cast<const capz::Take&>();
            return view(self, py::dtype("bool"), {ss(t.frames), ss(t.points)}, t.valid.data());
          },
          "bool (frames, points): True where a sample holds a measured "
          "position, False at a gap (a view, like xyz)")
      .def_property_readonly("frames", [](const capz::Take& t) { return t.frames; })
      .def_property_readonly("points", [](const capz::Take& t) { return t.points; })
      .def_property(
          "labels", [](const capz::Take& t) { return texts(t.labels); },
          [](capz::Take& t, const std::vector<std::string>& v) {
            if (v.size() != t.points) invalid("labels: one per point expected");
            t.labels = v;
          },
          "one label per point (may be empty strings)")
      .def_property_readonly("descriptions",
                             [](const capz::Take& t) { return texts(t.descriptions); })
      .def_property(
          "rate", [](const capz::Take& t) { return t.rate; },
          [](capz::Take& t, double r) {
            if (!(r >= 0) || !std::isfinite(r)) invalid("rate must be a finite number >= 0");
            t.rate = r;
          },
          "frames per second; 0 when unknown")
      .def_property(
          "units", [](const capz::Take& t) { return t.units; },
          [](capz::Take& t, const std::string& u) {
            if (!u.empty() && capz::units_to_metres(u) == 0)
              invalid("units: unknown unit '" + u + "'");
            t.units = u;
          },
          "length units of xyz as the source says (\"mm\", \"cm\", \"m\"); \"\" when unknown")
      .def_property(
          "first_frame", [](const capz::Take& t) { return t.first_frame; },
          [](capz::Take& t, int64_t f) { t.first_frame = f; },
          "number of the first frame as the source counts them")
      .def_property_readonly("source", [](const capz::Take& t) { return t.source; })
      .def_property_readonly("format",
                             [](const capz::Take& t) { return capz::format_name(t.format); })
      .def_property_readonly("warnings", [](const capz::Take& t) { return texts(t.warnings); });
}

// Take: analog channels, rotations and point fields.
void bind_take_channels(TakeClass* cls) {
  (*cls)
      .def_property_readonly(
          "analog",
          [](const py::object& self) {
            const auto& t = self.cast<const capz::Take&>();
            const size_t C = static_cast<size_t>(std::max(0, t.analog.channels));
            const size_t S = C ? t.analog.values.size() / C : 0;
            return view(self, py::dtype::of<double>(), {ss(S), ss(C)}, t.analog.values.data());
          },
          "analog channels, float64 (samples, channels), samples = frames x "
          "analog_samples_per_frame, the numbers the file stores (analog_physical gives "
          "them in the channels' units); shape (0, 0) without analog")
      .def_property_readonly("analog_labels",
                             [](const capz::Take& t) { return texts(t.analog.labels); })
      .def_property_readonly("analog_rate", [](const capz::Take& t) { return t.analog.rate; })
      .def_property_readonly("analog_samples_per_frame",
                             [](const capz::Take& t) { return t.analog.samples_per_frame; })
      .def_property_readonly(
          "rotations",
          [](const py::object& self) {
            const auto& t = self.cast<const capz::Take&>();
            const capz::Rotations& r = t.rotations;
            const size_t G = static_cast<size_t>(std::max(0, r.segments));
            const size_t S = r.samples(t.frames);
            if (r.matrices.size() != S * G * 16 || r.reliability.size() != S * G)
              capz::fail(capz::ErrorCode::kInternal, t.source,
                         "rotation arrays do not match samples x segments");
            py::dict d;
            const py::ssize_t f = sizeof(float);
            // M[s, g, row, col] = matrices[(s * G + g) * 16 + col * 4 + row] (column-major).
            d["matrices"] = view(self, py::dtype::of<float>(), {ss(S), ss(G), 4, 4},
                                 r.matrices.data(), {ss(G) * 16 * f, 16 * f, f, 4 * f});
            d["reliability"] =
                view(self, py::dtype::of<float>(), {ss(S), ss(G)}, r.reliability.data());
            d["labels"] = texts(r.labels);
            d["rate"] = r.rate;
            d["samples_per_frame"] = r.samples_per_frame;
            return d;
          },
          "C3D rotations: dict with matrices float32 (samples, segments, 4, 4) indexed "
          "[sample, segment, row, column], reliability float32 (samples, segments), labels, "
          "rate and samples_per_frame")
      .def_property_readonly(
          "attributes",
          [](const py::object& self) {
            return attributes_of(self, self.cast<const capz::Take&>());
          },
          "per-point fields of the source besides x y z (PCD: rgb, "
          "intensity, normals, ...): dict name -> array (frames, points) or "
          "(frames, points, count) of the field's type (float32, uint8, ...)")
      .def_property_readonly(
          "analog_units",
          [](const capz::Take& t) {
            py::list u;
            for (const capz::AnalogPhysics& p : capz::analog_physics(t)) u.append(text(p.unit));
            return u;
          },
          "each analog channel's unit (C3D ANALOG:UNITS, trimmed; \"\" when not given)")
      .def_property_readonly(
          "analog_physical",
          [](const capz::Take& t) {
            const std::vector<capz::AnalogPhysics> phys = capz::analog_physics(t);
            const size_t C = phys.size(), S = C ? t.analog.values.size() / C : 0;
            py::array_t<double> a({ss(S), ss(C)});
            double* out = a.mutable_data();
            for (size_t i = 0; i < S; ++i)
              for (size_t c = 0; c < C; ++c)
                out[i * C + c] = (t.analog.values[i * C + c] - phys[c].offset) * phys[c].scale;
            return a;
          },
          "analog channels in their units, float64 (samples, channels): (stored - "
          "ANALOG:OFFSET) x ANALOG:SCALE x ANALOG:GEN_SCALE per channel, as the C3D "
          "specification gives it (the stored numbers when the take has no C3D parameters). "
          "A new array");
}

// Take: the C3D parameter section, sample words and header events.
void bind_take_c3d(TakeClass* cls) {
  (*cls)
      .def("set_parameter", &set_parameter, py::arg("group"), py::arg("name"), py::arg("value"),
           py::arg("description") = py::none(),
           "sets C3D parameter GROUP:NAME (added when absent; names matched without regard to "
           "case) of a take read from C3D: value a str, a list of str, an int (int16), a float "
           "(float32) or a numpy array (uint8 -> byte, integers -> int16, floats -> float32; "
           "its shape reversed as the C3D dimensions, each at most 255). write() and compress() "
           "keep it; write() rewrites the POINT, ANALOG, TRIAL and ROTATION fields that "
           "describe the data from the take")
      .def_property_readonly(
          "parameters", [](const capz::Take& t) { return parameters_of(t); },
          "the C3D parameter section: dict group -> dict parameter -> value (str for a char "
          "array, list of str for a 2-D one, numpy uint8/int16/float32 array with the C3D "
          "dimensions reversed, a number when it has no dimensions); {} when the take did not "
          "come from C3D. A copy: changing it does not change the take")
      .def(
          "parameter",
          [](const capz::Take& t, const std::string& group, const std::string& name) {
            return parameter_of(t, group, name);
          },
          py::arg("group"), py::arg("name"),
          "one C3D parameter, names matched without regard to case: dict with value (as in "
          "parameters), description, type (\"char\", \"byte\", \"int16\", \"float\"), dims (as "
          "the file gives them, first varying fastest), locked and group_description; None when "
          "absent")
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
          "point (0 at a gap); None when the take did not come from C3D (a view, like xyz)")
      .def_property_readonly(
          "events",
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
          "the C3D header's events: list of dict label, time (s), display. The EVENT group's "
          "events are in parameters[\"EVENT\"]");
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

// Take: counts, copy and repr.
void bind_take_rest(TakeClass* cls) {
  (*cls)
      .def_property_readonly("gap_samples", &capz::Take::gap_samples)
      .def(
          "copy", [](const capz::Take& t) { return std::make_shared<capz::Take>(t); },
          "a deep copy of the take")
      .def("__repr__", [](const capz::Take& t) {
        std::string s = "<capz.Take " + std::to_string(t.frames) + " frames x " +
                        std::to_string(t.points) + " points";
        if (t.rate > 0) {
          char rate[32];
          std::snprintf(rate, sizeof rate, ", %g Hz", t.rate);
          s += rate;
        }
        if (!t.units.empty()) s += ", " + t.units;
        if (t.analog.channels > 0) s += ", " + std::to_string(t.analog.channels) + " analog";
        if (!t.attributes.empty()) s += ", " + std::to_string(t.attributes.size()) + " attributes";
        if (t.format != capz::Format::kUnknown)
          s += ", from " + std::string(capz::format_name(t.format));
        return s + ">";
      });
}

// The module's functions: reading, writing, coding, comparing.
void bind_functions(py::module_& m) {
  m.def("take_from_arrays", &take_from_arrays);

  m.attr("DEFAULT_MEMORY_LIMIT") = capz::kDefaultMemoryLimit;
  m.attr("AUTO_MEMORY_LIMIT") = capz::kAutoMemoryLimit;

  m.def("read", [](const std::string& path, uint64_t memory_limit) {
    capz::Take t;
    {
      py::gil_scoped_release nogil;
      if (file_is_capz(path)) {
        const std::vector<uint8_t> bytes = capz::read_file(path);
        capz::DecompressOptions o;
        o.memory_limit = memory_limit;
        t = capz::decompress(bytes.data(), bytes.size(), path, o);
      } else {
        t = capz::read_take(path);
      }
    }
    return adopt(std::move(t));
  });

  m.def("write", [](const capz::Take& take, const std::string& path, bool overwrite,
                    const std::string& pcd_encoding, bool c3d_float, bool drop_fields) {
    capz::WriteOptions o;
    o.overwrite = overwrite;
    o.pcd_encoding = pcd_encoding;
    o.c3d_float = c3d_float;
    o.drop_fields = drop_fields;
    py::gil_scoped_release nogil;
    capz::write_take(take, path, o);
  });

  m.def("compress", &compress_take);

  m.def("decompress", [](const py::buffer& data, const std::string& name, uint64_t memory_limit) {
    const py::buffer_info b = data.request();
    if (b.ndim != 1 || b.itemsize != 1) invalid("decompress wants bytes (a 1-D buffer of bytes)");
    capz::Take t;
    {
      py::gil_scoped_release nogil;
      capz::DecompressOptions o;
      o.memory_limit = memory_limit;
      t = capz::decompress(static_cast<const uint8_t*>(b.ptr), static_cast<size_t>(b.size), name,
                           o);
    }
    return adopt(std::move(t));
  });

  m.def("compress_file",
        [](const std::string& in, const std::string& out, bool lossless,
           std::optional<double> kg_error, std::optional<std::string> max_error,
           const std::string& units, const std::string& codec, int clusters, size_t window,
           bool check, const std::map<std::string, std::string>& codec_options, int threads,
           const std::map<std::string, double>& attr_error, bool drop_fields,
           const std::map<std::string, double>& analog_max_error, bool overwrite) {
          capz::CompressStats st;
          {
            py::gil_scoped_release nogil;
            capz::compress_file(in, out, target_of(lossless, kg_error, std::move(max_error)),
                                coding_options(codec, clusters, window, check, codec_options,
                                               threads, attr_error, drop_fields, analog_max_error),
                                units, overwrite, &st);
          }
          return compress_stats(st);
        });

  m.def("compare", [](const capz::Take& a, const capz::Take& b) {
    capz::ErrorStats e;
    {
      py::gil_scoped_release nogil;
      e = capz::compare(a, b);
    }
    return error_stats(e);
  });

  m.def("parse_length", &capz::parse_length);
  m.def("units_to_metres", &capz::units_to_metres);
}

// capz.open's file: random access to a .capz.
void bind_capz_file(py::module_& m) {
  py::class_<CapzFile>(m, "CapzFile")
      .def(py::init<const std::string&, uint64_t>())
      .def("read_frames", &CapzFile::read_frames)
      .def_property_readonly("info", &CapzFile::info)
      .def_property_readonly("frames", &CapzFile::frames)
      .def_property_readonly("points", &CapzFile::points)
      .def_property_readonly("path", &CapzFile::path);
}

}  // namespace

PYBIND11_MODULE(_capz, m) {
  m.doc() = "capz's C++ library (use the package capz, which wraps this module)";
  py::register_exception_translator(&translate_errors);
  m.attr("version") = capz::version_string();

  TakeClass take_class(m, "Take", "A motion-capture take: positions, gaps, analog, metadata");
  bind_take_positions(&take_class);
  bind_take_channels(&take_class);
  bind_take_c3d(&take_class);
  bind_take_trc(&take_class);
  bind_take_rest(&take_class);

  bind_functions(m);
  bind_capz_file(m);
}
