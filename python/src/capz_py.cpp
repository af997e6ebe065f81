// capz._capz: the library's Take and calls for Python (python/capz/__init__.py wraps this module
// and checks arguments; docs/PYTHON.md documents the package). Here the module's functions and
// its definition; the Take class's bindings are py_take.cpp's and py_c3d.cpp's.
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
// The progress hook of a Python compress, called after each window from the thread that writes
// it: with the GIL, the caller's progress(done, total) when it gave one (a borrowed reference:
// the call's argument outlives the coding, and a handle copies without the GIL), then the
// handlers of pending signals (Ctrl-C: KeyboardInterrupt). A Python exception from either stops
// the coding, which leaves nothing written, and is raised to the caller.
std::function<void(size_t, size_t)> python_progress(const py::object& progress) {
  PyObject* call = progress.is_none() ? nullptr : progress.ptr();
  return [call](size_t done, size_t total) {
    py::gil_scoped_acquire gil;
    if (call) py::handle{call}(done, total);
    if (PyErr_CheckSignals() != 0) throw py::error_already_set();
  };
}

// A compress's notes as UserWarnings, as the CLI's: the default bound's (note), the coordinates
// dropped, and each analog_max_error key that named no channel (those stay lossless).
void warn_notes(const std::string& note, const capz::CompressStats& st) {
  warn_note(note);
  warn_note(capz::dropped_coordinates_note(st));
  for (const std::string& k : st.analog_unmatched)
    warn_note("analog_max_error '" + k +
              "' names no analog channel's label or unit; those stay lossless");
}

py::tuple compress_take(const capz::Take& take, bool lossless, std::optional<double> kg_error,
                        std::optional<std::string> max_error, const std::string& units,
                        const std::string& codec, int clusters, size_t window, bool check,
                        const std::map<std::string, std::string>& codec_options, int threads,
                        const std::map<std::string, double>& attr_error, bool drop_fields,
                        const std::map<std::string, double>& analog_max_error, bool any_point_order,
                        const py::object& progress) {
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
    opts.progress = python_progress(progress);
    std::unique_ptr<capz::FrameSource> src = capz::take_frames(t);
    note =
        capz::set_compress_target(*src, target_of(lossless, kg_error, std::move(max_error)), &opts);
    if (t.units_assumed) {  // as the CLI: the archive stores no assumed units
      with_units->units.clear();
      with_units->units_assumed = false;
    }
    bytes = capz::compress(t, opts, &st);
  }
  warn_notes(note, st);
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

// The CLI's --trc-delimiter: "tab", "comma", or "" for the take's own (WriteOptions 0).
char trc_delimiter_char(const std::string& name) {
  if (name == "tab") return '\t';
  if (name == "comma") return ',';
  if (!name.empty()) invalid("trc_delimiter: tab or comma, not '" + name + "'");
  return 0;
}

// Building takes from arrays, and the memory limits' constants.
void bind_take_builders(py::module_& m) {
  m.def("take_from_arrays", &take_from_arrays);
  m.def("take_from_frames", &take_from_frames);

  m.attr("DEFAULT_MEMORY_LIMIT") = capz::kDefaultMemoryLimit;
  m.attr("AUTO_MEMORY_LIMIT") = capz::kAutoMemoryLimit;
}

// Reading and writing takes by path.
void bind_reading_writing(py::module_& m) {
  m.def("read", [](const std::string& path, uint64_t memory_limit, const py::object& progress,
                   const std::string& bin_fields) {
    capz::Take t;
    {
      py::gil_scoped_release nogil;
      if (file_is_capz(path)) {
        const std::vector<uint8_t> bytes = capz::read_file(path);
        capz::DecompressOptions o;
        o.memory_limit = memory_limit;
        o.progress = python_progress(progress);
        t = capz::decompress(bytes.data(), bytes.size(), path, o);
      } else {  // read_take's take, block by block: progress and Ctrl-C between blocks
        capz::ReadOptions read;
        read.bin_fields = bin_fields;
        std::unique_ptr<capz::FrameSource> src = capz::open_frames(path, read);
        t = capz::read_all_frames(*src, python_progress(progress));
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
}

// Coding: compress, decompress, compress_file, and what a format would drop.
void bind_coding(py::module_& m) {
  m.def("compress", &compress_take);

  m.def("dropped_by", [](const capz::Take& take, const std::string& path) {
    return capz::dropped_by(take, capz::format_for_output(path));
  });

  m.def("decompress", [](const py::buffer& data, const std::string& name, uint64_t memory_limit,
                         const py::object& progress) {
    const py::buffer_info b = data.request();
    if (b.ndim != 1 || b.itemsize != 1) invalid("decompress wants bytes (a 1-D buffer of bytes)");
    capz::Take t;
    {
      py::gil_scoped_release nogil;
      capz::DecompressOptions o;
      o.memory_limit = memory_limit;
      o.progress = python_progress(progress);
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
           bool overwrite, const py::object& progress, const std::string& bin_fields) {
          capz::CompressStats st;
          std::string note;
          {
            py::gil_scoped_release nogil;
            capz::CompressOptions opts =
                coding_options(codec, clusters, window, check, codec_options, threads, attr_error,
                               drop_fields, analog_max_error, any_point_order);
            opts.progress = python_progress(progress);
            capz::ReadOptions read;
            read.bin_fields = bin_fields;
            note = capz::compress_file(in, out, target_of(lossless, kg_error, std::move(max_error)),
                                       opts, units, overwrite, &st, read);
          }
          warn_notes(note, st);
          return compress_stats(st);
        });
}

// Comparing two takes, and the unit helpers.
void bind_comparing(py::module_& m) {
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

// The module's functions: reading, writing, coding, comparing.
void bind_functions(py::module_& m) {
  bind_take_builders(m);
  bind_reading_writing(m);
  bind_coding(m);
  bind_comparing(m);
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
