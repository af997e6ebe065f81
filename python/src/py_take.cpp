// capz._capz's Take class (py_common.h's TakeClass): its arrays as numpy views of the Take's own
// storage, its metadata, copies and pickling. The C3D and TRC parts are py_c3d.cpp's; the module's
// functions and its definition are capz_py.cpp's.
#include <pybind11/numpy.h>
#include <pybind11/pybind11.h>
#include <pybind11/stl.h>

#include <algorithm>
#include <cmath>
#include <cstdio>
#include <map>
#include <memory>
#include <string>
#include <utility>
#include <vector>

#include "capz/codec.h"
#include "capz/error.h"
#include "capz/io.h"
#include "capz/tool/compress_file.h"
#include "py_common.h"

namespace capz_py {

std::string attribute_dtype(char type, int size) {
  const char kind = type == 'F' ? 'f' : type == 'U' ? 'u' : type == 'I' ? 'i' : '?';
  const bool ok = kind != '?' && (size == 1 || size == 2 || size == 4 || size == 8) &&
                  (kind != 'f' || size == 4 || size == 8);
  if (!ok)
    invalid("attribute type " + std::string(1, type) + " of " + std::to_string(size) +
            " bytes has no numpy dtype");
  return std::string("<") + kind + std::to_string(size);
}

namespace {

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

// Take's positions and gaps as views, and their counts and frame offsets.
void bind_take_position_arrays(TakeClass* cls) {
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
          "of the flattened arrays (for a fixed take too: multiples of points). A new array");
}

// Take's labels, rate, units, frame numbering and source.
void bind_take_naming(TakeClass* cls) {
  (*cls)
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

}  // namespace

// Take: positions, gaps and what names them.
void bind_take_positions(TakeClass* cls) {
  bind_take_position_arrays(cls);
  bind_take_naming(cls);
}

namespace {

// Take.rotations: the matrices and reliability as views of the take's storage, with labels and
// rates.
py::dict rotations_of(py::handle self, const capz::Take& t) {
  const capz::Rotations& r = t.rotations;
  const size_t G = static_cast<size_t>(std::max(0, r.segments));
  const size_t S = r.samples(t.frames);
  if (r.matrices.size() != S * G * 16 || r.reliability.size() != S * G)
    capz::fail(capz::ErrorCode::kInternal, t.source,
               "rotation arrays do not match samples x segments");
  py::dict d;
  const py::ssize_t f = sizeof(float);
  // M[s, g, row, col] = matrices[(s * G + g) * 16 + col * 4 + row] (column-major).
  d["matrices"] = view(self, py::dtype::of<float>(), {ss(S), ss(G), 4, 4}, r.matrices.data(),
                       {ss(G) * 16 * f, 16 * f, f, 4 * f});
  d["reliability"] = view(self, py::dtype::of<float>(), {ss(S), ss(G)}, r.reliability.data());
  d["labels"] = texts(r.labels);
  d["rate"] = r.rate;
  d["samples_per_frame"] = r.samples_per_frame;
  return d;
}

// Take's analog samples, rotations and point fields as stored.
void bind_take_stored_channels(TakeClass* cls) {
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
          [](const py::object& self) { return rotations_of(self, self.cast<const capz::Take&>()); },
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
          "(total points) or (total points, count), flattened like xyz");
}

// Take's analog channels' units, and the channels in them.
void bind_take_analog_physics(TakeClass* cls) {
  (*cls)
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

}  // namespace

// Take: analog channels, rotations and point fields.
void bind_take_channels(TakeClass* cls) {
  bind_take_stored_channels(cls);
  bind_take_analog_physics(cls);
}

namespace {

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

}  // namespace

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

}  // namespace capz_py
