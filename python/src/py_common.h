// What the files of capz._capz share (capz_py.cpp has the module, py_c3d.cpp a take's C3D and TRC
// metadata, py_capz_file.cpp random access to a .capz): the Take's holder and class, argument
// errors, numpy views of a Take's storage, and text from files as Python str.
#pragma once

#include <pybind11/numpy.h>
#include <pybind11/pybind11.h>

#include <cstddef>
#include <limits>
#include <memory>
#include <string>
#include <vector>

#include "capz/error.h"
#include "capz/take.h"

namespace capz_py {

namespace py = pybind11;

using TakePtr = std::shared_ptr<capz::Take>;

[[noreturn]] inline void invalid(const std::string& what) {
  capz::fail(capz::ErrorCode::kInvalidParameter, "", what);
}

// A Take for Python: its arrays checked against its counts (the views rely on them), validity
// as 0 or 1 (numpy's bool), gaps set to NaN (their values are unspecified by contract).
inline TakePtr adopt(capz::Take&& t) {
  auto p = std::make_shared<capz::Take>(std::move(t));
  const size_t n = p->total_points();
  const std::string fault = p->shape_fault();
  if (!fault.empty()) capz::fail(capz::ErrorCode::kInternal, p->source, "take arrays: " + fault);
  const double nan = std::numeric_limits<double>::quiet_NaN();
  for (size_t i = 0; i < n; ++i) {
    p->valid[i] = p->valid[i] ? 1 : 0;
    if (!p->valid[i]) p->xyz[3 * i] = p->xyz[3 * i + 1] = p->xyz[3 * i + 2] = nan;
  }
  return p;
}

// A Take made of a caller's arrays (from_arrays): its point field names checked (point_field_fault:
// a field named x, or "a b", would write files that do not read back), then adopted.
inline TakePtr adopt_arrays(capz::Take&& t) {
  const std::string fault = capz::point_field_fault(t);
  if (!fault.empty()) capz::fail(capz::ErrorCode::kInvalidParameter, t.source, fault);
  return adopt(std::move(t));
}

// A numpy array over `data` (C order unless `strides` are given) that keeps `owner` alive.
inline py::array view(py::handle owner, const py::dtype& dt, const std::vector<py::ssize_t>& shape,
                      const void* data, std::vector<py::ssize_t> strides = {}) {
  if (strides.empty()) {
    strides.assign(shape.size(), dt.itemsize());
    for (size_t i = shape.size(); i-- > 1;) strides[i - 1] = strides[i] * shape[i];
  }
  return py::array(dt, shape, strides, data, owner);
}

inline py::ssize_t ss(size_t v) {
  return static_cast<py::ssize_t>(v);
}

// Text from a C3D file as a Python str: UTF-8 when it is valid UTF-8, else Latin-1 (older
// files), so that no label or parameter fails to read.
inline py::str text(const std::string& s) {
  PyObject* o = PyUnicode_DecodeUTF8(s.data(), ss(s.size()), nullptr);
  if (!o) {
    PyErr_Clear();
    o = PyUnicode_DecodeLatin1(s.data(), ss(s.size()), nullptr);
  }
  if (!o) throw py::error_already_set();
  return py::reinterpret_steal<py::str>(o);
}

// Take.events, and the "events" of capz.open(...).info: one dict an event (py_c3d.cpp).
py::list events_list(const std::vector<capz::C3DEvent>& events);

// Whether a take's text reads as Latin-1: some label, description, group or parameter name or
// char parameter of it is not valid UTF-8, so text() gave it as Latin-1 (py_c3d.cpp).
bool latin1_text(const capz::Take& t);

// A Python str as a file's bytes: Latin-1 when `latin1` (the take's text is) and every character
// has a Latin-1 byte, so that a label read and set again keeps its bytes; else UTF-8.
std::string file_text(const py::handle& s, bool latin1);

// A sequence of str as file_text each; `what` names it in the error for anything else.
inline std::vector<std::string> file_texts(const py::sequence& v, bool latin1, const char* what) {
  if (py::isinstance<py::str>(v)) invalid(std::string(what) + ": a list of str, not a str");
  std::vector<std::string> out;
  for (const py::handle& e : v) {
    if (!py::isinstance<py::str>(e)) invalid(std::string(what) + ": str expected");
    out.push_back(file_text(e, latin1));
  }
  return out;
}

inline py::list texts(const std::vector<std::string>& v) {
  py::list out;
  for (const std::string& x : v) out.append(text(x));
  return out;
}

// A note of the library's (the default bound's, dropped_coordinates_note's) as a Python
// UserWarning, as the CLI prints it.
inline void warn_note(const std::string& note) {
  if (!note.empty() && PyErr_WarnEx(PyExc_UserWarning, ("capz: " + note).c_str(), 1) != 0)
    throw py::error_already_set();
}

using TakeClass = py::class_<capz::Take, TakePtr>;

// numpy's name of a PCD field type: 'F' 4 -> "<f4", 'U' 2 -> "<u2", 'I' 8 -> "<i8"; throws
// for a type numpy has no dtype of (py_take.cpp).
std::string attribute_dtype(char type, int size);

// Take: positions, gaps and what names them; analog channels, rotations and point fields; counts,
// copies, pickling and repr (py_take.cpp).
void bind_take_positions(TakeClass* cls);
void bind_take_channels(TakeClass* cls);
void bind_take_rest(TakeClass* cls);
// Take: the C3D parameter section, sample words and header events (py_c3d.cpp).
void bind_take_c3d(TakeClass* cls);
// Take: a TRC file's Time and Frame# columns and its header's rates (py_c3d.cpp).
void bind_take_trc(TakeClass* cls);
// capz.open's file: random access to a .capz (py_capz_file.cpp).
void bind_capz_file(py::module_& m);

}  // namespace capz_py
