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
#include "capz/error.h"
#include "capz/io.h"
#include "capz/metrics.h"
#include "capz/tool/compress_file.h"
#include "capz/tool/file.h"
#include "capz/tool/original.h"
#include "capz/version.h"
#include "py_common.h"

namespace capz_py {
namespace {

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
    if (a.count < 1 || a.data.size() != t.total_points() * a.bytes_per_point())
      capz::fail(capz::ErrorCode::kInternal, t.source,
                 "attribute '" + a.name + "' holds " + std::to_string(a.data.size()) +
                     " bytes, not frames x points x count x size");
    // A ragged take's fields are flattened like its xyz: (total points[, count]).
    std::vector<py::ssize_t> shape = t.ragged()
                                         ? std::vector<py::ssize_t>{ss(t.total_points())}
                                         : std::vector<py::ssize_t>{ss(t.frames), ss(t.points)};
    if (count > 1) shape.push_back(ss(count));
    // A name repeated in the source (PCD padding "_") gets "#2", "#3", ...
    const int n = ++seen[a.name];
    const std::string key = n == 1 ? a.name : a.name + "#" + std::to_string(n);
    d[py::str(key)] = view(self, py::dtype(attribute_dtype(a.type, a.size)), shape, a.data.data());
  }
  return d;
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

// The attributes [(name, type, size, count, array)] of `points` points each, added to *t.
void add_attributes(const std::vector<py::tuple>& attributes, size_t points, capz::Take* t) {
  for (const py::tuple& at : attributes) {
    capz::PointAttribute a;
    a.name = at[0].cast<std::string>();
    a.type = at[1].cast<std::string>().at(0);
    a.size = at[2].cast<int>();
    a.count = at[3].cast<int>();
    attribute_dtype(a.type, a.size);
    if (a.count < 1) invalid("attribute '" + a.name + "': count must be >= 1");
    const py::array arr = at[4].cast<py::array>();
    a.data.resize(points * a.bytes_per_point());
    if (!a.data.empty())
      std::memcpy(a.data.data(), array_bytes(arr, a.data.size(), a.name.c_str()), a.data.size());
    t->attributes.push_back(std::move(a));
  }
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
  add_attributes(attributes, F * N, &t);
  return adopt_arrays(std::move(t));
}

// Take.from_arrays with a list of frames, after the Python layer's checks and concatenation:
// xyz float64 (T, 3), valid uint8 (T), offsets int64 (F + 1, from 0, non-decreasing, ending at
// T), attributes [(name, type, size, count, array (T[, count]))].
TakePtr take_from_frames(const py::array& xyz, const py::array& valid, const py::array& offsets,
                         double rate, const std::string& units, int64_t first_frame,
                         const std::vector<py::tuple>& attributes) {
  if (xyz.ndim() != 2 || xyz.shape(1) != 3) invalid("xyz must have shape (points, 3)");
  if (offsets.ndim() != 1 || offsets.shape(0) < 1) invalid("frame offsets: F + 1 expected");
  const size_t T = static_cast<size_t>(xyz.shape(0)), F = static_cast<size_t>(offsets.shape(0)) - 1;
  const int64_t* o = reinterpret_cast<const int64_t*>(array_bytes(offsets, (F + 1) * 8, "offsets"));
  std::vector<size_t> counts(F);
  for (size_t f = 0; f < F; ++f) {
    if (o[f + 1] < o[f] || o[0] != 0) invalid("frame offsets must grow from 0");
    counts[f] = static_cast<size_t>(o[f + 1] - o[f]);
  }
  if (static_cast<size_t>(o[F]) != T) invalid("frame offsets do not end at the point count");
  capz::Take t;
  t.resize_ragged(counts);
  if (T > 0) {
    std::memcpy(t.xyz.data(), array_bytes(xyz, T * 3 * sizeof(double), "xyz"),
                T * 3 * sizeof(double));
    std::memcpy(t.valid.data(), array_bytes(valid, T, "valid"), T);
  }
  for (size_t i = 0; i < T; ++i) {
    t.valid[i] = t.valid[i] ? 1 : 0;
    for (int a = 0; t.valid[i] && a < 3; ++a)
      if (!std::isfinite(t.xyz[3 * i + static_cast<size_t>(a)]))
        invalid("xyz[" + std::to_string(i) + "] is marked valid but is not a finite number");
  }
  t.rate = rate;
  t.units = units;
  t.first_frame = first_frame;
  add_attributes(attributes, T, &t);
  return adopt_arrays(std::move(t));
}

capz::CompressOptions coding_options(const std::string& codec, int clusters, size_t window,
                                     bool check,
                                     const std::map<std::string, std::string>& codec_options,
                                     int threads, const std::map<std::string, double>& attr_error,
                                     bool drop_fields,
                                     const std::map<std::string, double>& analog_max_error,
                                     bool any_point_order) {
  capz::CompressOptions o;
  o.any_point_order = any_point_order;
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
  return capz::CompressTarget{lossless, kg_error, std::move(max_error)};
}

// capz.compress: (bytes, stats). `units` is given to a take without units, as --units does.
py::tuple compress_take(const capz::Take& take, bool lossless, std::optional<double> kg_error,
                        std::optional<std::string> max_error, const std::string& units,
                        const std::string& codec, int clusters, size_t window, bool check,
                        const std::map<std::string, std::string>& codec_options, int threads,
                        const std::map<std::string, double>& attr_error, bool drop_fields,
                        const std::map<std::string, double>& analog_max_error,
                        bool any_point_order) {
  std::vector<uint8_t> bytes;
  capz::CompressStats st;
  std::string note;  // the default bound's, as the CLI's note
  {
    py::gil_scoped_release nogil;
    if (!units.empty() && capz::units_to_metres(units) == 0)
      invalid("units: unknown unit '" + units + "'");
    const bool give_units =
        !units.empty() && (capz::units_to_metres(take.units) == 0 || take.units_assumed);
    std::unique_ptr<capz::Take> with_units;
    if (give_units || take.units_assumed) {  // a copy: the caller's take is left as it is
      with_units = std::make_unique<capz::Take>(take);
      if (give_units) with_units->units = units, with_units->units_assumed = false;
    }
    const capz::Take& t = with_units ? *with_units : take;
    capz::CompressOptions opts =
        coding_options(codec, clusters, window, check, codec_options, threads, attr_error,
                       drop_fields, analog_max_error, any_point_order);
    std::unique_ptr<capz::FrameSource> src = capz::take_frames(t);
    note =
        capz::set_compress_target(*src, target_of(lossless, kg_error, std::move(max_error)), &opts);
    if (t.units_assumed) {  // as the CLI: the archive stores no assumed units
      with_units->units.clear();
      with_units->units_assumed = false;
    }
    bytes = capz::compress(t, opts, &st);
  }
  warn_note(note);
  warn_note(capz::dropped_coordinates_note(st));
  return py::make_tuple(py::bytes(reinterpret_cast<const char*>(bytes.data()), bytes.size()),
                        compress_stats(st));
}

void translate_errors(std::exception_ptr p) {  // NOLINT: pybind11 passes it by value
  try {
    if (p) std::rethrow_exception(p);
  } catch (const capz::Error& e) {
    py::object cls = py::module_::import("capz._error").attr("Error");
    py::object exc = cls(capz::error_code_name(e.code()), e.what(), static_cast<int>(e.code()));
    PyErr_SetObject(cls.ptr(), exc.ptr());
  }
}

// Take: positions, gaps and what names them.
void bind_take_positions(TakeClass* cls) {
  (*cls)
      .def_property_readonly(
          "xyz",
          [](const py::object& self) {
            const auto& t = self.cast<const capz::Take&>();
            if (t.ragged())
              return view(self, py::dtype::of<double>(), {ss(t.total_points()), 3}, t.xyz.data());
            return view(self, py::dtype::of<double>(), {ss(t.frames), ss(t.points), 3},
                        t.xyz.data());
          },
          "positions, float64 (frames, points, 3) in the take's units; NaN at gaps. A ragged "
          "take (frames of their own point count): (total points, 3), frame f being rows "
          "frame_offsets[f] to frame_offsets[f + 1]. A view of the take's storage (no copy): "
          "writing to it changes the take")
      .def_property_readonly(
          "valid",
          [](const py::object& self) {
            const auto& t = self.cast<const capz::Take&>();
            if (t.ragged())
              return view(self, py::dtype("bool"), {ss(t.total_points())}, t.valid.data());
            return view(self, py::dtype("bool"), {ss(t.frames), ss(t.points)}, t.valid.data());
          },
          "bool (frames, points), (total points,) for a ragged take: True where a sample holds "
          "a measured position, False at a gap (a view, like xyz)")
      .def_property_readonly("frames", [](const capz::Take& t) { return t.frames; })
      .def_property_readonly(
          "points", [](const capz::Take& t) { return t.points; },
          "points per frame; 0 for a ragged take (see frame_offsets)")
      .def_property_readonly("ragged", &capz::Take::ragged,
                             "True when the frames have their own point counts")
      .def_property_readonly("total_points", &capz::Take::total_points,
                             "points of all frames together")
      .def_property_readonly(
          "frame_offsets",
          [](const capz::Take& t) {
            py::array_t<int64_t> a(ss(t.frames + 1));
            int64_t* o = a.mutable_data();
            for (size_t f = 0; f <= t.frames; ++f)
              o[f] = static_cast<int64_t>(f < t.frames ? t.frame_begin(f) : t.total_points());
            return a;
          },
          "int64 (frames + 1,): frame f holds points frame_offsets[f] to frame_offsets[f + 1] "
          "of the flattened arrays (for a fixed take too: multiples of points). A new array")
      .def_property_readonly(
          "units_assumed", [](const capz::Take& t) { return t.units_assumed; },
          "True when the file holds no units and the reader assumed them "
          "(metres for PCD, PLY and .bin frames)")
      .def_property(
          "labels", [](const capz::Take& t) { return texts(t.labels); },
          [](capz::Take& t, const py::sequence& v) {
            if (t.ragged()) invalid("labels: a ragged take has no point labels");
            if (static_cast<size_t>(py::len(v)) != t.points)
              invalid("labels: one per point expected");
            t.labels = file_texts(v, latin1_text(t), "labels");
          },
          "one label per point (may be empty strings), or none: a ragged take's points and "
          "those of PCD, PLY and .bin frames have no labels")
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
            t.units_assumed = false;
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
      .def_property(
          "analog_labels", [](const capz::Take& t) { return texts(t.analog.labels); },
          [](capz::Take& t, const py::sequence& v) {
            if (static_cast<size_t>(py::len(v)) != static_cast<size_t>(t.analog.channels))
              invalid("analog_labels: one per analog channel expected");
            t.analog.labels = file_texts(v, latin1_text(t), "analog_labels");
          },
          "one label per analog channel (write() and compress() keep them)")
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
          "(frames, points, count) of the field's type (float32, uint8, ...); a ragged take's: "
          "(total points) or (total points, count), flattened like xyz")
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

// A copy that shares nothing with t: a Take's copy shares its C3D, TRC and PCD metadata, which
// set_parameter and set_events change in place.
TakePtr deep_copy(const capz::Take& t) {
  auto p = std::make_shared<capz::Take>(t);
  if (t.c3d) p->c3d = std::make_shared<capz::C3DExtra>(*t.c3d);
  if (t.trc) p->trc = std::make_shared<capz::TRCExtra>(*t.trc);
  if (t.pcd) p->pcd = std::make_shared<capz::PCDExtra>(*t.pcd);
  return p;
}

// Pickled as (1, the take's lossless .capz bytes, source, warnings): the archive holds
// everything else a take has, bit for bit, and is what capz keeps best tested.
py::tuple take_state(const capz::Take& t) {
  std::vector<uint8_t> bytes;
  {
    py::gil_scoped_release nogil;
    capz::CompressOptions opts;
    std::unique_ptr<capz::FrameSource> src = capz::take_frames(t);
    capz::CompressTarget lossless;
    lossless.lossless = true;
    capz::set_compress_target(*src, lossless, &opts);
    bytes = capz::compress(t, opts);
  }
  // A fifth element says the units were assumed (states of 4 elements, from before, did not).
  return py::make_tuple(1, py::bytes(reinterpret_cast<const char*>(bytes.data()), bytes.size()),
                        t.source, t.warnings, t.units_assumed);
}

TakePtr take_from_state(const py::tuple& s) {
  if ((s.size() != 4 && s.size() != 5) || s[0].cast<int>() != 1)
    invalid("unpickling a capz.Take: not a state this version wrote");
  const std::string bytes = s[1].cast<std::string>();
  capz::Take t;
  {
    py::gil_scoped_release nogil;
    capz::DecompressOptions o;
    o.memory_limit = 0;  // the take was in memory where it was pickled
    t = capz::decompress(reinterpret_cast<const uint8_t*>(bytes.data()), bytes.size(),
                         "pickled take", o);
  }
  t.source = s[2].cast<std::string>();
  t.warnings = s[3].cast<std::vector<std::string>>();
  t.units_assumed = s.size() == 5 && s[4].cast<bool>();
  return adopt(std::move(t));
}

// Take: counts, copies, pickling and repr.
void bind_take_rest(TakeClass* cls) {
  (*cls)
      .def_property_readonly("gap_samples", &capz::Take::gap_samples)
      .def("copy", &deep_copy, "a deep copy of the take (nothing shared with it)")
      .def("__copy__", &deep_copy)
      .def(
          "__deepcopy__", [](const capz::Take& t, const py::dict&) { return deep_copy(t); },
          py::arg("memo"))
      .def(py::pickle(&take_state, &take_from_state))
      .def("__repr__", [](const capz::Take& t) {
        std::string s = "<capz.Take " + std::to_string(t.frames) + " frames x " +
                        (t.ragged() ? std::to_string(t.total_points()) + " points in all (ragged)"
                                    : std::to_string(t.points) + " points");
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

// The CLI's --trc-delimiter: "tab", "comma", or "" for the take's own (WriteOptions 0).
char trc_delimiter_char(const std::string& name) {
  if (name == "tab") return '\t';
  if (name == "comma") return ',';
  if (!name.empty()) invalid("trc_delimiter: tab or comma, not '" + name + "'");
  return 0;
}

// The module's functions: reading, writing, coding, comparing.
void bind_functions(py::module_& m) {
  m.def("take_from_arrays", &take_from_arrays);
  m.def("take_from_frames", &take_from_frames);

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

  m.def("write",
        [](const capz::Take& take, const std::string& path, bool overwrite,
           const std::string& pcd_encoding, bool c3d_float, bool drop_fields, const std::string& to,
           const std::string& ply_encoding, const std::string& trc_delimiter) {
          capz::WriteOptions o;
          o.overwrite = overwrite;
          o.trc_delimiter = trc_delimiter_char(trc_delimiter);
          o.pcd_encoding = pcd_encoding;
          o.ply_encoding = ply_encoding;
          o.folder_format = to == "pcd"   ? capz::Format::kPCDFolder
                            : to == "ply" ? capz::Format::kPLYFolder
                            : to == "bin" ? capz::Format::kBinFolder
                                          : capz::Format::kUnknown;
          if (!to.empty() && o.folder_format == capz::Format::kUnknown)
            invalid("to: pcd, ply or bin, not '" + to + "'");
          o.c3d_float = c3d_float;
          o.drop_fields = drop_fields;
          py::gil_scoped_release nogil;
          capz::write_take(take, path, o);
        });

  m.def("compress", &compress_take);

  m.def("dropped_by", [](const capz::Take& take, const std::string& path) {
    return capz::dropped_by(take, capz::format_for_output(path));
  });

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
           const std::map<std::string, double>& analog_max_error, bool any_point_order,
           bool overwrite) {
          capz::CompressStats st;
          std::string note;
          {
            py::gil_scoped_release nogil;
            note = capz::compress_file(
                in, out, target_of(lossless, kg_error, std::move(max_error)),
                coding_options(codec, clusters, window, check, codec_options, threads, attr_error,
                               drop_fields, analog_max_error, any_point_order),
                units, overwrite, &st);
          }
          warn_note(note);
          warn_note(capz::dropped_coordinates_note(st));
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

}  // namespace
}  // namespace capz_py

using namespace capz_py;

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
